"""End to end through runtime.simulate: a moving cup (a bowl with a thickness) and a free
hollow frame (a compound of four bars) carrying other bodies.

References: a pair at rest relative to each other moving as one (the contact forces are the
weights they carry, the motion uniform); conservation of linear momentum where no horizontal
force acts from outside, of angular momentum and of energy in elastic impacts without gravity.

The runs keep the default guards: the guard against bodies passing through each other
(runtime.step.guards.passed_through) treats a body whose centre of mass lies outside its
material (a cup's, a frame's: in the hollow, where the bodies it carries are) as hollow.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import runtime

G = 9.81
R, T, R_DISC = 0.5, 0.05, 0.1


def cup_scene(angle: float, velocity: float) -> runtime.Scene:
    """A half-turn cup (inner radius R, thickness T) standing on a frictionless floor, its arc
    centre at height R + T, and a disc inside it ``angle`` from the bottom, both moving
    sideways at ``velocity``."""
    centre = np.array([0.0, R + T])
    disc = centre + (R - R_DISC) * np.array([math.sin(angle), -math.cos(angle)])
    cup = {"type": "bowl", "radius": R, "start_angle": -math.pi, "end_angle": 0.0, "thickness": T}
    return runtime.scene_from_dict(
        {"body": [
            {"name": "floor", "fixed": True, "shape": {"type": "wall", "start": [-10, 0], "end": [10, 0]}},
            {"name": "cup", "shape": cup, "density": 100.0, "position": centre.tolist(), "velocity": [velocity, 0.0]},
            {"name": "disc", "shape": {"type": "disc", "radius": R_DISC}, "mass": 0.7,
             "position": disc.tolist(), "velocity": [velocity, 0.0]},
        ]},
        source="cup",
    )  # fmt: skip


def test_disc_at_the_bottom_of_a_cup_sliding_sideways_moves_with_it():
    """The pair slides at 0.3 m/s as one: every record has the cup on the floor carrying
    (m_cup + m_disc) g and the disc in the cup (body 2: its concave arc) pressing m_disc g, to
    1e-9 relative, and both bodies at x0 + v t to 1e-12 m."""
    v = 0.3
    scene = cup_scene(0.0, v)
    run = runtime.simulate(scene, duration=0.2, dt=1e-3)
    m_cup, m_disc = scene.body("cup").mass, scene.body("disc").mass
    want = {(1, 0): (m_cup + m_disc) * G, (2, 1): m_disc * G}
    for contacts, forces in zip(run.contacts, run.contact_forces, strict=True):
        got = {
            (int(i), int(j)): f
            for i, j, f in zip(contacts.body1, contacts.body2, forces, strict=True)
        }
        assert got.keys() == want.keys()
        for pair, force in want.items():
            assert got[pair] == pytest.approx(force, rel=1e-9)
    x0 = run.poses[0, 1:, 0]
    np.testing.assert_allclose(run.poses[:, 1:, 0], x0 + v * run.t[:, None], rtol=0, atol=1e-12)
    still = run.poses[:, 1:, 1:] - run.poses[0, 1:, 1:]  # heights and angles
    assert np.abs(still).max() <= 1e-12


def test_disc_rolling_in_a_cup_on_a_frictionless_floor_keeps_the_horizontal_momentum():
    """A disc let go 0.6 rad up the side of a moving cup: it slides down and the cup rocks and
    recoils, but the floor and gravity push only vertically, so the total horizontal
    momentum stays (to 1e-14 relative); no impact occurs (the disc stays on the arc, the cup
    on the floor) and energy is kept to the integrator's error (1e-11 relative)."""
    scene = cup_scene(0.6, 0.2)
    run = runtime.simulate(scene, duration=0.2, dt=1e-3)
    px = run.momentum[:, 0]
    assert np.abs(px - px[0]).max() <= 1e-14 * abs(px[0])
    assert np.abs(run.energy - run.energy[0]).max() <= 1e-11 * run.energy[0]
    assert len(run.impact_times) == 0 and np.abs(run.impact_losses).max() <= 1e-16 * run.energy[0]
    assert run.min_gap.min() > -1e-12
    assert all(len(c) == 2 for c in run.contacts)
    assert run.poses[-1, 1, 2] < -1e-3  # the cup did rock (the disc pushed it)
    assert run.poses[-1, 2, 0] - run.poses[0, 2, 0] < 0.2 * 0.2 - 1e-3  # and the disc slid back


def _angular_momentum(scene: runtime.Scene, poses: np.ndarray, velocities: np.ndarray) -> float:
    total = 0.0
    for k, body in enumerate(scene.bodies):
        (x, y, _), (vx, vy, w) = poses[k], velocities[k]
        total += body.mass * (x * vy - y * vx) + body.inertia * w
    return total


def test_two_balls_in_a_free_hollow_frame_conserve_momentum_and_energy():
    """Two balls bouncing inside a free 1 x 0.6 frame (bars 0.05 thick), no gravity,
    restitution 1 (tests/runtime/data/balls_in_frame.toml): a dozen impacts on the frame's inner sides and between the balls keep the
    linear momentum, the angular momentum and the energy to 1e-12 (relative), and the balls
    stay inside the opening."""
    scene = runtime.load_scene(Path(__file__).resolve().parent / "data" / "balls_in_frame.toml")
    run = runtime.simulate(scene)  # 1.5 s in steps of 1 ms
    assert len(run.impact_times) >= 8
    p0 = run.momentum[0]
    assert np.abs(run.momentum - p0).max() <= 1e-12 * np.hypot(*p0)
    assert np.abs(run.energy - run.energy[0]).max() <= 1e-12 * run.energy[0]
    angular = [
        _angular_momentum(scene, q, v) for q, v in zip(run.poses, run.velocities, strict=True)
    ]
    scale = sum(b.mass for b in scene.bodies) * 0.5 * 1.0  # kg x the frame's size x speed
    assert np.abs(np.array(angular) - angular[0]).max() <= 1e-12 * scale
    for q in run.poses:  # each ball's centre in the frame's coordinates
        x, y, th = q[0]
        c, s = math.cos(th), math.sin(th)
        for k, r in ((1, 0.1), (2, 0.08)):
            dx, dy = q[k, 0] - x, q[k, 1] - y
            u, w = c * dx + s * dy, -s * dx + c * dy
            assert abs(u) <= 0.5 - r + 1e-9 and abs(w) <= 0.3 - r + 1e-9
