"""Lift-offs located inside a step (runtime.step.lift_events): a disc sliding off a cylinder.

Oracle, written apart from the engine: the inverted pendulum phi'' = (g / L) sin phi (L = R + r,
phi from the top) by scipy's DOP853 at rtol 1e-12 until the normal force m (g cos phi - L phi'^2)
vanishes, which also checks the closed form cos phi = (2/3) cos phi0 + v0^2 / (3 g L); then a
parabola. Before lift-offs were located, RK4 at dt = 0.05 s stepped across the instant the force
vanishes (a kink in the right-hand side) and the disc's flight was 1.8e-3 m off (9.8e-5 m at
dt = 0.02 s).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import runtime

SCENES = Path(__file__).resolve().parents[2] / "scenes"
L, V0 = 0.6, 0.1  # the scene's R + r and the disc's initial speed (m, m/s)


def _oracle(g: float):
    """(leaving time, leaving angle, t -> centre of the disc)."""

    def force(_t, y):
        return g * math.cos(y[0]) - L * y[1] ** 2

    force.terminal = True
    sol = solve_ivp(lambda _t, y: [y[1], g / L * math.sin(y[0])], (0.0, 3.0), [0.0, V0 / L],
                    method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True, events=force)  # fmt: skip
    t_leave = float(sol.t_events[0][0])
    phi, dphi = sol.y_events[0][0]
    assert abs(math.cos(phi) - (2.0 / 3.0 + V0**2 / (3.0 * g * L))) < 1e-10

    def centre(t: float) -> np.ndarray:
        if t <= t_leave:
            a = sol.sol(t)[0]
            return L * np.array([math.sin(a), math.cos(a)])
        tau = t - t_leave
        p = L * np.array([math.sin(phi), math.cos(phi)])
        v = L * dphi * np.array([math.cos(phi), -math.sin(phi)])
        return p + v * tau + 0.5 * np.array([0.0, -g]) * tau**2

    return t_leave, phi, centre


@pytest.mark.parametrize(
    ("dt", "time_tol", "angle_tol", "flight_tol"),
    # measured: 1.5e-5 s, 1.6e-5 rad, 9.9e-5 m; 4.5e-7 s, 5.6e-7 rad, 2.9e-6 m
    [(0.05, 3e-5, 3e-5, 2e-4), (0.02, 1e-6, 1e-6, 1e-5)],
)
def test_the_disc_leaves_the_cylinder_at_a_located_lift_off(dt, time_tol, angle_tol, flight_tol):
    scene = runtime.load_scene(SCENES / "disc_over_cylinder.toml")
    disc = scene.index("disc")
    t_leave, phi_leave, centre = _oracle(-scene.gravity[1])
    run = runtime.simulate(scene, 1.5, dt, "rk4")
    assert len(run.lift_times) == 1 and len(run.impact_times) == 0
    lift = float(run.lift_times[0])
    assert abs(lift - t_leave) < time_tol
    off = max(np.hypot(*(run.poses[k, disc, :2] - centre(t))) for k, t in enumerate(run.t))
    assert off < flight_tol
    # the force falls to 0 where the disc leaves: the record before carried it, the one after not
    k = int(np.searchsorted(run.t, lift))
    assert run.contact_forces[k - 1].sum() > 0.0 and run.contact_forces[k].sum() == 0.0
    # the angle at the lift, the first record after it taken back along its flight
    back = run.t[k] - lift
    p = run.poses[k, disc, :2] - back * run.velocities[k, disc, :2]
    p[1] += 0.5 * scene.gravity[1] * back**2
    assert abs(math.atan2(p[0], p[1]) - phi_leave) < angle_tol
    # World.step one step at a time (its quiet check, not simulate's compiled stretches) locates
    # the same lift-off and ends in the same state, to the bit
    world = runtime.World(scene, "rk4")
    steps = round(1.5 / dt)
    for k in range(1, steps + 1):
        world.step((1.5 if k == steps else k * dt) - world.t)  # simulate's grid
    assert world.lift_times == [lift]
    assert np.array_equal(world.poses, run.poses[-1])


def test_contacts_at_rest_do_not_lift():
    """A box on its two corners and a disc in a bowl press all along: no lift-off, and the
    small steps of a disc leaving a cylinder (d'' dt below the resting speed) locate none."""
    for name, dt in (("box_on_floor.toml", 0.01), ("disc_in_bowl.toml", 0.05)):
        run = runtime.simulate(runtime.load_scene(SCENES / name), 1.0, dt, "rk4")
        assert len(run.lift_times) == 0, name
    run = runtime.simulate(runtime.load_scene(SCENES / "disc_over_cylinder.toml"), 1.5, 1e-3)
    assert len(run.lift_times) == 0 and sum(len(c) == 0 for c in run.contacts) > 500


def test_the_earliest_of_several_lift_offs_is_located():
    """An island's first lift-off is the earliest of its contacts'. A contact still pressing at
    the earliest lift-off found so far lifts later and is not located; one that has lifted by
    then is. Three contacts whose force F (or, once it is 0, -d'' / A_kk) falls to 0 at h / 3
    (as (1 - 3 t / h)^3: found first), 0.2 h and 0.9 h (linearly): 0.2 h, and nothing inside
    the step near 0.9 h is asked."""
    from types import SimpleNamespace

    from runtime import settings
    from runtime.step.lift_events import LiftEvents

    h = 1e-3
    lifts = np.array([h / 3, 0.2 * h, 0.9 * h])
    asked = []

    def state(t: float):
        asked.append(t)
        F = np.array([(1 - 3 * t / h) ** 3, 1 - t / lifts[1], 1 - t / lifts[2]])
        diagonal = np.full(3, 2.0)
        return np.maximum(F, 0.0), np.maximum(-F, 0.0) * diagonal, diagonal

    events = LiftEvents(SimpleNamespace(resting_speed=1e-3))
    t = events._earliest(state, np.ones(3, bool), h)
    assert t is not None and lifts[1] <= t <= lifts[1] + settings.LIFT_TIME * h
    assert not any(abs(x - lifts[2]) < 0.1 * h for x in asked if 0.0 < x < h)
