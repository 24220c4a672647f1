"""The recorded friction forces (Run.friction_forces, World.friction_forces) against closed forms.

Each record's contacts give the force on the moving body, sum over its contacts of
+-(f_n n + f_t t) (t = n turned by +90 degrees, + where it is body 1): at rest on an incline it
is the weight's opposite, f_t summing to m g sin theta; sliding, |f_t| = mu f_n against the slip
and the sum m a - m g with a = g (sin - mu cos); a disc rolling down needs f_t = m g sin / 3.
"""

from __future__ import annotations

import math

import numpy as np

import runtime
from runtime.io.scene_file import scene_from_dict

G = 9.81
BLOCK = {"type": "rounded_rect", "width": 0.2, "height": 0.1, "corner_radius": 0.0}


def slope(theta: float, mu: float, shape: dict, height: float):
    c, s = math.cos(theta), math.sin(theta)
    return scene_from_dict({"body": [
        {"name": "slope", "fixed": True, "friction": mu,
         "shape": {"type": "wall", "start": [-5 * c, -5 * s], "end": [5 * c, 5 * s]}},
        {"name": "body", "shape": shape, "mass": 2.0, "friction": mu, "angle": theta,
         "position": [-s * height, c * height]},
    ]})  # fmt: skip


def contact_force_on_body(run, k: int, body: int = 1) -> np.ndarray:
    """The total contact force (N, world) on ``body`` at record k, from the recorded forces."""
    contacts = run.contacts[k]
    n = contacts.normal
    t = np.column_stack([-n[:, 1], n[:, 0]])
    sign = np.where(contacts.body1 == body, 1.0, -1.0)
    f = run.contact_forces[k][:, None] * n + run.friction_forces[k][:, None] * t
    return (sign[:, None] * f).sum(axis=0)


def test_a_block_held_on_an_incline_records_friction_m_g_sin_theta():
    theta, mu = 0.35, 0.6  # tan 0.365 < mu: it sticks
    run = runtime.simulate(slope(theta, mu, BLOCK, 0.05), duration=0.2, dt=1e-3)
    weight = 2.0 * G
    for k in range(len(run.t)):
        assert len(run.contacts[k]) == 2 and len(run.friction_forces[k]) == 2
        np.testing.assert_allclose(
            contact_force_on_body(run, k), [0.0, weight], atol=1e-12 * weight
        )
        assert abs(abs(run.friction_forces[k].sum()) / (weight * math.sin(theta)) - 1) < 1e-12
        assert np.all(np.abs(run.friction_forces[k]) <= mu * run.contact_forces[k] * (1 + 1e-12))
    world = runtime.World(slope(theta, mu, BLOCK, 0.05))
    world.step(1e-3)
    assert abs(abs(world.friction_forces.sum()) / (weight * math.sin(theta)) - 1) < 1e-12


def test_a_block_sliding_down_records_mu_times_its_normal_force_against_the_slip():
    theta, mu = 0.5, 0.3
    run = runtime.simulate(slope(theta, mu, BLOCK, 0.05), duration=0.2, dt=1e-3)
    downhill = -np.array([math.cos(theta), math.sin(theta)])
    a = G * (math.sin(theta) - mu * math.cos(theta))
    expected = 2.0 * (a * downhill + np.array([0.0, G]))  # m a - m g
    for k in range(1, len(run.t)):  # moving from the first step on
        np.testing.assert_allclose(contact_force_on_body(run, k), expected, atol=1e-12 * 2 * G)
        friction, normal = run.friction_forces[k], run.contact_forces[k]
        np.testing.assert_allclose(np.abs(friction), mu * normal, rtol=1e-12)
        slip = (
            run.velocities[k, 1, :2]
            @ np.column_stack([-run.contacts[k].normal[:, 1], run.contacts[k].normal[:, 0]]).T
        )
        assert np.all(
            np.sign(friction) == -np.sign(slip * np.where(run.contacts[k].body1 == 1, 1, -1))
        )


def test_a_disc_rolling_down_an_incline_records_a_third_of_m_g_sin_theta():
    theta, mu, r = 0.4, 0.5, 0.1  # mu >= tan / 3: it rolls
    run = runtime.simulate(slope(theta, mu, {"type": "disc", "radius": r}, r), 0.2, 1e-3)
    for k in range(len(run.t)):
        (friction,) = run.friction_forces[k]
        assert abs(abs(friction) / (2.0 * G * math.sin(theta) / 3) - 1) < 1e-12


def test_a_run_without_friction_records_zero_friction_forces():
    run = runtime.simulate(slope(0.3, 0.0, BLOCK, 0.05), duration=0.01, dt=1e-3)
    assert [len(f) for f in run.friction_forces] == [len(c) for c in run.contacts]
    assert all(np.all(f == 0.0) for f in run.friction_forces)
