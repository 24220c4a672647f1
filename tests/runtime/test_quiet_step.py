"""A quiet step (runtime.step.quiet: the event search skipped where it has nothing to find) is the
same step as the one the event search ends: scenes with bounces, simultaneous impacts, corners
that turn onto edges, fast bodies and piles step to the same states, bit for bit, with the check
on and off -- and the check does decide both ways, so the equality is not vacuous."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from stepping import states_and_impacts

import runtime
from bench.scenes import falling_pile
from generated import CASE_ID
from runtime.step import quiet
from runtime.step.classify import SEPARATING
from runtime.step.stepper import Stepper

SCENES = Path(__file__).resolve().parents[2] / "scenes"


def _run(scene, steps: int, dt: float, quiet: bool, monkeypatch) -> tuple:
    """States after every step, impact times, and how often the check said quiet / not."""
    decided = {True: 0, False: 0}
    check = Stepper._quiet

    def counted(self, *args):
        said = check(self, *args)
        decided[said] += 1
        return said and quiet

    monkeypatch.setattr(Stepper, "_quiet", counted)
    world = runtime.World(scene)
    assert world.stepper.compiled  # the check belongs to the compiled path
    states, impacts = states_and_impacts(world, steps, dt)
    monkeypatch.undo()
    return states, impacts, decided


CASES = [  # scene, steps, dt, what the check should say: always quiet, both, never quiet
    ("disc_in_bowl.toml", 300, 0.01, "quiet"),  # resting on an arc
    ("box_on_floor.toml", 300, 0.005, "quiet"),  # resting on its corners
    ("d_shape_rolling.toml", 300, 0.005, "quiet"),  # an arc rolling on a floor
    ("ball_drop.toml", 400, 0.005, "both"),  # bounces: located impacts, apexes
    ("disc_pile.toml", 300, 0.002, "both"),  # simultaneous impacts, a pile settling
    ("rounded_box_into_bowl.toml", 300, 0.005, "both"),  # arcs and corners landing in an arc
    ("wall_shot.toml", 30, 1 / 60, "both"),  # a fast body: 1.67 m a step at a 1 cm wall
    # steps so long that bodies move more than a quarter of their half width (fast): quiet
    # only where every feature pair no contact watches is clear (runtime.step.clearance)
    ("disc_in_bowl.toml", 60, 0.05, "quiet"),  # fast on an arc, its one feature pair
    ("disc_over_cylinder.toml", 30, 0.05, "both"),  # fast over a disc, lifting off, flying
    ("d_shape_rolling.toml", 40, 0.05, "both"),  # an arc and two corners rolling on a floor
    ("rounded_box_into_bowl.toml", 40, 0.05, "both"),  # corners near the bowl's arc
    ("ball_drop.toml", 40, 0.05, "both"),
]


@pytest.mark.parametrize(("name", "steps", "dt", "said"), CASES)
def test_shipped_scenes_step_the_same_with_and_without_the_quiet_check(
    name, steps, dt, said, monkeypatch
):
    scene = runtime.load_scene(SCENES / name)
    states, impacts, decided = _run(scene, steps, dt, True, monkeypatch)
    general, general_impacts, _ = _run(scene, steps, dt, False, monkeypatch)
    assert np.array_equal(states, general)
    assert np.array_equal(impacts, general_impacts)
    assert (decided[True] > 0) == (said != "never")  # the check was taken, or never
    assert (decided[False] > 0) == (said != "quiet")  # and declined, or never


def test_a_landing_pile_steps_the_same_with_and_without_the_quiet_check(monkeypatch):
    states, impacts, decided = _run(falling_pile(12), 300, 1e-3, True, monkeypatch)
    general, general_impacts, _ = _run(falling_pile(12), 300, 1e-3, False, monkeypatch)
    assert len(impacts) > 20  # impacts located within steps, in islands of several contacts
    assert decided[True] > 50 and decided[False] > 20
    assert np.array_equal(states, general)
    assert np.array_equal(impacts, general_impacts)


def test_the_check_declines_each_kind_of_trial_end_the_search_must_see():
    """The check on hand-made trial ends of a ball 1 cm above a floor, falling at 1 m/s: the
    start itself is quiet; an end that is NaN, 1 um through the floor (a move too small to
    make the ball fast), moving up again (a dip) or past the ball's margin is not."""
    world = runtime.World(runtime.load_scene(SCENES / "ball_drop.toml"))
    stepper = world.stepper
    ball = int(np.flatnonzero(~stepper.fixed)[0])
    q, v = world.poses.copy(), world.velocities.copy()
    q[ball, 1], v[ball, 1] = 0.11, -1.0  # radius 0.1: a gap of 1 cm
    frame, resting = stepper.settled_frame(q, v, 0.1, stepper.limits(0.1))
    assert len(frame.monitored) == 1 and abs(frame.rows.gap[0] - 0.01) < 1e-12  # the floor
    assert stepper._quiet(q, (q, v), frame, resting, 0.1)
    for change in ("nan", "through", "dip"):
        end, end_v = q.copy(), v.copy()
        if change == "nan":
            end[ball, 0] = np.nan
        elif change == "through":
            end[ball, 1] -= 0.01 + 1e-6
        else:
            end_v[ball, 1] = 1.0
        assert not stepper._quiet(q, (end, end_v), frame, resting, 0.1), change
    # at rest, steps of 0.01 s: a margin of g h^2 = 1 mm; 1 cm sideways outruns it, yet is
    # too little to make the ball fast (a quarter of its half width, 2.5 cm)
    v[:] = 0.0
    frame, resting = stepper.settled_frame(q, v, 0.01, stepper.limits(0.01))
    end = q.copy()
    end[ball, 0] += 0.01
    assert frame.margin[ball] < 0.01 < 0.025
    assert not stepper._quiet(q, (end, v), frame, resting, 0.01)


def _disc_in_bowl_past_a_peg():
    """A disc (r = 0.1) released at rest 0.9 rad up a fixed bowl (R = 1), and a fixed peg
    (r = 0.02) inside the bowl, placed where the disc's centre is after 0.15 s (its angle to
    leading order, 0.9 - g sin(0.9) t^2 / 1.8), 2 mm into the disc's path."""
    rho, start, peg_radius = 0.9, 0.9, 0.02
    there = start - 0.5 * 9.81 * math.sin(start) / rho * 0.15**2
    reach = rho - (0.1 + peg_radius - 0.002)
    bowl = {
        "type": "bowl",
        "radius": 1.0,
        "start_angle": -5 * math.pi / 6,
        "end_angle": -math.pi / 6,
    }
    bodies = [
        {"name": "bowl", "fixed": True, "shape": bowl},
        {"name": "disc", "shape": {"type": "disc", "radius": 0.1}, "density": 1000.0,
         "position": [rho * math.sin(start), -rho * math.cos(start)]},
        {"name": "peg", "fixed": True, "shape": {"type": "disc", "radius": peg_radius},
         "position": [reach * math.sin(there), -reach * math.cos(there)]},
    ]  # fmt: skip
    data = {"scene": {"name": "peg"}, "simulation": {"duration": 1.0, "dt": 0.2}, "body": bodies}
    return runtime.scene_from_dict(data, source="peg")


def test_a_body_with_a_resting_contact_is_not_taken_to_fly_free(monkeypatch):
    """The disc rests on the bowl, so its path is the bowl's arc, not the parabola of its start
    acceleration (a straight line along the bowl's tangent, from rest): over a step of 0.2 s the
    parabola passes the peg 2 mm clear while the arc runs into it. The check must leave that
    step to the search, which locates the impact within it; the runs with and without the
    check agree."""
    scene = _disc_in_bowl_past_a_peg()
    world = runtime.World(scene)
    stepper = world.stepper
    q, v = world.poses.copy(), world.velocities.copy()
    frame, resting = stepper.settled_frame(q, v, 0.2, stepper.limits(0.2))
    c = frame.contacts
    peg = int(np.flatnonzero((c.body1 == 1) & (c.body2 == 2) | (c.body1 == 2) & (c.body2 == 1))[0])
    a0 = resting.accelerations
    flight = quiet.least_gap_in_flight(
        peg, c.case, c.body1, c.body2, c.geometry, q, frame.velocities, a0, stepper.fixed, 0.2
    )
    assert 0.001 < flight < 0.003  # the parabola would pass the peg clear
    states, impacts, decided = _run(scene, 3, 0.2, True, monkeypatch)
    general, general_impacts, _ = _run(scene, 3, 0.2, False, monkeypatch)
    assert 0.1 < impacts[0] < 0.15  # the arc meets the peg within the first step
    assert np.array_equal(states, general)
    assert np.array_equal(impacts, general_impacts)


def test_a_graze_the_cubic_misses_is_left_to_the_search(monkeypatch):
    """A disc (r = 0.1) passing a fixed peg (r = 0.1) at 1 m/s, its centre's line 50 nm closer
    than touching, in steps of 0.02 s (not fast: 2 cm, under a quarter of the radius): the
    Hermite cubic through the gap's ends overestimates the gap at the closest approach by
    3/D^3 (h/2)^4 / 24 = 156 nm, so it stays above 0 while the disc overlaps the peg. The
    check must leave that step to the search, which checks the real gap and finds the impact
    where the line meets the peg: x = -sqrt(R^2 - D^2)."""
    depth, R = 5e-8, 0.2
    bodies = [
        {"name": "peg", "fixed": True, "shape": {"type": "disc", "radius": 0.1}},
        {"name": "disc", "shape": {"type": "disc", "radius": 0.1}, "density": 1000.0,
         "position": [-0.05, R - depth], "velocity": [1.0, 0.0]},
    ]  # fmt: skip
    data = {
        "scene": {"name": "graze", "gravity": [0.0, 0.0]},
        "simulation": {"duration": 0.1, "dt": 0.02},
        "body": bodies,
    }
    scene = runtime.scene_from_dict(data, source="graze")
    states, impacts, decided = _run(scene, 4, 0.02, True, monkeypatch)
    general, general_impacts, _ = _run(scene, 4, 0.02, False, monkeypatch)
    touch = 0.05 - math.sqrt(R**2 - (R - depth) ** 2)  # 0.0498586 s
    assert len(impacts) == 1 and abs(impacts[0] - (touch - 0.04)) < 1e-9  # in the third step
    assert decided[True] > 0  # the steps before and after are quiet
    assert np.array_equal(states, general)
    assert np.array_equal(impacts, general_impacts)


def _least(case: str, geometry, q0, v0, a0, fixed, h: float) -> float:
    """quiet.least_gap_in_flight of one contact of body 0 on body 1."""
    arrays = [np.array(x, dtype=float).reshape(2, 3) for x in (q0, v0, a0)]
    return quiet.least_gap_in_flight(
        0, np.array([CASE_ID[case]]), np.array([0]), np.array([1]),
        np.array([geometry], dtype=float), *arrays, np.array(fixed), h,
    )  # fmt: skip


def test_the_least_gap_in_free_flight_is_the_parabolas_least_distance():
    """Bodies with no resting contact move along parabolas; the least gap over a step is then
    known in closed form. Checked against the parabolas sampled at a million instants (numpy,
    apart from the code under test): a disc passing a fixed cylinder (R = 0.5) straight, and
    falling past it under gravity; a ball sinking onto a floor while its acceleration points up
    (the least gap inside the step, at t = 1/9.81 s); a concave arc (r2 < 0: a disc inside a
    ring of radius 1, whose farthest reach counts)."""
    t = np.linspace(0.0, 1.0, 1_000_001)

    def sampled(c0, v, a, h, gap):
        x = c0[0] + v[0] * t * h + 0.5 * a[0] * (t * h) ** 2
        y = c0[1] + v[1] * t * h + 0.5 * a[1] * (t * h) ** 2
        return gap(x, y).min()

    cylinder = [0.0, 0.0, 0.1, 0.0, 0.0, 0.5, 0.0]  # disc r = 0.1 on a disc r = 0.5
    for c0, v, a, h in [
        ((-1.0, 0.65), (1.0, 0.0), (0.0, 0.0), 2.0),  # closest at t = 1: gap 0.05
        ((-1.0, 0.65), (1.0, 0.0), (0.0, 0.0), 0.5),  # closest at the end
        ((-0.3, 0.9), (1.5, 0.4), (0.0, -9.81), 0.3),
    ]:
        want = sampled(c0, v, a, h, lambda x, y: np.hypot(x, y) - 0.6)
        got = _least("circle_circle", cylinder, [*c0, 0.0, 0, 0, 0], [*v, 3.0, 0, 0, 0],
                     [*a, 0.0, 0, 0, 0], [False, True], h)  # fmt: skip
        assert got == pytest.approx(want, abs=1e-11)
    assert _least("circle_circle", cylinder, [-1.0, 0.65, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0],
                  [0] * 6, [False, True], 2.0) == pytest.approx(0.05, abs=1e-11)  # fmt: skip
    floor = [0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 1.0]  # r = 0.1 over the line y = 0, normal up
    got = _least("circle_edge", floor, [0.0, 0.2, 0, 0, 0, 0], [0.5, -1.0, 0, 0, 0, 0],
                 [0.0, 9.81, 0, 0, 0, 0], [False, True], 0.3)  # fmt: skip
    assert got == pytest.approx(0.1 - 1.0 / (2 * 9.81), abs=1e-11)
    ring = [0.0, 0.0, 0.1, 0.0, 0.0, -1.0, 0.0]  # inside a ring of radius 1
    want = sampled((0.2, -0.5), (0.8, -0.6), (0.0, -9.81), 0.2, lambda x, y: 0.9 - np.hypot(x, y))
    got = _least("circle_circle", ring, [0.2, -0.5, 0, 0, 0, 0],
                 [0.8, -0.6, 0, 0, 0, 0], [0.0, -9.81, 0, 0, 0, 0], [False, True], 0.2)  # fmt: skip
    assert got == pytest.approx(want, abs=1e-11)
    off_centre = [0.05, 0.0, 0.1, 0.0, 0.0, 0.5, 0.0]  # a circle that turns with its body
    assert _least("circle_circle", off_centre, [-1.0, 0.65, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0],
                  [0] * 6, [False, True], 1.0) == -np.inf  # fmt: skip


@pytest.mark.parametrize(
    ("turn", "expected"),
    [(0.25, False), (0.75, False), (1.0 + 1e-6, True), (-1e-6, True)],
)
def test_a_resting_contact_past_its_arcs_end_may_slide_off(turn, expected):
    """A disc (r = 0.1) on the top-right corner arc (centre (0.3, 0.3), radius 0.2, spanning
    0 to 90 degrees) of a fixed rounded box, at the start at 45 degrees: at the end its centre
    at ``turn`` x 90 degrees about the arc's centre -- within the span it stays on the arc,
    beyond either end it may have slid onto a side (clearance.may_slide_off); unmoved, never."""
    from runtime.step.clearance import sliding_off

    block = {"type": "rounded_rect", "width": 1.0, "height": 1.0, "corner_radius": 0.2}
    scene = runtime.scene_from_dict(
        {
            "body": [
                {"name": "block", "fixed": True, "shape": block},
                {
                    "name": "disc",
                    "shape": {"type": "disc", "radius": 0.1},
                    "mass": 1.0,
                    "position": [0.5, 0.6],
                },
            ]
        },
        source="corner",
    )

    def at(fraction):
        phi = fraction * math.pi / 2
        return np.array([[0, 0, 0], [0.3 + 0.3 * math.cos(phi), 0.3 + 0.3 * math.sin(phi), 0]])

    q0, q1 = at(0.5), at(turn)
    stepper = Stepper(scene)
    contacts = stepper.collision.finder.find(q0, 1e-9)
    assert [contacts.case_name(k) for k in range(len(contacts))] == ["circle_circle"]
    tables = stepper.collision.finder.tables
    switches = np.array([True, False])

    def slides(end):
        return bool(
            sliding_off(q0, end, stepper.radii, switches, np.array([0]), contacts.body1,
                        contacts.body2, contacts.feature, tables.rows, tables.body_start, 1e-9)[0]
        )  # fmt: skip

    assert slides(q1) == expected
    assert not slides(q0)


@pytest.mark.parametrize(("turn", "expected"), [(0.0, False), (0.5, False), (-0.5, False),
                                                (0.9, True), (-0.9, True)])  # fmt: skip
def test_a_resting_corner_turned_out_of_its_cone_may_slide_off(turn, expected):
    """A square (side 0.2) standing on its corner on top of a fixed cylinder (r = 0.5), the
    corner's normal cone (90 degrees) centred on the way down: turned about that corner by
    ``turn`` rad, the way to the cylinder's centre stays in the cone up to 45 degrees; beyond,
    a side next to the corner may meet the cylinder (clearance.may_slide_off)."""
    from runtime.step.clearance import sliding_off

    square = {"type": "polygon", "points": [[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]]}
    scene = runtime.scene_from_dict(
        {
            "body": [
                {"name": "cylinder", "fixed": True, "shape": {"type": "disc", "radius": 0.5},
                 "position": [0.0, 0.0]},
                {"name": "square", "shape": square, "mass": 1.0, "position": [0.0, 1.0]},
            ]
        },
        source="corner on a cylinder",
    )  # fmt: skip
    half = 0.1 * math.sqrt(2)

    def at(extra):
        th = math.pi / 4 + extra  # corner 0 at (0, -half) turned by extra about the corner
        return np.array([[0, 0, 0], [-half * math.sin(extra), 0.5 + half * math.cos(extra), th]])

    q0 = at(0.0)
    stepper = Stepper(scene)
    contacts = stepper.collision.finder.find(q0, 1e-9)
    assert [contacts.case_name(k) for k in range(len(contacts))] == ["vertex_circle"]
    tables = stepper.collision.finder.tables
    moved = at(turn)
    moved[1, :2] += 1e-6 * (turn == 0.0)  # (unturned: moved along, still in its cone)
    found = sliding_off(q0, moved, stepper.radii, np.array([False, True]), np.array([0]),
                        contacts.body1, contacts.body2, contacts.feature, tables.rows,
                        tables.body_start, 1e-9)  # fmt: skip
    assert bool(found[0]) == expected


@pytest.mark.parametrize(("tilt", "expected"), [(2e-8, False), (1e-8, False), (0.0, False),
                                                (-1e-8, True), (-0.1, True)])  # fmt: skip
def test_a_resting_smooth_end_turned_back_onto_its_arc_may_slide_off(tilt, expected):
    """A rounded box (1 x 0.4, corner radius 0.1) on a floor, tilted 1e-8 rad so that its left
    corner arc touches and the right end of its flat bottom (a smooth end, where the side runs
    into the arc) is 8e-9 m above the floor, facing it from beyond its arc: a contact of that
    end. Turned to ``tilt``: tilted the other way by more than clearance.LEAVE (2e-9 rad), the
    floor faces the right arc, which takes the contact (clearance.may_slide_off); flat or still
    tilted left, the end holds."""
    from runtime.step.clearance import sliding_off

    box = {"type": "rounded_rect", "width": 1.0, "height": 0.4, "corner_radius": 0.1}
    scene = runtime.scene_from_dict(
        {
            "body": [
                {"name": "floor", "fixed": True,
                 "shape": {"type": "wall", "start": [-5.0, 0.0], "end": [5.0, 0.0]}},
                {"name": "box", "shape": box, "mass": 1.0, "position": [0.0, 0.2]},
            ]
        },
        source="rounded box",
    )  # fmt: skip
    stepper = Stepper(scene)
    finder, tables = stepper.collision.finder, stepper.collision.finder.tables

    def at(theta):  # the box tilted by theta, its lowest point on the floor
        q = np.array([[0.0, 0.0, 0.0], [0.0, 0.2, theta]])
        q[1, 1] -= min(finder.find(q, 1.0).gap)
        return q

    q0 = at(1e-8)
    contacts = finder.find(q0, 1e-7)
    assert sorted(contacts.case_name(k) for k in range(len(contacts))) == [
        "circle_edge", "vertex_edge"]  # fmt: skip
    end = int(np.flatnonzero(contacts.feature[:, 0] == 2)[0])  # the smooth end's contact
    assert contacts.point[end, 0] > 0 and contacts.gap[end] == pytest.approx(8e-9, rel=1e-3)
    found = sliding_off(q0, at(tilt), stepper.radii, np.array([False, True]), np.array([end]),
                        contacts.body1, contacts.body2, contacts.feature, tables.rows,
                        tables.body_start, 1e-9)  # fmt: skip
    assert bool(found[0]) == expected


@pytest.mark.parametrize(("turn", "quiet"), [(-1.0, True), (1.0, False)])
def test_a_contact_moving_apart_past_its_arcs_end_is_not_quiet(turn, quiet):
    """A disc (r = 0.1) touching the top-right corner arc of a fixed rounded box 5e-5 rad
    short of its end (90 degrees), moving apart at 0.05 m/s and along the arc at 0.03 m/s:
    a step of 1 ms back along the arc is quiet; one on past its end (by 5e-5 rad, over the
    box's top) is not -- a contact moving apart is watched on its feature's whole circle, and
    beyond the arc's end the side is unwatched (in a mixed pile a box's corner lifting off a
    rounded box's arc ran on past its end, 1.3e-6 m into the side)."""
    block = {"type": "rounded_rect", "width": 1.0, "height": 1.0, "corner_radius": 0.2}
    scene = runtime.scene_from_dict(
        {"scene": {"gravity": [0.0, 0.0]}, "body": [
            {"name": "block", "fixed": True, "shape": block},
            {"name": "disc", "shape": {"type": "disc", "radius": 0.1}, "mass": 1.0,
             "position": [0.3, 0.6]},
        ]},
        source="corner",
    )  # fmt: skip
    world = runtime.World(scene)
    stepper, h = world.stepper, 1e-3
    phi = math.pi / 2 - 5e-5
    radial, along = (
        np.array([math.cos(phi), math.sin(phi)]),
        np.array([-math.sin(phi), math.cos(phi)]),
    )
    q, v = np.zeros((2, 3)), np.zeros((2, 3))
    q[1, :2] = (0.3, 0.3) + 0.3 * radial
    v[1, :2] = 0.05 * radial + turn * 0.03 * along
    frame, resting = stepper.settled_frame(q, v, h, stepper.limits(h))
    assert [frame.contacts.case_name(k) for k in range(len(frame.contacts))] == ["circle_circle"]
    assert frame.modes.tolist() == [SEPARATING]
    end = q.copy()
    end[1, :2] += h * v[1, :2]
    assert stepper._quiet(q, (end, v), frame, resting, h) == quiet
