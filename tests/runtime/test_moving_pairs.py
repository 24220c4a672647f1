"""Two moving bodies meeting within a step (issue #13, "moving bodies pass through each other").

Why: two discs head-on at +-100 m/s with dt = 1/60 s move 3.3 m a step, 17 diameters; a disc at
50 m/s crosses a resting one in a step. The gap is positive at both ends of such a step, so a
fit of the gap between the ends finds nothing: the impact search must sample the pair
(runtime.step.events, fast pairs), and if it still misses, the moving-pair tunnelling guard
(runtime.step.guards.passed_through) must stop the run naming the pair.

References: the impact of two discs is a closed form. The centres move on straight lines
(no gravity) until |c1 - c2| = r1 + r2 (a quadratic in t); the impulse along the normal n gives
v1' = v1 - (1 + e) m2 / (m1 + m2) (v_rel . n) n, v2' = v2 + (1 + e) m1 / (m1 + m2) (v_rel . n) n.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import strategies

import runtime
from runtime.step import events
from runtime.step.events import EventSearch

R = 0.1  # disc radius, m
DT = 1.0 / 60.0


def _disc(name, position, velocity, mass=1.0, restitution=0.0) -> dict:
    return {"name": name, "shape": {"type": "disc", "radius": R}, "mass": mass,
            "position": list(position), "velocity": list(velocity),
            "restitution": restitution}  # fmt: skip


def _scene(*bodies, gravity=(0.0, 0.0)) -> runtime.Scene:
    return runtime.scene_from_dict(
        {"scene": {"gravity": list(gravity)}, "body": list(bodies)}, source="moving pairs"
    )


def _exact_impact(p1, v1, p2, v2, m1, m2, e):
    """(time of contact, v1 after, v2 after) of two discs of radius R in free flight."""
    p, v = np.subtract(p1, p2), np.subtract(v1, v2)
    a, b, c = v @ v, 2.0 * (p @ v), p @ p - (2 * R) ** 2
    t = (-b - math.sqrt(b * b - 4.0 * a * c)) / (2.0 * a)
    n = (p + v * t) / (2 * R)
    jn = (1.0 + e) * (v @ n) / (1.0 / m1 + 1.0 / m2)
    return t, np.asarray(v1) - jn / m1 * n, np.asarray(v2) + jn / m2 * n


@pytest.mark.parametrize("restitution", [1.0, 0.5, 0.0])
@pytest.mark.parametrize(
    "offset",
    [0.0, 0.15, 0.1999999],
    ids=["head-on", "glancing", "near graze"],  # normal at 0, 41 and 89.94 degrees
)
def test_discs_head_on_at_100_m_per_s_collide_exactly(restitution, offset):
    """+-100 m/s, dt = 1/60 s, masses 1 and 3 kg: one located impact at the exact time, the
    exact velocities after it, the exact positions at every step, never an overlap. The near
    graze (centres passing 1e-7 m closer than touching; 0.2 m/s along the normal) used to be
    missed: the Hermite cubic between two samples of the fast pair does not dip that far
    (runtime.step.events.find_dip checks the real gap)."""
    p1, v1, p2, v2, m1, m2 = (-0.5, 0.0), (100.0, 0.0), (0.5, offset), (-100.0, 0.0), 1.0, 3.0
    scene = _scene(_disc("a", p1, v1, m1, restitution), _disc("b", p2, v2, m2, restitution))
    run = runtime.simulate(scene, duration=3 * DT, dt=DT)
    t_hit, u1, u2 = _exact_impact(p1, v1, p2, v2, m1, m2, restitution)
    assert run.impact_times.tolist() == pytest.approx([t_hit], abs=1e-12)
    np.testing.assert_allclose(run.velocities[-1, :, :2], [u1, u2], rtol=0, atol=1e-9)
    after = run.t[1:] - t_hit
    np.testing.assert_allclose(
        run.poses[1:, 0, :2], np.add(p1, np.multiply(v1, t_hit)) + np.outer(after, u1), atol=1e-9
    )
    np.testing.assert_allclose(
        run.poses[1:, 1, :2], np.add(p2, np.multiply(v2, t_hit)) + np.outer(after, u2), atol=1e-9
    )
    distance = np.hypot(*(run.poses[:, 0, :2] - run.poses[:, 1, :2]).T)
    assert np.all(distance >= 2 * R - 1e-12) and run.max_penetration <= 1e-12


@pytest.mark.parametrize("offset", [0.2, 0.2000001])
def test_discs_passing_at_touching_distance_or_beyond_are_not_deflected(offset):
    """Centres passing exactly 2 r apart (a tangent touch, a graze) or 1e-7 m farther: no
    impact, the velocities unchanged."""
    scene = _scene(_disc("a", (-0.5, 0.0), (100.0, 0.0), 1.0, 1.0),
                   _disc("b", (0.5, offset), (-100.0, 0.0), 3.0, 1.0))  # fmt: skip
    run = runtime.simulate(scene, duration=3 * DT, dt=DT)
    assert run.impact_times.size == 0
    assert np.all(run.velocities[:, :, 0] == [100.0, -100.0]) and np.all(
        run.velocities[:, :, 1:] == 0
    )


@pytest.mark.parametrize("restitution", [1.0, 0.5, 0.0])
def test_disc_at_50_m_per_s_hits_a_resting_disc_on_a_floor(restitution):
    """Both discs rest on a frictionless floor (gravity on); one slides at 50 m/s into the other
    (0.8 m away: 2.9 steps of travel in one step of 1/60 s). The impact is the 1-D exchange of
    equal masses (the floor contacts take no impulse): v = 50 (1 - e) / 2 and 50 (1 + e) / 2."""
    floor = {"name": "floor", "fixed": True,
             "shape": {"type": "wall", "start": [-50.0, 0.0], "end": [50.0, 0.0]}}  # fmt: skip
    a = _disc("a", (-1.0, R), (50.0, 0.0), restitution=restitution)
    b = _disc("b", (0.0, R), (0.0, 0.0), restitution=restitution)
    run = runtime.simulate(_scene(floor, a, b, gravity=(0.0, -9.81)), duration=3 * DT, dt=DT)
    assert run.impact_times.tolist() == pytest.approx([0.8 / 50.0], abs=1e-12)
    expected = [[25.0 * (1 - restitution), 0.0, 0.0], [25.0 * (1 + restitution), 0.0, 0.0]]
    np.testing.assert_allclose(run.velocities[-1, 1:], expected, rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.poses[:, 1:, 1], R, rtol=0, atol=1e-12)  # on the floor
    assert run.poses[-1, 2, 0] - run.poses[-1, 1, 0] >= 2 * R - 1e-12
    assert run.max_penetration <= 1e-12


@pytest.mark.parametrize(
    "bodies",
    [
        ((-0.5, 0.0), (100.0, 0.0), (0.5, 0.0), (-100.0, 0.0)),  # head-on, both moving
        ((-1.0, 0.0), (50.0, 0.0), (-0.5, 0.0), (0.0, 0.0)),  # at a disc at rest
    ],
    ids=["head-on", "at rest"],
)
def test_without_the_impact_search_the_guard_names_the_pair(monkeypatch, bodies):
    """The impact search switched off (no event is ever found): the discs pass through each
    other within the first step, leaving no overlap at its end; the moving-pair tunnelling
    guard stops the run at that step, names both discs and keeps the state before it. With
    the guard off too, the run ends 'successfully' with the discs through each other."""
    monkeypatch.setattr(EventSearch, "first", lambda self, *args: {})
    p1, v1, p2, v2 = bodies
    scene = _scene(_disc("a", p1, v1), _disc("b", p2, v2))
    with pytest.raises(runtime.SimulationError) as info:
        runtime.simulate(scene, duration=3 * DT, dt=DT)
    assert str(info.value).startswith(
        "step 0 at t = 0 s moved a and b through each other (a centre of mass came inside the "
        "other body's inscribed circle): the time step is too large"
    )
    np.testing.assert_array_equal(info.value.state[0], scene.poses())
    np.testing.assert_array_equal(info.value.state[1], scene.velocities())
    run = runtime.simulate(scene, duration=DT, dt=DT, guards=runtime.Guards(penetration=None))
    assert run.poses[-1, 0, 0] > run.poses[-1, 1, 0]  # passed through, silently


@pytest.mark.parametrize("fixed", [False, True], ids=["moving target", "fixed target"])
def test_centres_coinciding_at_a_trial_steps_end(fixed):
    """A disc at 50 m/s from 0.5 m away, dt = 0.01 s: the trial step ends with its centre
    exactly on the other disc's centre, where d' (and the normal) is undefined (0/0). This used
    to fail with 'Array must not contain infs or NaNs' (then ZeroDivisionError from the
    compiled kernel). Now: one plastic impact at t = 0.3 / 50 = 6 ms, the exact velocities
    after (equal masses: 25 and 25 m/s; a fixed target: 0), no overlap."""
    target = _disc("b", (0.0, 0.0), (0.0, 0.0))
    if fixed:
        target = {"name": "b", "fixed": True, "shape": target["shape"], "position": [0.0, 0.0]}
    scene = _scene(_disc("a", (-0.5, 0.0), (50.0, 0.0)), target)
    run = runtime.simulate(scene, duration=0.04, dt=0.01)
    assert run.impact_times.tolist() == pytest.approx([0.006], abs=1e-12)
    expected = [0.0, 0.0] if fixed else [25.0, 25.0]
    np.testing.assert_allclose(run.velocities[-1, :, 0], expected, rtol=0, atol=1e-9)
    assert np.all(np.isfinite(run.poses)) and run.max_penetration <= 1e-12


FOUND = json.loads((Path(__file__).parent / "data" / "moving_pairs_found.json").read_text())


@pytest.mark.parametrize("case", FOUND, ids=[c["what"][:60] for c in FOUND])
def test_moving_pairs_the_fuzzing_found_overlapping_do_not(case):
    """Scenes of tests/strategies.moving_pairs (2-8 half-widths a step, no gravity) that
    overlapped by 1-28 % of a body's size, silently or stopped by the penetration guard: a
    body turned by an impact brings another corner round within the same step, which no
    contact watched (runtime.step.events: fast pairs' other features are scanned with the
    contact finder). Now: no error, no overlap (sampled, 1e-9 half-widths), momentum kept."""
    scene = runtime.scene_from_dict(case["scene"], source="found")
    run = runtime.simulate(scene)
    half = min(strategies._half_width(s) for s in scene.shapes)
    depth, _, what = strategies.deepest_penetration(scene, run.poses, 1e-9 * half)
    assert depth <= 1e-9 * half, what
    report = strategies.Report(None, scene, run)
    strategies.check_conservation(report)
    assert not report.problems, report.problems


def test_an_impact_that_speeds_an_island_up_meets_the_next_body_within_the_step():
    """Three discs in a row (found by the fuzzing): a heavy one (10 m) strikes a resting one,
    which then reaches a slow third within the same step (dt = 0.083 s). Before, the struck
    disc's island was advanced on its own with margins from its speed before the impact, the
    third disc outside it, and they overlapped by 2.7 cm at the step's end. Closed form:
    elastic impacts one at a time, v' from the module docstring's formulas in 1-D."""
    m, big, e = 1.0, 10.0, 1.0
    bodies = [_disc("d1", (0.0, 0.0), (0.2, 0.0), m, e), _disc("d2", (2 * R + 0.05, 0.0), (0.0, 0.0), m, e),
              _disc("d3", (4 * R + 0.1, 0.0), (-1.0, 0.0), big, e)]  # fmt: skip
    run = runtime.simulate(_scene(*bodies), duration=0.25, dt=0.0832)

    def hit(u1, u2, m1, m2):  # 1-D elastic impact
        return ((m1 - m2) * u1 + 2 * m2 * u2) / (m1 + m2), ((m2 - m1) * u2 + 2 * m1 * u1) / (
            m1 + m2
        )

    x, v, times, t = np.array([0.0, 2 * R + 0.05, 4 * R + 0.1]), np.array([0.2, 0.0, -1.0]), [], 0.0
    for i, j, mi, mj in [(1, 2, m, big), (0, 1, m, m), (1, 2, m, big)]:
        tau = (x[j] - x[i] - 2 * R) / (v[i] - v[j])
        x, t = x + tau * v, t + tau
        v[i], v[j] = hit(v[i], v[j], mi, mj)
        times.append(t)
    assert run.impact_times == pytest.approx(times, abs=1e-12)
    assert np.all(np.diff(v) > 0)  # no fourth impact: they move apart
    np.testing.assert_allclose(run.velocities[-1, :, 0], v, rtol=0, atol=1e-12)
    assert run.max_penetration < 1e-12


def test_a_corner_sliding_past_a_corner_onto_its_edge():
    """Two polygons at 0.84 m/s, no rotation (found by the fuzzing): at the step's start the
    nearest features are a corner of each (a vertex_circle contact with a zero radius, gap
    2.8 mm); within the step the first corner slides past the other onto its adjacent edge.
    The corners' distance is smaller inside the step than at either end, so the pair counts as
    closing while its contact approaches at the start, and the edge's first touch is located
    (before: no impact, a 4.4 mm overlap)."""
    data = json.loads((Path(__file__).parent / "data" / "corner_slides_onto_edge.json").read_text())
    run = runtime.simulate(runtime.scene_from_dict(data, source="found"))
    assert run.max_penetration < 1e-9


@pytest.mark.parametrize("overlap", [1e-3, 1e-5, 1e-7])
@pytest.mark.parametrize("x0, x1", [(-0.1, 0.3), (-0.05, 0.4), (-0.3, 0.05), (-0.2, 0.6)])
def test_a_shallow_dip_is_found_at_its_exact_entry_time(overlap, x0, x1):
    """Two discs (radii summing to R = 1 m) passing with a miss distance R - overlap, from
    x0 to x1 along their relative line within one interval, asymmetric so that the Hermite
    cubic's minimum is not the real one: find_dip must narrow toward the real minimum (the side
    where the real d' changes sign, over several levels for the shallow dips) and bracket the
    exact entry time x = -sqrt(R^2 - b^2), which locate then finds to 1e-8 s."""
    b, speed, span = 1.0 - overlap, 1.0, x1 - x0

    def gap(t: float) -> tuple[float, float]:
        x = x0 + speed * t
        r = math.hypot(x, b)
        return r - 1.0, x * speed / r

    enter = (-math.sqrt(1.0 - b * b) - x0) / speed
    (g0, v0), (g1, v1) = gap(0.0), gap(span)
    assert g0 > 0 and g1 > 0 and v0 < 0 < v1  # open at both ends: only the dip search sees it
    bracket = events.find_dip(gap, 0, 0.0, g0, v0, span, g1, v1)
    assert bracket is not None
    assert bracket.lo <= enter <= bracket.hi and gap(bracket.hi)[0] <= 0
    t, _ = events.locate(gap, bracket.lo, bracket.hi, bracket.guess, gap_tol=1e-13, time_tol=1e-15)
    assert abs(t - enter) <= 1e-8
