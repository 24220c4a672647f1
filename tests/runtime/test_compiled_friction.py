"""The compiled path with friction (runtime.step.compiled_friction) against the general path and
against closed forms.

The general path (runtime.solve.friction, friction_impulses, runtime.step.friction_hold,
resting, friction_events; settings.COMPILED = False) is written apart from the compiled one:
the same scenes must run the same way on both -- impacts with friction and restitution,
tipping, stick -> slip and slip -> stick located, long RK4 steps -- and the compiled path must
really be the one taken. Its pieces are also checked alone: the impulses of a spinning disc
landing against Routh's construction, and the hold of a box's sticking corners against the
velocity that stops them.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import runtime
from runtime import settings
from runtime.io.scene_file import load_scene
from runtime.solve import friction
from runtime.step import compiled_friction, friction_events, stepper
from tests.runtime.test_friction import BLOCK, _pile, incline, rolling_in_a_bowl

ROOT = Path(__file__).resolve().parents[2]


def _spin(v0=2.0, omega0=10.0, mu=0.3):
    """A disc with backspin on a floor: slides, then rolls from s0 / (3 mu g) on."""
    return incline(0.0, mu, {"type": "disc", "radius": 0.1}, 0.1, speed=v0, spin=omega0)


SCENES = {
    # impacts with friction and restitution, tipping, sliding and sticking boxes, a disc
    "boxes and a disc thrown onto a floor": (lambda: _pile(0.6), 1.0, 1e-3),
    "a disc with backspin (slip -> stick)": (_spin, 0.5, 1e-3),
    "a block on a slope, tan theta = mu (sticks)": (
        lambda: incline(0.4, math.tan(0.4), BLOCK, 0.05), 0.5, 1e-3),
    "a block sliding up a slope (slip -> stick -> slip)": (
        lambda: incline(0.3, 0.25, BLOCK, 0.05, speed=1.0), 0.8, 1e-3),
    "the shipped disc rolling in a bowl, RK4 dt = 0.05 s": (
        lambda: load_scene(ROOT / "scenes" / "disc_rolling_in_bowl.toml"), 3.0, 0.05),
}  # fmt: skip


class _Count:
    """Frames the compiled path built, trials it called quiet, and islands the general path
    asked to hold (runtime.solve.friction_lcp.solve_held, which only it can call)."""

    def __init__(self, monkeypatch):
        self.frames = self.declined = self.quiet = self.searched = self.held = 0
        frame, quiet = compiled_friction.frame, stepper.Stepper._friction_quiet
        search = friction_events.FrictionEvents._compiled_args
        hold = friction.solve_held

        def counted_hold(*args):
            self.held += 1
            return hold(*args)

        monkeypatch.setattr(friction, "solve_held", counted_hold)

        def counted_search(*args):
            self.searched += 1
            return search(*args)

        monkeypatch.setattr(friction_events.FrictionEvents, "_compiled_args", counted_search)

        def counted_frame(*args):
            done = frame(*args)
            self.frames += done is not None
            self.declined += done is None and len(args[1]) > 0
            return done

        def counted_quiet(*args):
            found = quiet(*args)
            self.quiet += found
            return found

        monkeypatch.setattr(compiled_friction, "frame", counted_frame)
        monkeypatch.setattr(stepper.Stepper, "_friction_quiet", counted_quiet)


@pytest.mark.parametrize("name", SCENES)
def test_the_compiled_path_runs_a_scene_with_friction_as_the_general_path(name, monkeypatch):
    """Poses and velocities at every step to 1e-12 (m, rad, m/s, rad/s), the same located
    impacts and transitions; and every frame with contacts was built compiled (but those where
    an island sticking everywhere starts to move: the general path asks whether it can be held,
    runtime.solve.friction_lcp._moves), with quiet trials taken without the event search, and a
    search for a transition (->) asked the compiled friction state."""
    make, duration, dt = SCENES[name]
    count = _Count(monkeypatch)
    fast = runtime.simulate(make(), duration, dt)
    held = count.held
    monkeypatch.setattr(settings, "COMPILED", False)
    general = runtime.simulate(make(), duration, dt)
    assert count.frames > 0 and count.declined <= held
    assert count.quiet > 0
    assert count.searched > 0 or "->" not in name
    assert np.allclose(fast.impact_times, general.impact_times, rtol=0.0, atol=1e-12)
    assert np.max(np.abs(fast.poses - general.poses)) < 1e-12
    assert np.max(np.abs(fast.velocities - general.velocities)) < 1e-12


def test_the_compiled_path_keeps_the_bowls_pendulum_in_long_steps():
    """The rolling disc of tests/runtime/test_friction.py at RK4 dt = 0.05 s, now compiled: the
    pendulum's angle to RK4's error there (1.33e-5 rad) and no located transition."""
    run, phi, ref, _ = rolling_in_a_bowl(0.05)
    assert len(run.impact_times) == 0
    assert np.max(np.abs(phi - ref)) < 2e-5


@pytest.mark.parametrize(
    "mu, e, s0", [(0.5, 0.5, 0.5), (0.05, 0.5, 4.0), (0.3, 0.0, -1.5), (0.2, 1.0, 5.0)]
)
def test_compiled_impulses_of_a_spinning_disc_landing_are_rouths(mu, e, s0):
    """One contact under a disc's centre (m = 1, I = m r^2 / 2), landing at u = 2 m/s with slip
    s0: normal impulse (1 + e) m u; the slip stops if m s0 / 3 <= mu (1 + e) m u, else the
    tangential impulse is mu (1 + e) m u against it (Routh). The rows by hand: the contact point
    at (0, -r), n = (0, 1), t = (-1, 0), so d' = vy and v_t = -(vx + r omega)."""
    r, m, u = 0.1, 1.0, 2.0
    Jn, Jt = np.array([[0.0, 1.0, 0.0]]), np.array([[-1.0, 0.0, -r]])
    w = np.array([1 / m, 1 / m, 1 / (0.5 * m * r * r)])
    total = np.zeros(1)
    dv = compiled_friction.frictional_impulses(
        Jn, Jt, w, np.array([mu]), np.array([-u]), np.array([s0]), np.array([e]), 1e-3, 1e-12,
        total,
    )  # fmt: skip
    normal = (1 + e) * m * u
    slip_after = (
        0.0 if abs(s0) * m / 3 <= mu * normal else s0 - math.copysign(3 * mu * normal / m, s0)
    )
    assert total[0] == pytest.approx(normal, rel=1e-12)
    assert (Jn @ dv)[0] == pytest.approx(normal / m, rel=1e-12)  # d' after: e u
    assert s0 + (Jt @ dv)[0] == pytest.approx(slip_after, abs=1e-12)


def test_the_compiled_hold_stops_a_boxs_sticking_corners_and_leaves_their_d_prime():
    """A box (body 1) on a floor (body 0, fixed) on its two bottom corners (+-a, -b), creeping
    at vx = 3e-7 m/s and turning at 1e-7 rad/s. Rows by hand: d' = vy + omega x and
    v_t = -(vx - omega y) at the corner (x, y) from the centre. The hold keeps both corners' d'
    (so vy and omega stay) and stops their common slip: dv = (-(vx + b omega), 0, 0)."""
    a, b = 0.1, 0.05
    jac = np.array([[0.0, 1.0, -a, 0, 0, 0], [0.0, 1.0, a, 0, 0, 0]])
    tangent_jac = np.array([[-1.0, 0.0, -b, 0, 0, 0], [-1.0, 0.0, -b, 0, 0, 0]])
    v = np.array([[0.0, 0.0, 0.0], [3e-7, 0.0, 1e-7]])
    v_t = tangent_jac[:, :3] @ v[1]
    inv_mass = np.array([[0.0, 0.0, 0.0], [2.0, 2.0, 300.0]])
    dv = np.zeros((2, 3))
    held = compiled_friction.hold_sticking(
        jac, tangent_jac, np.array([1, 1]), np.array([0, 0]), v_t, np.array([0.5, 0.5]),
        np.zeros(2), np.array([0, 1]), inv_mass, np.array([True, False]), dv,
    )  # fmt: skip
    assert held
    assert np.allclose(dv, [[0, 0, 0], [-(3e-7 + b * 1e-7), 0, 0]], rtol=0, atol=1e-20)
    assert np.allclose(tangent_jac[:, :3] @ (v + dv)[1], 0.0, rtol=0, atol=1e-20)
    slow = np.full(2, 0.5 * settings.STICK_SPEED * settings.STICK_LOCATE)  # nothing to hold
    assert not compiled_friction.hold_sticking(
        jac, tangent_jac, np.array([1, 1]), np.array([0, 0]), slow, np.array([0.5, 0.5]),
        np.zeros(2), np.array([0, 1]), inv_mass, np.array([True, False]), dv,
    )  # fmt: skip
