"""Numerical stability of the engine on hard cases: each test asserts a stated bound.

Radius extremes (1e-6 and 1e6 against the vertex and straight-edge results, a 1e-3 disc in a
1e3 bowl against the pendulum), large coordinates (scenes translated by 1e4 and 1e6), a fast
spin, a mass ratio of 1e6, grazing contacts, contacts crossing an arc's end point, redundant
contacts and a disc that exactly fits its bowl. The bounds come from a float64 analysis of the
terms that lose digits (docs/numerics.md, which also lists the measured values) with a safety
factor over what was measured; ``_check`` prints each measured value next to its bound
(``pytest -s`` shows them).
"""

from __future__ import annotations

import functools
import itertools
import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import runtime
from runtime.step.stepper import Stepper

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
G = 9.81
FLOOR = {"type": "wall", "start": [-5.0, 0.0], "end": [5.0, 0.0]}
TOUCH = 1e-9  # the engine locates an impact to well inside this gap (Simulator.touch)
LCP_TOL = 1e-9  # runtime.solve.lcp.DEFAULT_TOL: |d''| <= LCP_TOL * max|b| counts as zero


def ulp(x: float) -> float:
    return float(np.spacing(abs(float(x))))


def _check(name: str, measured: float, bound: float) -> None:
    measured = float(measured)
    print(f"\n[hard case] {name}: measured {measured:.3g}, bound {bound:.3g}")
    assert measured <= bound, f"{name}: {measured:.3g} > bound {bound:.3g}"


# -- scenes ----------------------------------------------------------------------------------


def fixed(name: str, shape: dict, position=(0.0, 0.0), angle: float = 0.0) -> dict:
    return {"name": name, "fixed": True, "shape": shape, "position": list(position), "angle": angle}


def moving(name: str, shape: dict, position, *, mass=None, density=None, **state) -> dict:
    body = {"name": name, "shape": shape, "position": list(position), **state}
    if mass is not None:
        body["mass"] = mass
    else:
        body["density"] = 1000.0 if density is None else density
    return body


def disc(name: str, radius: float, position, **extra) -> dict:
    return moving(name, {"type": "disc", "radius": radius}, position, **extra)


def make_scene(*bodies: dict, gravity=(0.0, -G)) -> runtime.Scene:
    return runtime.scene_from_dict({"scene": {"gravity": list(gravity)}, "body": list(bodies)})


def simulate(scene, duration: float, dt: float, **options) -> runtime.Run:
    """runtime.simulate with RK4, checking that every recorded state is finite."""
    run = runtime.simulate(scene, duration, dt, "rk4", **options)
    assert np.all(np.isfinite(np.asarray(run.poses))), "NaN or inf in the poses"
    assert np.all(np.isfinite(np.asarray(run.velocities))), "NaN or inf in the velocities"
    assert all(np.all(np.isfinite(f)) for f in run.contact_forces), "NaN or inf in the forces"
    return run


def penetration(scene, poses) -> float:
    """Deepest penetration (>= 0) among the contacts found at the given poses."""
    return max(0.0, -smallest_gap(scene, poses))


def smallest_gap(scene, poses) -> float:
    """Smallest gap of all contacts the contact finder reports at the given poses (inf if none),
    independent of the run's own bookkeeping."""
    return min((g for p in poses for g in scene.contacts(p).gap), default=math.inf)


def _pendulum(phi0: float, omega0: float, sign: float, length: float, times) -> np.ndarray:
    """(phi, phi') of phi'' = sign g/length sin phi (sign -1: hanging, +1: inverted),
    solve_ivp DOP853 at rtol 1e-12."""
    sol = solve_ivp(
        lambda _t, y: [y[1], sign * G / length * math.sin(y[0])],
        (0.0, float(times[-1])),
        [phi0, omega0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-20,
        t_eval=times,
    )
    return sol.y


# -- radius extremes ------------------------------------------------------------------------


def test_disc_on_a_radius_1e6_disc_slides_as_on_a_flat_floor():
    """A disc (r = 0.1) sliding at 1 m/s over the top of a fixed disc of radius R = 1e6, against
    the same disc on a flat wall and against the exact motion on the big circle (an inverted
    pendulum of length R + r about (0, -R)).

    Bounds: the flat-floor result differs only by the geometry, the sag x^2 / (2R) in y and
    g v t^3 / (6R) in x (4.5e-8 m and 4.4e-8 m after 0.3 s): asserted <= 2 (v t)^2 / R. The
    exact motion: 1e-12 m (float64 resolution of positions ~0.3 m is 6e-17; the reference is
    good to rtol 1e-12 in phi ~ 3e-7). The gap on the big circle, |v| - R - r with |v| ~ 1e6:
    hypot and dy = y1 - y2 each round to ~1 ulp(1e6) = 1.2e-10 m, asserted <= 4 ulp(1e6).
    """
    R, r, v, T = 1e6, 0.1, 1.0, 0.3
    body = disc("disc", r, (0.0, r), velocity=[v, 0.0])
    big = make_scene(fixed("big", {"type": "disc", "radius": R}, (0.0, -R)), body)
    flat = make_scene(fixed("floor", FLOOR), body)
    run_big = simulate(big, T, 1e-3, record_every=10)
    run_flat = simulate(flat, T, 1e-3, record_every=10)
    pb, pf = np.array(run_big.poses)[:, 1], np.array(run_flat.poses)[:, 1]
    _check("R = 1e6 floor vs flat wall (m)", np.max(np.abs(pb - pf)), 2 * (v * T) ** 2 / R)
    t = np.array(run_big.t)
    phi, omega = _pendulum(0.0, v / (R + r), +1.0, R + r, t)
    x_exact = (R + r) * np.sin(phi)
    y_exact = r - 2 * (R + r) * np.sin(phi / 2) ** 2  # = -R + (R + r) cos phi, without cancelling
    error = max(np.max(np.abs(pb[:, 0] - x_exact)), np.max(np.abs(pb[:, 1] - y_exact)))
    _check("R = 1e6 floor vs exact motion on the circle (m)", error, 1e-12)
    gaps = [g for p in run_big.poses for g in big.contacts(p).gap]
    assert len(gaps) == len(run_big.poses)  # in contact throughout
    _check("R = 1e6 floor: |gap| (m)", max(abs(g) for g in gaps), 4 * ulp(R))
    mass = big.bodies[1].mass
    forces = np.array([f[0] for f in run_big.contact_forces])
    flat_forces = np.array([f[0] for f in run_flat.contact_forces])
    np.testing.assert_allclose(flat_forces, mass * G, rtol=1e-14)
    # on the circle: m (g cos phi - v^2 / (R + r)), 1e-7 below m g
    expected = mass * (G * np.cos(phi) - omega**2 * (R + r))
    _check("R = 1e6 floor: contact force, relative", np.max(np.abs(forces / expected - 1)), 1e-12)


def test_rounded_corner_of_radius_1e_6_behaves_like_a_vertex():
    """A box 0.4 x 0.2 standing tilted by 0.3 rad on one corner falls back flat (frictionless,
    the corner slides) and lands. With a rounded corner of radius 1e-6 (circle_edge contacts) it
    must move as the sharp box (vertex_edge) to within the radius: the rounded box starts
    r (1 - sin th - cos th) = -0.25 r lower and its contact point lies up to r(sqrt 2 - 1) off
    the corner, so the poses differ by O(r). Asserted: |dx|, |dy| <= r and |dth| <= r / (1 m)
    through the landing (0.2 s)."""
    hx, hy, th, T = 0.2, 0.1, 0.3, 0.2

    def box(rc: float):
        height = (hx - rc) * math.sin(th) + (hy - rc) * math.cos(th) + rc
        shape = {"type": "rounded_rect", "width": 2 * hx, "height": 2 * hy, "corner_radius": rc}
        scene = make_scene(
            fixed("floor", FLOOR), moving("box", shape, (0.0, height), mass=1.0, angle=th)
        )
        return scene, simulate(scene, T, 1e-3)

    sharp_scene, sharp = box(0.0)
    round_scene, rounded = box(1e-6)
    assert sharp_scene.contacts().case_name(0) == "vertex_edge"
    assert round_scene.contacts().case_name(0) == "circle_edge"
    ps, pr = np.array(sharp.poses)[:, 1], np.array(rounded.poses)[:, 1]
    assert np.all(np.abs(ps[-1, 2]) < 1e-9) and np.all(np.abs(pr[-1, 2]) < 1e-9)  # landed flat
    _check("r = 1e-6 corner vs vertex: position (m)", np.max(np.abs(pr[:, :2] - ps[:, :2])), 1e-6)
    _check("r = 1e-6 corner vs vertex: angle (rad)", np.max(np.abs(pr[:, 2] - ps[:, 2])), 1e-6)
    _check("r = 1e-6 corner: penetration (m)", penetration(round_scene, rounded.poses), TOUCH)


def test_disc_of_radius_1e_3_in_a_bowl_of_radius_1e3_is_a_pendulum():
    """A disc r = 1e-3 released 0.3 rad up a bowl R = 1e3: a pendulum of length L = R - r
    (period 63 s), RK4 at dt = 10 ms for 3 s against solve_ivp (rtol 1e-12).

    Float64: positions ~1e3 carry ulp(1e3) = 1.1e-13 m, i.e. 1.1e-16 rad of phi; the reference's
    rtol 1e-12 on phi ~ 0.3 allows 3e-13 rad and dominates (the RK4 truncation error,
    (omega dt)^4 with omega dt = 1e-3, is below both). Asserted: phi within 2e-12 rad; the
    distance from the bowl's centre within 64 ulp(1e3) = 7e-12 m of L (the gap |v| - |R| + r
    rounds to ~1 ulp(1e3) per evaluation and the constraint is not re-projected); the contact
    force m (g cos phi + v^2 / L) to 1e-12 relative; energy to 1e-12 relative.
    """
    R, r, phi0, T, dt = 1e3, 1e-3, 0.3, 3.0, 1e-2
    length = R - r
    bowl = {"type": "bowl", "radius": R, "start_angle": -2.6, "end_angle": -0.5}
    scene = make_scene(
        fixed("bowl", bowl), disc("disc", r, (length * math.sin(phi0), -length * math.cos(phi0)))
    )
    run = simulate(scene, T, dt, record_every=10)
    p, v = np.array(run.poses)[:, 1], np.array(run.velocities)[:, 1]
    phi = np.arctan2(p[:, 0], -p[:, 1])
    reference, _ = _pendulum(phi0, 0.0, -1.0, length, np.array(run.t))
    _check("1e-3 disc in 1e3 bowl: phi (rad)", np.max(np.abs(phi - reference)), 2e-12)
    radial = np.max(np.abs(np.hypot(p[:, 0], p[:, 1]) - length))
    _check("1e-3 disc in 1e3 bowl: radial drift (m)", radial, 64 * ulp(R))
    mass = scene.bodies[1].mass
    forces = np.array([f[0] for f in run.contact_forces])
    expected = mass * (G * np.cos(phi) + (v[:, 0] ** 2 + v[:, 1] ** 2) / length)
    _check("1e-3 disc in 1e3 bowl: force, relative", np.max(np.abs(forces / expected - 1)), 1e-12)
    energy = np.array(run.energy)
    drift = np.max(np.abs(energy - energy[0])) / abs(energy[0])
    _check("1e-3 disc in 1e3 bowl: energy, relative", drift, 1e-12)
    assert np.all(v[:, 2] == 0.0)  # frictionless: no torque about the disc's centre


# -- large coordinates ------------------------------------------------------------------------

SHIFT_DURATION = 0.2
SHIFT_DT = 1e-3


@functools.cache
def _unshifted(name: str):
    scene = runtime.load_scene(SCENES / f"{name}.toml")
    return scene, simulate(scene, SHIFT_DURATION, SHIFT_DT)


@pytest.mark.parametrize("shift", [1e4, 1e6])
@pytest.mark.parametrize("name", ["disc_in_bowl", "plank_on_cylinder"])
def test_translated_scene_moves_the_same(name, shift):
    """The scene translated by (s, s) must give the same motion minus the shift.

    Float64: a position near s is only known to ulp(s) (1.8e-12 m at 1e4, 1.2e-10 m at 1e6), so
    every step rounds each coordinate by up to ulp(s)/2; the kernels lose nothing more (they take
    dx = x1 - x2 first, exact by Sterbenz for nearby bodies). Independent roundings add like a
    random walk: after N steps ~ sqrt(N) ulp(s) / 2. Asserted: positions, angles (per metre of
    lever) and penetration within 4 sqrt(N) ulp(s) (measured ~0.4 sqrt(N) ulp(s)); the relative
    error (over the motion's amplitude) is printed. Same contacts at every step.
    """
    scene, base = _unshifted(name)
    shifted = scene.shifted(shift, shift)
    run = simulate(shifted, SHIFT_DURATION, SHIFT_DT)
    moving_ = [i for i, b in enumerate(scene.bodies) if not b.fixed]
    p0 = np.array(base.poses)[:, moving_]
    p = np.array(run.poses)[:, moving_]
    p[..., :2] -= shift
    steps = len(run.t) - 1
    bound = 4 * math.sqrt(steps) * ulp(shift)
    position = np.max(np.abs(p[..., :2] - p0[..., :2]))
    amplitude = np.max(np.abs(p0[..., :2] - p0[0, :, :2]))
    _check(f"{name} shifted by {shift:g}: position (m)", position, bound)
    print(f"[hard case] {name} shifted by {shift:g}: relative error {position / amplitude:.2g}")
    _check(
        f"{name} shifted by {shift:g}: angle (rad)", np.max(np.abs(p[..., 2] - p0[..., 2])), bound
    )
    assert [len(c) for c in run.contacts] == [len(c) for c in base.contacts]
    depth = penetration(shifted, run.poses[::10])
    _check(f"{name} shifted by {shift:g}: penetration (m)", depth, bound)


# -- fast spin, mass ratio -------------------------------------------------------------------


def test_fast_spinning_rounded_box_lands_on_a_floor():
    """A rounded box 0.2 x 0.1 (corner radius 0.02) spinning at 1e3 rad/s, released 1 mm above
    the reach of its corners, falls and strikes the floor (corner speed ~110 m/s).

    dt = 2e-5 s (0.02 rad per step; in free flight RK4 integrates the rotation exactly). The
    contact's d'' carries w^2 |c| ~ 1e5 m/s^2 against g ~ 10: the kernels' centripetal terms
    must not swamp the result. Asserted: no NaN or failure; at least one impact; the energy
    never rises by more than 4 ulp(E0) in a step (inelastic impacts, exact free flight); the
    horizontal velocity stays below 1e-12 m/s (floor impulses are vertical); no penetration
    deeper than the engine's touch distance 1e-9 m (without locating the impact a corner would
    go v_n dt ~ 2e-3 m deep); the spin stays within [0.9, 1] of 1e3 rad/s.
    """
    width, height, rc, w0 = 0.2, 0.1, 0.02, 1e3
    reach = math.hypot(width / 2 - rc, height / 2 - rc) + rc
    shape = {"type": "rounded_rect", "width": width, "height": height, "corner_radius": rc}
    box = moving("box", shape, (0.0, reach + 1e-3), mass=1.0, angular_velocity=w0)
    scene = make_scene(fixed("floor", FLOOR), box)
    run = simulate(scene, 0.03, 2e-5)
    energy = np.array(run.energy)
    vel = np.array(run.velocities)[:, 1]
    assert len(run.impact_times) >= 1
    assert energy[-1] < energy[0] - 1.0  # the inelastic strike took energy
    _check(
        "spin 1e3: largest energy rise in a step (J)", np.max(np.diff(energy)), 4 * ulp(energy[0])
    )
    _check("spin 1e3: |vx| (m/s)", np.max(np.abs(vel[:, 0])), 1e-12)
    _check("spin 1e3: penetration (m)", penetration(scene, run.poses), TOUCH)
    assert 0.9 * w0 <= np.min(vel[:, 2]) and np.max(vel[:, 2]) <= w0


def test_heavy_box_resting_on_a_light_disc_on_a_floor():
    """Mass ratio 1e6: a box of 1e3 kg balanced on a disc of 1e-3 kg on a floor.

    A = J M^-1 J^T = [[1/m, -1/m], [-1/m, 1/m + 1/M]] has condition number ~4 M/m = 4e6, so the
    forces are good to ~cond * eps = 1e-9 relative: asserted. The solver accepts |d''| up to
    LCP_TOL max|b| = 1e-8 m/s^2, so the bodies may drift by at most LCP_TOL g t^2 / 2: asserted
    for the vertical drift and the penetration. The scene is symmetric: nothing moves sideways.
    """
    r, big, small, T = 0.1, 1e3, 1e-3, 0.2
    box = {"type": "polygon", "points": [[-0.2, -0.05], [0.2, -0.05], [0.2, 0.05], [-0.2, 0.05]]}
    scene = make_scene(
        fixed("floor", FLOOR),
        disc("disc", r, (0.0, r), mass=small),
        moving("box", box, (0.0, 2 * r + 0.05), mass=big),
    )
    run = simulate(scene, T, 1e-3, record_every=10)
    forces = np.array(run.contact_forces)  # [floor/disc, disc/box]
    exact = np.array([(big + small) * G, big * G])
    _check("mass ratio 1e6: forces, relative", np.max(np.abs(forces / exact - 1)), 1e-9)
    p = np.array(run.poses)
    drift_bound = LCP_TOL * G * T**2 / 2
    _check(
        "mass ratio 1e6: vertical drift (m)", np.max(np.abs(p[:, 1:, 1] - p[0, 1:, 1])), drift_bound
    )
    _check("mass ratio 1e6: penetration (m)", penetration(scene, run.poses), drift_bound)
    assert np.all(p[:, 1:, 0] == 0.0) and np.all(p[:, 1:, 2] == 0.0)


# -- grazing contacts ------------------------------------------------------------------------


@pytest.mark.parametrize("normal_velocity", [-1e-12, 1e-12])
def test_disc_on_a_floor_with_a_normal_velocity_of_1e_12_creeps(normal_velocity):
    """A disc sliding on a floor with vy = +-1e-12 m/s: far below the resting speed, so no
    impulse; the contact force holds d'' = 0 and vy stays what it was (the engine does not
    project velocities). Asserted: vy unchanged to 1e-20 m/s, y = y0 + vy t to 1e-15 m."""
    T = 0.2
    scene = make_scene(
        fixed("floor", FLOOR), disc("disc", 0.1, (0.0, 0.1), velocity=[1.0, normal_velocity])
    )
    run = simulate(scene, T, 1e-3, record_every=10)
    p, v = np.array(run.poses)[:, 1], np.array(run.velocities)[:, 1]
    _check("grazing floor: vy change (m/s)", np.max(np.abs(v[:, 1] - normal_velocity)), 1e-20)
    creep = np.abs(p[:, 1] - 0.1 - normal_velocity * np.array(run.t))
    _check("grazing floor: y - (y0 + vy t) (m)", np.max(creep), 1e-15)
    assert all(len(c) == 1 for c in run.contacts)


@pytest.mark.parametrize("normal_velocity", [-1e-12, 0.0, 1e-12])
def test_disc_leaving_the_top_of_a_cylinder_tangentially_is_ballistic(normal_velocity):
    """A disc on top of a fixed cylinder (R + r = 0.6) moving at 1.2 sqrt(g (R + r)): gravity
    cannot hold it on the circle, so it leaves at once on the parabola. The contact starts with
    d = 0, d' = +-1e-12 (grazing) and d'' > 0 without force. Asserted: the exact parabola to
    1e-14 m (positions ~0.6 m: 1e-16 resolution, 200 steps), and no contact force."""
    R, r = 0.5, 0.1
    speed = 1.2 * math.sqrt(G * (R + r))
    scene = make_scene(
        fixed("cylinder", {"type": "disc", "radius": R}),
        disc("disc", r, (0.0, R + r), velocity=[speed, normal_velocity]),
    )
    run = simulate(scene, 0.2, 1e-3)
    p, t = np.array(run.poses)[:, 1], np.array(run.t)
    error = max(
        np.max(np.abs(p[:, 0] - speed * t)),
        np.max(np.abs(p[:, 1] - (R + r + normal_velocity * t - G * t**2 / 2))),
    )
    _check("grazing cylinder top: parabola (m)", error, 1e-14)
    assert all(np.all(f == 0.0) for f in run.contact_forces)


@pytest.mark.parametrize("clearance", [5e-5, 0.0])
def test_disc_grazing_a_cylinder_without_gravity_is_not_deflected(clearance):
    """Without gravity a disc moving at 1 m/s along the line tangent to a fixed cylinder (or
    5e-5 m above it, inside the 1e-4 contact tolerance) must pass straight: at the touch d' = 0,
    so there is nothing to resolve, and before it the gap is positive. (An impulse applied
    inside the contact tolerance while the gap is still positive would deflect it by up to
    v sqrt(2 tol / L) = 1.8e-2 m/s.) Asserted: the straight line to 1e-15 m, velocity unchanged
    to 1e-15 m/s."""
    R, r = 0.5, 0.1
    y0 = R + r + clearance
    scene = make_scene(
        fixed("cylinder", {"type": "disc", "radius": R}),
        disc("disc", r, (-0.1, y0), velocity=[1.0, 0.0]),
        gravity=(0.0, 0.0),
    )
    run = simulate(scene, 0.2, 1e-3)
    p, v = np.array(run.poses)[:, 1], np.array(run.velocities)[:, 1]
    _check("grazing without gravity: deflection (m)", np.max(np.abs(p[:, 1] - y0)), 1e-15)
    _check("grazing without gravity: |v - v0| (m/s)", np.max(np.abs(v[:, :2] - [1.0, 0.0])), 1e-15)


@pytest.mark.parametrize("normal_velocity", [-1e-12, -1e-9])
def test_grazing_impact_on_a_cylinder_is_the_exact_plastic_impact(normal_velocity):
    """As above, on the tangent line but with vy = -1e-12 (-1e-9) m/s: the disc now does touch,
    at x* = -3.5e-7 (-1.1e-5) m before the top, approaching at v_n = -5.8e-7 (-1.8e-5) m/s
    (below the resting speed: a plastic impulse). Exact result: at the touch point (root of
    |p(t)| = R + r) the normal part of the velocity is removed, v+ = v - (v.n) n.

    The engine locates the touch to a time error dt*; the normal there is off by v dt* / L, and
    so is v+ (measured dt* ~1e-10 s, |v+ - exact| ~2e-10 m/s). Asserted: |v+ - exact| <= 1e-9
    m/s; afterwards the straight line from the touch point to 1e-10 m."""
    R, r = 0.5, 0.1
    length = R + r
    scene = make_scene(
        fixed("cylinder", {"type": "disc", "radius": R}),
        disc("disc", r, (-0.1, length), velocity=[1.0, normal_velocity]),
        gravity=(0.0, 0.0),
    )
    run = simulate(scene, 0.2, 1e-3)
    from scipy.optimize import brentq

    touch = brentq(
        lambda t: math.hypot(t - 0.1, length + normal_velocity * t) - length, 0.0, 0.1, xtol=1e-16
    )
    point = np.array([touch - 0.1, length + normal_velocity * touch])
    n = point / np.hypot(*point)
    v0 = np.array([1.0, normal_velocity])
    after = v0 - (v0 @ n) * n
    assert len(run.impact_times) == 1 and abs(run.impact_times[0] - touch) < 1e-8
    v, p, t = np.array(run.velocities)[:, 1, :2], np.array(run.poses)[:, 1, :2], np.array(run.t)
    late = t > touch
    _check(
        f"grazing impact vy = {normal_velocity:g}: |v+ - exact| (m/s)",
        np.max(np.abs(v[late] - after)),
        1e-9,
    )
    line = point + (t[late] - touch)[:, None] * after
    _check(
        f"grazing impact vy = {normal_velocity:g}: path after (m)",
        np.max(np.abs(p[late] - line)),
        1e-10,
    )
    print(
        f"[hard case] grazing impact: located {run.impact_times[0] - touch:.2g} s off, v_n = {v0 @ n:.2g} m/s"
    )


# -- a contact crossing an arc's end point -----------------------------------------------------


def _lag(speed: float, dt: float, length: float) -> tuple[float, float]:
    """Where a contact crosses from a straight edge to an arc (or back) inside a step, the
    step's constraint is the old feature's: after the step the disc is off the new circle of
    radius L by up to v^2 dt^2 / (2L) with a normal velocity up to v^2 dt / L. Returns both."""
    return speed**2 * dt**2 / (2 * length), speed**2 * dt / length


def test_disc_slides_from_a_flat_face_over_a_rounded_corner():
    """A disc (r = 0.1) slides at 0.5 m/s along the top of a fixed rounded box (corner radius
    0.2) onto the corner arc (circle_edge -> circle_circle at the arc's end point) and leaves it
    where cos phi = 2/3 + v0^2 / (3 g L), L = 0.3 (as over a cylinder).

    The flat face's contact is held on its whole line: were the switch left to the next step's
    contacts, the step that crosses the join would carry the disc on past it, d0 =
    v^2 dt'^2/(2L) above the arc, separating at v^2 dt'/L (dt' <= dt: the part of the step
    beyond the join); it would fall back and land with v_n^2 = (v^2 dt'/L)^2 (1 + a L / v^2),
    a = g - v^2/L, a plastic impact costing m v_n^2 / 2 (1.3e-4 J of 189 J here, as it did up to
    session 24). The event search locates the instant the disc's centre passes the face's end
    (runtime.step.events: a resting contact that left its feature) and the frame there takes
    the arc. Asserted: the energy change <= 1e-8 J (5e-11 of the energy: no impact, the
    integrator's error); the leave angle within 1e-5 rad (the angle is interpolated between
    steps); while the arc pushes, the distance from its centre within the touch gap of L (it
    was up to d0); no penetration.
    """
    width, height, rc, r, v0, dt = 2.0, 1.0, 0.2, 0.1, 0.5, 1e-3
    length = rc + r
    block = {"type": "rounded_rect", "width": width, "height": height, "corner_radius": rc}
    start = (width / 2 - rc - 0.1, height / 2 + r)
    scene = make_scene(fixed("block", block), disc("disc", r, start, velocity=[v0, 0.0]))
    run = simulate(scene, 0.55, dt)
    cx, cy = width / 2 - rc, height / 2 - rc
    cases = [c.case_name(0) if len(c) else None for c in run.contacts]
    order = [k for k, _ in itertools.groupby(cases)]
    assert order[0] == "circle_edge" and "circle_circle" in order and order[-1] is None
    mass = scene.bodies[1].mass
    d0, vn = _lag(v0, dt, length)
    a = G - v0**2 / length
    worst = mass * vn**2 * (1 + a * length / v0**2) / 2
    energy = np.array(run.energy)
    assert worst > 1e4 * 1e-8  # what the unlocated switch cost
    _check("flat -> arc: energy change (J)", np.max(np.abs(energy - energy[0])), 1e-8)
    stepper = Stepper(scene)
    angles, free, radial = [], [], []
    first = cases.index("circle_circle")
    for pose, vel, contacts, force in zip(
        run.poses[first:],
        run.velocities[first:],
        run.contacts[first:],
        run.contact_forces[first:],
        strict=True,
    ):
        # the arc's contact at this pose, held or not, and its d'' if it pushed with no force
        found = scene.contacts(pose, tolerance=1e-2)
        arc = found.take(
            np.array([found.case_name(k) == "circle_circle" for k in range(len(found))], dtype=bool)
        )
        if not len(arc):
            break
        angles.append(math.atan2(pose[1, 0] - cx, pose[1, 1] - cy))
        free.append(stepper.contact_forces(arc, pose, vel).free_rates[0])
        if len(contacts) and force[0] > 0:
            radial.append(abs(math.hypot(pose[1, 0] - cx, pose[1, 1] - cy) - length))
    free = np.array(free)
    k = int(np.argmax(free > 0))
    assert k > 0 and free[k] > 0
    leave = angles[k - 1] + (angles[k] - angles[k - 1]) * free[k - 1] / (free[k - 1] - free[k])
    predicted = math.acos(2 / 3 + v0**2 / (3 * G * length))
    _check("flat -> arc: leave angle (rad)", abs(leave - predicted), 1e-5)
    assert d0 > 100 * TOUCH
    _check("flat -> arc: radial error on the arc (m)", max(radial), TOUCH)
    _check("flat -> arc: penetration (m)", penetration(scene, run.poses), TOUCH)


def test_disc_slides_off_a_rounded_apex_onto_the_straight_side():
    """A fixed rounded box (corner radius 0.2) turned 45 degrees: a disc (r = 0.1) starts on
    top of the apex arc at 0.3 m/s, follows the arc (it would leave only at 47.4 degrees) to its
    end point at 45 degrees and slides on down the straight side (circle_circle -> circle_edge).

    The arc's contact is held on its whole circle, which beyond the join runs inside the
    straight side: were the switch left to the next step's contacts, the disc would end up to
    d0 = v^2 dt^2 / (2L) inside the side (3.0e-6 m; it was 9.6e-8 m here), approaching at up
    to v^2 dt / L, and a plastic impulse would take up to m (v^2 dt / L)^2 / 2 (5.7e-4 J). The
    event search locates the instant the disc's centre passes the arc's end (runtime.step.events:
    a resting contact that left its feature) and the frame there takes the side. Asserted: no
    penetration beyond the touch gap; the energy change <= 1e-8 J (no impact: the integrator's
    error; it was 8.7e-10 J with the side's impact located, 1.8e-5 J unlocated); the penetration
    does not grow afterwards (by more than N ulp(1), N steps on the side); on the side the disc
    accelerates at g sin 45 along it to 1e-9 m/s^2 and has no normal velocity (1e-12 m/s).
    """
    size, rc, r, v0, dt = 1.0, 0.2, 0.1, 0.3, 1e-3
    length, turn = rc + r, math.pi / 4
    c, s = math.cos(turn), math.sin(turn)
    apex = ((size / 2 - rc) * (c - s), (size / 2 - rc) * (s + c))  # the arc's centre, turned
    block = {"type": "rounded_rect", "width": size, "height": size, "corner_radius": rc}
    scene = make_scene(
        fixed("block", block, angle=turn),
        disc("disc", r, (apex[0], apex[1] + length), velocity=[v0, 0.0]),
    )
    run = simulate(scene, 0.5, dt)
    cases = [c.case_name(0) if len(c) else None for c in run.contacts]
    assert cases[0] == "circle_circle" and cases[-1] == "circle_edge"
    k = cases.index("circle_edge")
    assert "circle_circle" not in cases[k:] and None not in cases
    mass = scene.bodies[1].mass
    speed2 = v0**2 + 2 * G * length * (1 - c)  # at the join
    d0, vn = _lag(math.sqrt(speed2), dt, length)
    energy = np.array(run.energy)
    assert mass * vn**2 / 2 > 1e4 * 1e-8  # what a plastic impulse there could cost
    _check("arc -> flat: energy change (J)", np.max(np.abs(energy - energy[0])), 1e-8)
    gaps = np.array([smallest_gap(scene, [p]) for p in run.poses[k:]])
    assert d0 > 1e3 * TOUCH  # (what the located switch saves)
    _check("arc -> flat: penetration (m)", -np.min(gaps), TOUCH)
    # positions ~0.7 m round by ulp(1)/2 per step: at most N ulp(1) over the N steps on the side
    _check("arc -> flat: penetration growth (m)", np.ptp(gaps), len(gaps) * ulp(1.0))
    t = np.array(run.t[k + 1 :])
    vel = np.array(run.velocities)[k + 1 :, 1, :2]
    along = vel @ np.array([c, -s])
    acc = np.diff(along) / np.diff(t)
    _check("arc -> flat: acceleration along the side (m/s^2)", np.max(np.abs(acc - G * s)), 1e-9)
    _check("arc -> flat: normal velocity (m/s)", np.max(np.abs(vel @ np.array([s, c]))), 1e-12)


# -- redundant contacts ----------------------------------------------------------------------

BOX = {"type": "polygon", "points": [[-0.2, -0.1], [0.2, -0.1], [0.2, 0.1], [-0.2, 0.1]]}


def _wall(name, start, end, **extra):
    return fixed(name, {"type": "wall", "start": list(start), "end": list(end), **extra})


REDUNDANT = {
    # 2 bottom corners: not redundant in 2-D (vertical force and torque), m g / 2 each
    "box on a floor": [_wall("floor", (-2, 0), (2, 0))],
    # the box spans the joint of two collinear walls: one corner on each
    "box on two collinear walls": [_wall("left", (-2, 0), (0, 0)), _wall("right", (0, 0), (2, 0))],
    # ... whose ends are vertices: both wall ends touch the box's bottom at the same point
    "box on two collinear walls with end vertices": [
        _wall("left", (-2, 0), (0, 0), end_vertices=True),
        _wall("right", (0, 0), (2, 0), end_vertices=True),
    ],
    # the same floor twice: every constraint doubled
    "box on a doubled floor": [_wall("floor", (-2, 0), (2, 0)), _wall("floor2", (-2, 0), (2, 0))],
    # a container the box exactly fits: 6 contacts (2 on the floor, 2 on each side wall)
    "box exactly fitting a container": [
        fixed("walls", {"type": "box_walls", "width": 0.4, "height": 0.3})
    ],
}


@pytest.mark.parametrize("name", list(REDUNDANT))
def test_box_resting_on_redundant_contacts_stays_put(name):
    """The box (0.4 x 0.2, m = 1) rests at x = 0.05 (x = 0 in the container). The forces are
    not unique when contacts are redundant (A singular); any valid set must hold the box.
    Asserted: no NaN or solver failure; the forces sum to m g and have no torque about the
    centre of mass (1e-12 relative); the box moves less than LCP_TOL g t^2 / 2 (the solver's
    acceptance of |d''| <= LCP_TOL max|b|)."""
    x0 = 0.0 if "container" in name else 0.05
    scene = make_scene(*REDUNDANT[name], moving("box", BOX, (x0, 0.1), mass=1.0))
    contacts = scene.contacts()
    T = 0.1
    run = simulate(scene, T, 1e-3, record_every=10)
    p = np.array(run.poses)[:, -1]
    _check(f"{name}: motion (m)", np.max(np.abs(p - p[0])), LCP_TOL * G * T**2 / 2)
    for pose, resting, forces in zip(run.poses, run.contacts, run.contact_forces, strict=True):
        points, normals = resting.point, resting.normal
        sign = np.where(resting.body1 == len(scene.bodies) - 1, 1.0, -1.0)
        push = (sign * forces)[:, None] * normals  # the force on the box at each contact
        lever = points - pose[-1, :2]
        torque = np.sum(lever[:, 0] * push[:, 1] - lever[:, 1] * push[:, 0])
        assert np.allclose(push.sum(axis=0), [0.0, G], rtol=0, atol=1e-12 * G)
        assert abs(torque) <= 1e-12 * G
    print(f"[hard case] {name}: {len(contacts)} contacts, forces {run.contact_forces[-1]}")


def test_disc_wedged_in_a_v_stays_put():
    """scenes/disc_in_v.toml: two contacts at +-45 degrees, each m g / sqrt 2 (1e-12 relative);
    the disc moves less than LCP_TOL g t^2 / 2."""
    scene = runtime.load_scene(SCENES / "disc_in_v.toml")
    T = 0.2
    run = simulate(scene, T, 1e-3, record_every=10)
    mass = scene.body("disc").mass
    forces = np.array(run.contact_forces)
    _check(
        "disc in V: forces, relative", np.max(np.abs(forces / (mass * G / math.sqrt(2)) - 1)), 1e-12
    )
    p = np.array(run.poses)[:, scene.index("disc")]
    _check("disc in V: motion (m)", np.max(np.abs(p - p[0])), LCP_TOL * G * T**2 / 2)


@pytest.mark.parametrize("radius", [0.1, 1.0])
def test_disc_that_exactly_fits_its_bowl(radius):
    """A disc whose radius equals the bowl's, centred on the bowl's centre: contact along the
    whole arc (a continuum). The narrow phase cannot choose a normal when the two centres
    coincide (|c1 - c2| = 0) and reports no contact, so the disc falls freely for one step,
    g dt^2 / 2 = 4.9e-6 m; then the centres differ, the one contact (gap -4.9e-6, normal up)
    appears, a plastic impulse stops the disc and the force m g holds it there. Asserted: no
    NaN or failure; the sink is at most g dt^2 / 2 (1 + 1e-9); no sideways motion or turning;
    at rest after the second step, and Run.max_penetration reports the sink; force m g to 1e-12
    relative from then on."""
    dt = 1e-3
    bowl = {"type": "bowl", "radius": radius, "start_angle": -2.6, "end_angle": -0.5}
    scene = make_scene(fixed("bowl", bowl), disc("disc", radius, (0.0, 0.0)))
    assert len(scene.contacts()) == 0
    run = simulate(scene, 0.05, dt)
    p, v = np.array(run.poses)[:, 1], np.array(run.velocities)[:, 1]
    _check(f"exact fit r = {radius}: sink (m)", -np.min(p[:, 1]), G * dt**2 / 2 * (1 + 1e-9))
    assert np.all(p[:, 0] == 0.0) and np.all(p[:, 2] == 0.0)
    assert np.all(v[2:] == 0.0)
    # the engine reports the penetration it keeps (Run.min_gap is the gap found at each step)
    assert run.max_penetration == pytest.approx(-np.min(p[:, 1]), rel=1e-9)
    mass = scene.bodies[1].mass
    forces = np.array([f[0] for f in run.contact_forces[2:]])
    _check(
        f"exact fit r = {radius}: force, relative", np.max(np.abs(forces / (mass * G) - 1)), 1e-12
    )


@pytest.mark.parametrize("dt", [1e-3, 1e-4])
def test_disc_that_exactly_fits_its_bowl_moving_sideways(dt):
    """The exactly fitting disc (r = R = 0.1) moving sideways at 0.3 m/s in a half-circle bowl
    (its span covers the direction of motion). Physically a plastic impact at t = 0 stops it
    (no velocity along +-x is admissible). The engine cannot choose a normal at coincident
    centres, so the first step is free: the disc moves v dt sideways and g dt^2 / 2 down;
    then the contact (normal along c1 - c2) stops it from going deeper, and it hangs there as
    a pendulum of length v dt about the bowl's centre (issue #13: "sinks 3e-4 m and stays";
    docs/numerics.md §2.9). Asserted: the sink never exceeds that first step's displacement
    (3.0e-4 m at dt = 1 ms, 3.0e-5 m at 0.1 ms: O(dt), measured equal to it to 1e-9), the
    disc stays in the bowl (no failure, no NaN), and the energy does not grow."""
    v = 0.3
    bowl = {"type": "bowl", "radius": 0.1, "start_angle": -math.pi, "end_angle": 0.0}
    scene = make_scene(fixed("bowl", bowl), disc("disc", 0.1, (0.0, 0.0), velocity=[v, 0.0]))
    run = simulate(scene, 1.0, dt)
    first = math.hypot(v * dt, G * dt**2 / 2)
    sink = np.hypot(run.poses[:, 1, 0], run.poses[:, 1, 1])
    _check(f"exact fit sideways dt = {dt}: sink / first step", np.max(sink) / first, 1 + 1e-9)
    assert sink[-1] >= 0.99 * first  # it stays down: nothing pushes the overlap out
    assert run.max_penetration == pytest.approx(np.max(sink), rel=1e-6)
    assert np.max(run.energy - run.energy[0]) <= 1e-9 * run.energy[0]


def test_disc_that_exactly_fits_a_bowl_with_open_ends_leaves_through_an_end():
    """The shipped bowl's span (-150 .. -30 degrees) does not cover the direction of motion:
    without end corners (end_vertices = false, the default) nothing holds the disc where the
    arc ends, it slides out through the arc near its end, and the penetration guard stops the
    run naming the pair; with end corners the end stops it (a plastic impact at t = 0 along
    the end's direction u, taking m (v.u)^2 / 2), it pivots about the end (no energy lost),
    rises 1.2 mm and comes back to the centre, where a located plastic impact on the arc
    takes the rest of its kinetic energy: at rest at the centre, no penetration."""
    v, dt = 0.3, 1e-3
    span = {"start_angle": -5 * math.pi / 6, "end_angle": -math.pi / 6}
    for corners in (False, True):
        bowl = {"type": "bowl", "radius": 0.1, **span, "end_vertices": corners}
        scene = make_scene(fixed("bowl", bowl), disc("disc", 0.1, (0.0, 0.0), velocity=[v, 0.0]))
        if not corners:
            with pytest.raises(runtime.SimulationError, match=r"left disc/bowl overlapping by"):
                runtime.simulate(scene, 1.0, dt)
            continue
        run = simulate(scene, 1.0, dt)
        kinetic = 0.5 * scene.bodies[1].mass * v**2
        loss = kinetic * math.cos(math.pi / 6) ** 2
        assert run.impact_losses[1] == pytest.approx(loss, rel=1e-12)
        back = int(np.searchsorted(run.t, run.impact_times[-1]))  # the return to the centre
        assert len(run.impact_times) == 1 and back > 1
        assert np.max(np.abs(run.energy[1:back] - (run.energy[0] - loss))) <= 1e-9 * kinetic
        assert np.sum(run.impact_losses) == pytest.approx(kinetic, rel=1e-9)  # all of it
        assert run.max_penetration <= 1e-12
        assert np.max(np.abs(run.poses[-1, 1])) <= 1e-12
        assert np.max(np.abs(run.velocities[-1, 1])) <= 1e-12


def test_an_impact_located_on_the_step_end_finishes_the_step():
    """A soak scene (Euler, 0.49 s steps, found at 30x coarse steps): an impact located by
    rounding at the step's very end left h - elapsed = -1e-16 s, whose negative reach the
    contact finder refused ("margins must be finite and >= 0") as a failure at t = 10.3 s. Now
    the rest of the step is empty, as when it ends on the impact exactly: 12 s without a
    failure; the restitution-0 box lands and slides on (frictionless: its horizontal velocity is
    kept, its vertical one gone to 1e-9 of the 28 m/s it fell at)."""
    data = json.loads((Path(__file__).parent / "data" / "impact_on_step_end.json").read_text())
    run = runtime.simulate(runtime.scene_from_dict(data, source="soak"))
    assert run.t[-1] == pytest.approx(12.0)
    v0, v1 = run.velocities[0, 1], run.velocities[-1, 1]
    assert v1[0] == pytest.approx(v0[0], rel=1e-12)
    assert abs(v1[1]) <= 1e-9 * abs(v0[1])


def test_mixed_bodies_falling_into_a_v_do_not_sink_into_each_other():
    """30 bodies of every shape (discs, boxes, rounded boxes, half discs, ellipses) falling into
    a V, 0.44 s of World.step: at t = 0.392 s an ellipse resting on a rounded box's corner arc
    slid on past the arc's end and went 4.6e-6 m into the box's side, unlocated (a resting
    contact is held on its feature's whole circle); at t = 0.433 s a disc-disc contact restarted
    just past its lift-off was found pressing with 1.3e-7 N of its island's 165 N (a redundant
    set's other solution) and located lifting again 4e-12 s on, over and over, until "more than
    1000 events within one step" (runtime.step.lift_events: pressing means above LCP_TOL of the
    island's largest force). Asserted after every step, by the contact
    finder: no overlap beyond 1e-7 m -- resting contacts on curves may drift settings.DRIFT of
    g dt^2 / 2 (4.9e-9 m) a step before a frame holds them again: 2.0e-8 m at most here."""
    from bench.scenes import mixed_bodies

    scene = mixed_bodies(30)
    world = runtime.World(scene)
    deepest = 0.0
    for _ in range(440):
        world.step(1e-3)
        deepest = max(deepest, penetration(scene, [world.poses]))
    _check("mixed bodies in a V: deepest overlap (m)", deepest, 1e-7)
