"""Impacts, times of impact, tunnelling and resting piles (issue: collisions, resting piles).

Why: an impact must happen at d = 0 (located inside the step), with the restitution law and the
multi-contact policy of runtime/solve/impulses.py, and bouncing must end in a resting contact in
finite time. The numbers asked for by the issue are asserted here; bench/settle.py runs the pile
and the stack until they rest and reports timings.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

import runtime
from runtime.collide import sweep
from runtime.solve import assembly, impulses, lcp
from runtime.step import events
from runtime.step.classify import Limits, Mode, classify
from runtime.step.collision import Collision
from runtime.step.stepper import Stepper

SCENES = Path(__file__).resolve().parents[2] / "scenes"
G = 9.81
R = 0.0625  # exact in binary: rows of touching discs touch exactly


def disc(name, x, y, *, vx=0.0, vy=0.0, e=1.0, r=R):
    return {
        "name": name,
        "shape": {"type": "disc", "radius": r},
        "density": 1000.0,
        "position": [x, y],
        "velocity": [vx, vy],
        "restitution": e,
    }


def scene(bodies, gravity=(0.0, 0.0)):
    return runtime.scene_from_dict(
        {"scene": {"name": "test", "gravity": list(gravity)}, "body": bodies}
    )


def final_velocities(run) -> np.ndarray:
    return np.asarray(run.velocities[-1])


# -- two discs and rows of discs ---------------------------------------------------------------


def test_head_on_elastic_collision_exchanges_velocities():
    s = scene([disc("a", -0.225, 0.0, vx=1.0), disc("b", 0.0, 0.0)])  # gap 0.1 m
    run = runtime.simulate(s, duration=0.2, dt=1e-3)
    v = final_velocities(run)
    assert np.max(np.abs(v[:, 0] - [0.0, 1.0])) < 1e-12
    assert np.max(np.abs(v[:, 1:])) == 0.0
    assert run.impact_times == [pytest.approx(0.1, abs=1e-12)]  # at d = 0, inside step 100
    assert run.max_penetration < 1e-12


def test_head_on_plastic_collision_moves_them_together():
    s = scene([disc("a", -0.225, 0.0, vx=1.0, e=0.0), disc("b", 0.0, 0.0, e=0.0)])
    run = runtime.simulate(s, duration=0.2, dt=1e-3)
    v = final_velocities(run)
    assert np.max(np.abs(v[:, 0] - 0.5)) < 1e-12
    poses = np.asarray(run.poses[-1])
    assert abs(poses[1, 0] - poses[0, 0] - 2 * R) < 1e-12  # still touching, not penetrating


def cradle(n=5, e=1.0):
    bodies = [disc("striker", -2 * R - 0.1, 0.0, vx=1.0, e=e)]
    bodies += [disc(f"d{k}", 2 * R * k, 0.0, e=e) for k in range(n - 1)]
    return scene(bodies)


def test_newtons_cradle_sends_the_last_disc_off():
    run = runtime.simulate(cradle(), duration=0.2, dt=1e-3)
    v = final_velocities(run)
    assert np.max(np.abs(v[:-1])) < 1e-12
    assert abs(v[-1, 0] - 1.0) < 1e-12 and np.max(np.abs(v[-1, 1:])) == 0.0
    assert run.max_penetration < 1e-12


def test_a_simultaneous_lcp_would_not_give_the_cradle():
    """The policy's effect: at the instant of impact the waves send the last disc off alone,
    one simultaneous LCP over the touching row moves the row together instead."""
    s = cradle()
    poses, vel = s.poses(), s.velocities()
    poses[0, 0] = -2 * R  # the striker touching the row
    stepper = Stepper(s)
    contacts = s.contacts(poses)
    rows = stepper.evaluator.rows(contacts, poses, vel)
    A = np.empty((len(contacts), len(contacts)))
    jac, inverse_mass = np.ascontiguousarray(rows.jacobian), s.inverse_masses
    fixed = np.asarray(s.fixed)
    assembly.island_matrix(jac, rows.body1, rows.body2, inverse_mass, fixed, 0, len(contacts), A)
    e = np.ones(len(contacts))

    def velocities_after(p):
        dv = np.zeros_like(vel)
        assembly.add_forces(jac, rows.body1, rows.body2, inverse_mass, p, dv)
        return vel + dv

    waves = impulses.resolve(A, rows.gap_velocity, e, 1e-3, 1e-9)
    together = velocities_after(impulses.simultaneous(A, rows.gap_velocity, e, 1e-3))
    assert waves.waves == 4
    assert np.max(np.abs(velocities_after(waves.impulses)[:, 0] - [0, 0, 0, 0, 1])) < 1e-12
    # simultaneously, the row acts as one body of 4 masses: the striker rebounds at -3/5 and
    # the row moves on together at 2/5 (momentum and energy conserved, but no cradle)
    assert np.max(np.abs(together[:, 0] - [-0.6, 0.4, 0.4, 0.4, 0.4])) < 1e-12


def test_ball_hitting_two_touching_balls_at_once():
    """A hits B and C (touching each other) at the same instant: one simultaneous wave. For
    equal discs at 30 degrees from the line of motion, A leaves upward at v/5, B and C at
    0.8 v cos 30 along their normals; the elastic impact conserves energy."""
    h = R * math.sqrt(3.0)  # equilateral triangle of centres, side 2 R
    s = scene([disc("b", -R, 0.0), disc("c", R, 0.0), disc("a", 0.0, h + 0.05, vy=-1.0)])
    run = runtime.simulate(s, duration=0.1, dt=1e-3)
    v = final_velocities(run)
    assert len(run.impact_times) == 1
    assert abs(v[2, 1] - 0.2) < 1e-12 and abs(v[2, 0]) < 1e-12
    speed = 0.8 * math.cos(math.radians(30))
    expected_b = -speed * np.array([math.sin(math.radians(30)), math.cos(math.radians(30))])
    assert np.max(np.abs(v[0, :2] - expected_b)) < 1e-12
    assert np.max(np.abs(v[1, :2] - expected_b * [-1, 1])) < 1e-12
    assert abs(np.sum(v[:, :2] ** 2) - 1.0) < 1e-12


def test_block_landing_flat_bounces_without_spin():
    """Both bottom corners meet the floor at the same instant: one wave, no rotation."""
    block = {
        "name": "block",
        "shape": {"type": "rounded_rect", "width": 0.5, "height": 0.25, "corner_radius": 0.0},
        "density": 400.0,
        "position": [0.1, 0.125 + 0.2],
        "restitution": 0.5,
    }
    floor = {"name": "floor", "fixed": True,
             "shape": {"type": "wall", "start": [-2.0, 0.0], "end": [2.0, 0.0]}}  # fmt: skip
    run = runtime.simulate(scene([floor, block], (0.0, -G)), duration=0.25, dt=1e-3)
    t_hit = math.sqrt(2 * 0.2 / G)
    assert run.impact_times[0] == pytest.approx(t_hit, abs=1e-12)
    k = next(i for i, t in enumerate(run.t) if t > t_hit)
    vy = run.velocities[k][1, 1] + G * (run.t[k] - t_hit)  # just after the bounce
    assert vy == pytest.approx(0.5 * G * t_hit, abs=1e-12)
    assert np.max(np.abs(np.asarray(run.velocities)[:, 1, 2])) < 1e-12


# -- every contact case: the time of impact is located at d = 0 -----------------------------


def fixed(name, shape, x=0.0, y=0.0):
    return {"name": name, "fixed": True, "shape": shape, "position": [x, y]}


def square(y, e=0.0):
    """A square standing on a corner (45 degrees): its lowest corner at (0, y - a sqrt 2 / 2)."""
    return {"name": "square", "shape": {"type": "rounded_rect", "width": 0.2, "height": 0.2,
            "corner_radius": 0.0}, "density": 500.0, "position": [0.0, y],
            "angle": math.pi / 4, "restitution": e}  # fmt: skip


HALF_DIAGONAL = 0.1 * math.sqrt(2.0)
WALL = {"type": "wall", "start": [-1.0, 0.0], "end": [1.0, 0.0]}
BOWL = {"type": "bowl", "radius": 1.0, "start_angle": -2.5, "end_angle": -0.6}
CASES = {
    # case: (bodies, height fallen at the impact)
    "vertex_edge": ([fixed("floor", WALL), square(0.5)], 0.5 - HALF_DIAGONAL),
    "vertex_circle": (
        [fixed("post", {"type": "disc", "radius": 0.3}, 0.0, -0.3), square(0.5)],
        0.5 - HALF_DIAGONAL,
    ),
    "vertex_circle_concave": ([fixed("bowl", BOWL), square(0.0)], 1.0 - HALF_DIAGONAL),
    "circle_edge": ([fixed("floor", WALL), disc("d", 0.0, 0.5, e=0.0, r=0.1)], 0.4),
    "circle_circle": (
        [fixed("post", {"type": "disc", "radius": 0.3}, 0.0, -0.3), disc("d", 0, 0.5, e=0, r=0.1)],
        0.4,
    ),
    "circle_circle_concave": ([fixed("bowl", BOWL), disc("d", 0.0, -0.5, e=0.0, r=0.1)], 0.4),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_impact_is_located_at_zero_gap_in_every_case(case):
    bodies, fall = CASES[case]
    s = scene(bodies, (0.0, -G))
    near = s.contacts(s.poses(), 10.0)
    found = {near.case_name(k) for k in range(len(near))}
    assert case.removesuffix("_concave") in found
    run = runtime.simulate(s, duration=0.5, dt=1e-3)
    assert run.impact_times[0] == pytest.approx(math.sqrt(2 * fall / G), abs=1e-12)
    assert run.max_penetration < 1e-9
    mover = np.asarray(run.velocities)[:, 1]
    assert np.max(np.abs(mover[-1])) < 1e-9  # plastic impact, then resting


@pytest.mark.parametrize("dt", [1e-3, 0.05])
def test_spinning_oval_lands_at_zero_gap(dt):
    """An ellipse spinning as it falls: the contact point moves over the oval (its osculating
    circle is found again at each Newton step); the impact time solves y(t) = support(t). RK4
    integrates this free flight exactly (a quadratic in t, a constant spin), so the located time
    is that root to rounding; with a long step (0.05 s) the cubic's first guess is not the root
    and Newton must finish the job (stopping at |d| <= the touch gap instead of a thousandth of
    it is 4e-11 s early)."""
    a, b, w, y0, phi0 = 0.2, 0.1, 3.0, 0.6, 0.4
    oval = {"name": "oval", "shape": {"type": "ellipse", "a": a, "b": b}, "density": 500.0,
            "position": [0.0, y0], "angle": phi0, "angular_velocity": w}  # fmt: skip
    s = scene([fixed("floor", WALL), oval], (0.0, -G))
    run = runtime.simulate(s, duration=0.35, dt=dt)

    def gap(t):
        phi = phi0 + w * t
        return y0 - 0.5 * G * t * t - math.sqrt((a * math.sin(phi)) ** 2 + (b * math.cos(phi)) ** 2)

    lo, hi = 0.0, 0.35
    for _ in range(200):  # bisection to rounding: the reference time of impact
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if gap(mid) > 0 else (lo, mid)
    assert gap(0.35) < 0 and run.impact_times[0] == pytest.approx(lo, abs=1e-12)
    # (after the impact it rocks on the floor in resting contact, where the oval's osculating
    # circle is frozen over a step: that drift belongs to the resting-contact path)


# -- contact modes and brackets ---------------------------------------------------------------


def test_contact_modes_are_explicit():
    limits = Limits(touch=1e-9, hold_gap=1e-7, resting_speed=1e-3, separation_speed=1e-3,
                    creep_speed=1e-9)  # fmt: skip
    cases = [  # (gap, d', held before, mode)
        (1e-3, -1.0, False, Mode.OPEN),
        (0.0, -0.5, False, Mode.COLLIDING),  # restitution applies
        (0.0, -1e-4, False, Mode.RESTING),  # plastic impulse, then held by the force
        (0.0, 1e-4, False, Mode.RESTING),  # moving apart slowly: rests (pressed if pressed)
        (0.0, 2e-3, False, Mode.SEPARATING),
        (1e-12, -1e-4, True, Mode.RESTING),
        (5e-8, 1e-12, True, Mode.RESTING),  # drifted apart by less than the hold gap
        (5e-8, -1e-4, True, Mode.RESTING),  # and coming back slowly: no new impact
        (5e-8, 1e-4, True, Mode.RESTING),  # moving apart slowly: pressed or lifting (resting.py)
        (5e-8, -2e-3, True, Mode.COLLIDING),  # coming back fast: its impact is now
        (5e-8, 2e-3, True, Mode.OPEN),  # moving apart fast: let go
        (1e-6, 1e-4, True, Mode.OPEN),  # beyond the hold gap: let go
        (1e-6, -1e-4, False, Mode.OPEN),  # beyond the hold gap: its impact will be located
        (5e-8, -1e-4, False, Mode.RESTING),  # closing within the hold gap: plastic now
        (5e-8, -0.5, False, Mode.COLLIDING),  # ... and with restitution when fast
        (5e-8, 1e-4, False, Mode.OPEN),  # within the hold gap but moving apart: open
    ]
    gap, dv, held, expected = (np.array(c) for c in zip(*cases, strict=True))
    modes = classify(gap, dv, limits, held.astype(bool))
    assert modes.tolist() == [int(m) for m in expected]


@pytest.mark.parametrize("up", [5e-4, 1.5e-3])
def test_a_disc_pushed_off_the_floor_hops_or_rests_but_never_hovers(up):
    """Slower than the separation speed (the resting speed, 1e-3 m/s) it rests at once (its hop
    would be shorter than 0.2 ms and land plastically); faster it hops, its landing is located
    at t = 2 v / g, and a bounce slower than the separation speed rests at once too: |v| = 0,
    gap 0 -- never drifting up while the force holds it."""
    s = scene([fixed("floor", WALL), disc("d", 0.0, 0.1, vy=up, e=0.5, r=0.1)], (0.0, -G))
    run = runtime.simulate(s, duration=0.01, dt=1e-3)
    if up < 1e-3:
        assert run.impact_times.size == 0 and run.contacts[1]
    else:  # lands at 1.5e-3 m/s: the bounce (7.5e-4) is below the separation speed: rests
        assert run.impact_times == [pytest.approx(2 * up / G, abs=1e-12)]
    assert np.max(np.abs(run.velocities[-1])) < 1e-12
    assert abs(run.poses[-1][1][1] - 0.1) < 1e-12


def test_brackets_catch_crossings_dips_and_returns():
    h = 1e-3
    # free flight d = g0 + v0 t - g t^2 / 2: the cubic guess is its exact root
    g0, v0 = 1e-3, -1.5
    g1, v1 = g0 + v0 * h - 0.5 * G * h * h, v0 - G * h

    def brackets(g0, v0, g1, v1, touching):
        return events.brackets(*(np.array(x, dtype=float) for x in (g0, v0, g1, v1)), h,
                               np.array(touching, dtype=bool))  # fmt: skip

    [b] = brackets([g0], [v0], [g1], [v1], [False])
    root = (-v0 - math.sqrt(v0 * v0 + 2 * G * g0)) / -G
    assert b.kind == events.CROSS and b.guess == pytest.approx(root, rel=1e-12)
    # a dip below zero and back within the step (both ends open)
    [b] = brackets([1e-7], [-1e-3], [1e-7], [1e-3], [False])
    assert b.kind == events.DIP and 0 < b.guess < b.hi < h
    # a touching contact that separates and comes back (a bounce shorter than the step)
    [b] = brackets([0.0], [2e-3], [-1e-6], [-8e-3], [True])
    assert b.kind == events.RETURN and 0 < b.lo < b.guess < h
    assert brackets([1e-3], [1.0], [2e-3], [1.0], [False]) == []
    # a touching contact that closes from the start (taken as lifting or separating, it sinks:
    # a falling 30-disc pile with mu = 1), from d > 0 or from d <= 0: the whole step
    a = 0.85
    for g0 in (4.3e-8, -5e-14):
        [b] = brackets([g0], [0.0], [g0 - 0.5 * a * h * h], [-a * h], [True])
        assert b.kind == events.SINK and (b.lo, b.hi) == (0.0, h)


# -- bouncing ball -------------------------------------------------------------------------------


def test_ball_bounces_to_h_e2k_then_rests_in_finite_time():
    s = runtime.load_scene(SCENES / "ball_drop.toml")
    e, h0, r = 0.5, 1.0, 0.1
    run = runtime.simulate(s, duration=1.6, dt=1e-3)
    t = np.asarray(run.t)
    y, vy = np.asarray(run.poses)[:, 1, 1], np.asarray(run.velocities)[:, 1, 1]
    apex = y - r + vy**2 / (2 * G)  # the height this flight reaches (exact for free flight)
    hits = run.impact_times
    for k in range(1, 6):
        flight = (t > hits[k - 1]) & (t < hits[k])
        assert flight.any()
        assert np.max(np.abs(apex[flight] / (h0 * e ** (2 * k)) - 1.0)) < 1e-6
    # the impact times themselves: t_k = t0 (1 + 2 e (1 - e^k) / (1 - e))
    t0 = math.sqrt(2 * h0 / G)
    for k in range(8):
        assert hits[k] == pytest.approx(t0 * (1 + 2 * e * (1 - e**k) / (1 - e)), abs=1e-9)
    # rest in finite time: the last impact is plastic; from then on |v| < 1e-9 for good
    speed = np.max(np.abs(np.asarray(run.velocities)[:, 1]), axis=1)
    moving = np.flatnonzero(speed >= 1e-9)
    rest = t[moving[-1] + 1]
    limit = t0 * (1 + e) / (1 - e)  # the sum of all flight times of the ideal ball
    assert limit < rest <= hits[-1] + 1e-3 and rest < limit + 0.01
    assert len(hits) <= math.ceil(math.log(1e-3 / (G * t0)) / math.log(e)) + 1
    assert run.contacts[-1] and run.max_penetration < 1e-9


# -- tunnelling ---------------------------------------------------------------------------------


def test_a_corner_sliding_onto_a_disc_is_an_impact():
    """From a soak failure: a heptagon moving at 2.7 m/s over a disc watches its edge against the
    disc; in step 26 the edge's line crosses the disc where the contact finder already sees the
    edge's corner, still clear, and the corner then sinks in (1.6e-4 m at the next step, when
    the impact search only confirmed the edge). The corner's impact must be located instead."""
    polygon = [
        [0.05967232253329676, 0.0],
        [0.04161815036294097, 0.04276348485431739],
        [-0.0060912486496402995, 0.05936061629065227],
        [-0.05284614219198848, 0.027714099876090716],
        [-0.05128275999025439, -0.03051007381668816],
        [0.0067714453006183966, -0.05928687548740049],
        [0.051755078161147876, -0.02970181747050625],
    ]
    data = {
        "scene": {"contact_tolerance": 5.152411507049318e-08,
                  "overlap_tolerance": 5.152411507049319e-11},
        "simulation": {"duration": 0.01618777589632709, "dt": 0.00034442076375164023},
        "body": [
            {"name": "floor", "fixed": True,
             "shape": {"type": "wall", "start": [-13.0, 0.0], "end": [13.0, 0.0]}},
            {"name": "disc", "shape": {"type": "disc", "radius": 0.10106429904618526},
             "density": 361.62968974795456, "position": [0.03789575907349052, 0.10339448872439364],
             "angle": 0.8940273505153415, "angular_velocity": -2.0412597932401244,
             "restitution": 1.0},
            {"name": "polygon", "shape": {"type": "polygon", "points": polygon},
             "density": 3330.1776099448934, "position": [0.03627526246533175, 0.26593147854887816],
             "angle": -0.5350777202266257, "velocity": [2.632135835599392, -0.8171114746980639],
             "angular_velocity": -1.7064250769128317, "restitution": 1.0},
        ],
    }  # fmt: skip
    scene = runtime.scene_from_dict(data, source="corner")
    run = runtime.simulate(scene)
    gaps = [g for poses in run.poses for g in scene.contacts(poses, tolerance=0.0).gap]
    assert min(gaps, default=0.0) > -1e-9  # was -1.56e-4 m
    assert len(run.impact_times) == 4  # the corner's impact is the new one


SOAK_REGRESSIONS = Path(__file__).parent / "data" / "soak_regressions.jsonl"


@pytest.mark.parametrize("line", SOAK_REGRESSIONS.read_text().splitlines(), ids=["turn", "slide"])
def test_scenes_the_soak_found_penetrating_do_not(line):
    """Random scenes (bench/soak.py, steps of 0.1 half-widths) where an impact at a feature
    the pair reached only within a step was missed: an arc meeting a polygon's edge while the
    watched contact was a corner (4.7e-5 m deep), a corner sliding onto a disc (1.6e-4 m).
    Checked as the soak does: exact gaps and sampled boundary points."""
    import strategies

    entry = json.loads(line)
    scene = runtime.scene_from_dict(entry["data"], source="soak")
    run = runtime.simulate(scene)
    depth, step, where = strategies.deepest_penetration(scene, run.poses, 0.0)
    assert depth < 1e-9, f"{where} by {depth:.3g} m at step {step} (was: {entry['found']})"


@pytest.mark.parametrize("dt", [1.0 / 60.0, 1e-3])
def test_disc_at_100_m_per_s_does_not_pass_through_a_1_cm_wall(dt):
    s = runtime.load_scene(SCENES / "wall_shot.toml")
    if dt > 0.01:
        assert 100.0 * dt > 100 * 0.01  # a step is 167 wall thicknesses
        assert not len(s.contacts(s.poses()))  # the plain contact search does not see the wall
        radii = np.array([b.shape.bounding_radius for b in s.bodies])
        moving = np.array([0.0 if b.fixed else 1.0 for b in s.bodies])
        margin = sweep.margins(s.velocities(), dt, radii, moving, G)
        assert len(Collision(s).swept(s.poses(), margin, None))  # the swept one does
    run = runtime.simulate(s, duration=0.5, dt=dt)
    x = np.asarray(run.poses)[:, 1, 0]
    assert np.all(x <= -0.025)
    assert run.impact_times == [pytest.approx(0.975 / 100.0, abs=1e-12)]
    assert run.velocities[-1][1][0] == pytest.approx(-50.0, abs=1e-9)
    assert run.max_penetration < 1e-9


def test_a_body_that_outruns_its_margin_is_searched_again(monkeypatch):
    """The safety net of runtime.collide.sweep: with margins forced to 0 (as if a contact force had
    thrown the disc), the trial step shows it moved farther, the search is widened and the
    impact still found."""
    monkeypatch.setattr(sweep, "margins", lambda v, h, radii, moving, g: np.zeros(len(radii)))
    s = runtime.load_scene(SCENES / "wall_shot.toml")
    run = runtime.simulate(s, duration=0.05, dt=1.0 / 60.0)
    assert run.impact_times == [pytest.approx(0.975 / 100.0, abs=1e-12)]
    assert np.all(np.asarray(run.poses)[:, 1, 0] <= -0.025)


# -- piles and stacks ---------------------------------------------------------------------------


def test_rounded_stack_stays_at_rest():
    s = runtime.load_scene(SCENES / "rounded_stack.toml")
    run = runtime.simulate(s, duration=0.5, dt=1e-3, record_every=10)
    assert run.max_penetration < 1e-9
    assert np.max(np.abs(run.velocities[-1])) < 1e-9
    assert len(run.contacts[-1]) == 10 and run.impact_times.size == 0


def test_disc_pile_comes_to_rest_without_penetration():
    """20 discs fall into the box, land (about 1400 located impacts) and are at rest (every
    |v|, |w| < 1e-9) from about 1.7 s on. bench/settle.py reports the same with timings."""
    s = runtime.load_scene(SCENES / "disc_pile.toml")
    run = runtime.simulate(s, duration=2.0, dt=1e-3, record_every=10)
    assert run.max_penetration < 1e-9
    assert len(run.impact_times) > 1000
    speeds = np.max(np.abs(np.asarray(run.velocities)), axis=(1, 2))
    t = np.asarray(run.t)
    assert np.all(speeds[t >= 1.9] < 1e-9)
    assert len(run.contacts[-1]) >= 35  # a pile, not a row of discs on the floor
    # impacts and presses only take energy out, resting contacts do no work: never a rise
    assert np.max(np.diff(run.energy)) < 1e-8  # J, of 965 J at the start


def test_warm_started_forces_equal_the_pivoting_solver():
    """The forces stage's warm start (the last clamped set tried first) gives the accelerations
    the pivoting solver gives, on a pile's rank-deficient A, as b changes from solve to solve."""
    s = runtime.load_scene(SCENES / "rounded_stack.toml")
    stepper = Stepper(s)
    q, v = s.poses(), s.velocities()
    contacts = s.contacts(q)
    assert len(contacts) >= 8
    rng = np.random.default_rng(1)
    for k in range(5):
        vk = (
            v
            + (0.0 if k == 0 else 1e-3 * k)
            * rng.normal(size=v.shape)
            * ~np.asarray(s.fixed)[:, None]
        )
        solution = stepper.contact_forces(contacts, q, vk)
        rows = stepper.evaluator.rows(contacts, q, vk)
        A = np.empty((len(contacts), len(contacts)))
        assembly.island_matrix(np.ascontiguousarray(rows.jacobian), rows.body1, rows.body2,
                               s.inverse_masses, np.asarray(s.fixed), 0, len(contacts), A)  # fmt: skip
        b = solution.free_rates
        reference = lcp.solve(A, b)
        f = solution.forces
        assert np.max(np.abs(A @ (f - reference))) < 1e-9 * np.max(np.abs(b))
        a = A @ f + b
        scale = np.max(np.abs(b))
        assert (
            np.all(f >= 0) and np.all(a >= -1e-9 * scale) and abs(f @ a) < 1e-9 * scale * np.sum(f)
        )


def test_an_impact_the_dense_solver_gives_up_on_is_resolved_by_the_general_one():
    """The final plastic pass of an impact in the landing 200-disc pile at t = 0.749 s
    (tests/runtime/data/impulse_213.npz: A of 213 touching contacts, rank 203, and their d'):
    the compiled dense solver gives up on it (the run failed there), the general solver's
    sparse path solves it. Checked by the conditions themselves: impulses >= 0, no contact
    left approaching beyond the creep speed, and none that takes an impulse left separating."""
    data = np.load(Path(__file__).parent / "data" / "impulse_213.npz")
    m = data["rate"].size
    A = np.zeros((m, m))
    for i in range(m):
        row = slice(data["indptr"][i], data["indptr"][i + 1])
        A[i, data["indices"][row]] = data["data"][row]
    rate, e = data["rate"], data["e"]
    assert np.linalg.matrix_rank(A) < m
    compiled = impulses.resolve_island(A, rate.copy(), e, 1e-3, 1e-12, np.zeros(m))
    assert compiled == -1
    out = impulses.resolve(A, rate, e, 1e-3, 1e-12)
    after = rate + A @ out.impulses
    assert np.allclose(after, out.gap_velocity, rtol=0, atol=1e-12)
    assert out.impulses.min() >= 0.0 and out.impulses.max() > 0.0
    assert after.min() >= -1e-12
    scale = np.abs(A).max() * out.impulses.max() + np.abs(rate).max()
    assert np.all(np.abs(after[out.impulses > 0]) <= 1e-9 * scale)
