"""Time stepping (method "time-stepping", runtime.step.time_stepping) against references written
here apart from the engine: the exact recurrence of semi-implicit Euler in free fall and on a
frictionless slope, momentum and Newton's law at a collision, the weight a resting pile puts on
its floor, and the overlap bound after every step.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import runtime
from bench.scenes import falling_pile
from runtime import settings
from runtime.io.scene_file import scene_from_dict

G = 9.81
H = 1e-3  # s
TS = "time-stepping"


def _scene(bodies: list[dict], gravity=(0.0, -G)) -> runtime.Scene:
    data = {
        "scene": {"name": "ts", "gravity": list(gravity)},
        "simulation": {"duration": 1.0, "dt": H, "method": TS},
        "body": bodies,
    }
    return scene_from_dict(data)


FLOOR = {"name": "floor", "fixed": True, "shape": {"type": "wall", "start": [-2, 0], "end": [2, 0]}}


def _disc(name, x, y, vx=0.0, vy=0.0, r=0.1, mass=1.0, e=0.0) -> dict:
    return {"name": name, "shape": {"type": "disc", "radius": r}, "mass": mass,
            "position": [x, y], "velocity": [vx, vy], "restitution": e}  # fmt: skip


def test_a_dropped_disc_falls_by_the_euler_recurrence_then_rests_with_its_weight():
    """Semi-implicit Euler from rest: v_n = -g h n, y_n = y_0 - g h^2 n (n + 1) / 2, exactly
    (to rounding) until the step that reaches the floor; that step stops it at the floor
    (speculative contact, plastic); then it rests at a gap within the projection tolerance,
    at rest, with a contact force of m g."""
    y0 = 0.1 + 0.05
    world = runtime.World(_scene([FLOOR, _disc("d", 0.0, y0)]))
    ball = world.index("d")
    n = 0
    while True:
        world.step(H)
        n += 1
        y_exact = y0 - G * H * H * n * (n + 1) / 2
        if y_exact - 0.1 < 0.0:
            break
        assert world.poses[ball, 1] == pytest.approx(y_exact, abs=1e-14)
        assert world.velocities[ball, 1] == pytest.approx(-G * H * n, abs=1e-13)
    assert n == math.ceil(math.sqrt(2 * 0.05 / (G * H * H) + 0.25) - 0.5)  # the first step below
    assert abs(world.poses[ball, 1] - 0.1) <= 1e-12  # stopped at the floor
    for _ in range(200):
        report = world.step(H)
    gap = world.poses[ball, 1] - 0.1
    assert -settings.PROJECTION_TOL * settings.TOUCH <= gap <= 1e-12
    assert np.abs(world.velocities[ball]).max() <= 1e-12
    assert report.forces.sum() == pytest.approx(1.0 * G, rel=1e-9)


def test_a_box_slides_down_a_frictionless_slope_by_the_recurrence_and_stays_on_it():
    """A box flat on a slope at 30 degrees, at rest: along the slope v_n = g sin(th) h n and
    s_n = g sin(th) h^2 n (n + 1) / 2 exactly (the normal impulses are normal to it); its gap
    stays within 1e-11 m (rounding: it has no force to drift by) and its angle at the slope's."""
    th = math.radians(30.0)
    t, nrm = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
    w, h = 0.2, 0.1
    centre = 0.5 * t + (h / 2) * nrm
    slope = {"name": "slope", "fixed": True, "shape": {"type": "wall", "start": (-2 * t).tolist(),
             "end": (2 * t).tolist()}}  # fmt: skip
    box = {"name": "box", "shape": {"type": "polygon", "points": [[-w / 2, -h / 2], [w / 2, -h / 2],
           [w / 2, h / 2], [-w / 2, h / 2]]}, "density": 100.0, "position": centre.tolist(),
           "angle": th}  # fmt: skip
    world = runtime.World(_scene([slope, box]))
    b = world.index("box")
    a = G * math.sin(th)
    for n in range(1, 301):
        world.step(H)
        s = float((world.poses[b, :2] - centre) @ t)
        assert s == pytest.approx(-a * H * H * n * (n + 1) / 2, rel=1e-11, abs=1e-15)
        assert abs(float((world.poses[b, :2] - centre) @ nrm)) <= 1e-11
        assert abs(world.poses[b, 2] - th) <= 1e-12
    assert float(world.velocities[b, :2] @ t) == pytest.approx(-a * H * 300, rel=1e-12)


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_a_head_on_collision_keeps_momentum_and_newtons_law(e):
    """Two discs (1 and 3 kg) meeting head on without gravity: momentum is kept to rounding,
    and after the collision the relative velocity is -e times that before it (e = 0: one
    common velocity)."""
    m1, m2, v1, v2 = 1.0, 3.0, 2.0, -1.0
    scene = _scene(
        [_disc("a", -0.5, 0.0, vx=v1, mass=m1, e=e), _disc("b", 0.5, 0.0, vx=v2, mass=m2, e=e)],
        gravity=(0.0, 0.0),
    )
    world = runtime.World(scene)
    p0 = m1 * v1 + m2 * v2
    for _ in range(500):
        world.step(H)
        va, vb = world.velocities[0, 0], world.velocities[1, 0]
        assert m1 * va + m2 * vb == pytest.approx(p0, abs=1e-12)
    assert vb - va == pytest.approx(-e * (v2 - v1), abs=1e-12)
    assert np.abs(world.velocities[:, 1:]).max() == 0.0
    gap = world.poses[1, 0] - world.poses[0, 0] - 0.2
    assert gap >= -settings.PROJECTION_TOL * settings.TOUCH


def test_a_bounce_returns_e_times_the_approach_speed():
    """A disc (e = 0.5) falling onto the floor: the step of the bounce leaves it moving up at
    exactly e times its speed down (the speed after that step's gravity, as the impulse sees it)."""
    world = runtime.World(_scene([FLOOR, _disc("d", 0.0, 0.2, e=0.5)]))
    ball = world.index("d")
    before = 0.0
    for _ in range(400):
        down = world.velocities[ball, 1] - G * H
        world.step(H)
        if world.velocities[ball, 1] > 0.0:
            before = down
            break
    assert before == pytest.approx(-math.sqrt(2 * G * 0.1), rel=0.01)
    assert world.velocities[ball, 1] == pytest.approx(-0.5 * before, rel=1e-12)


def test_a_falling_pile_settles_without_overlap_and_its_floor_carries_its_weight():
    """20 discs of 1 kg falling into a box, 1 s: after every step no contact overlaps deeper
    than the projection tolerance (the contact finder asked at every record), the pile ends at
    rest, and the contacts on the box carry the weight 20 m g."""
    scene = falling_pile(20)
    run = runtime.simulate(scene, duration=1.0, dt=H, method=TS)
    limit = settings.PROJECTION_TOL * settings.TOUCH
    assert run.min_gap.min() >= -limit
    assert len(run.min_gap) == 1001
    moving = ~np.asarray(scene.fixed)
    assert 0.5 * np.sum(run.velocities[-1][moving, :2] ** 2) <= 1e-12
    box = scene.index("box")
    world = runtime.World(scene, TS)
    world.poses, world.velocities = run.poses[-1].copy(), run.velocities[-1].copy()
    report = world.step(H)
    contacts = report.frame.contacts.take(report.recorded)
    on_box = (contacts.body1 == box) | (contacts.body2 == box)
    normal_y = report.frame.rows.take(report.recorded).jacobian[:, 1]
    lift = np.sum(report.forces[on_box] * np.abs(normal_y[on_box]))
    assert lift == pytest.approx(20 * G, rel=1e-6)


def test_the_landing_pile_whose_unregularised_solve_failed_runs_on():
    """The landing 50-disc pile (seed 7) through t = 0.7 s: without the impulse LCP's
    regularisation its step 630 ended "infeasible" (tests/runtime/test_island_impulses.py keeps
    that problem); now every step solves, with no overlap beyond the tolerance."""
    run = runtime.simulate(falling_pile(50, seed=7), duration=0.7, dt=H, method=TS)
    assert run.min_gap.min() >= -settings.PROJECTION_TOL * settings.TOUCH


def test_reruns_are_identical():
    scene = falling_pile(12)
    a = runtime.simulate(scene, duration=0.4, dt=H, method=TS)
    b = runtime.simulate(scene, duration=0.4, dt=H, method=TS)
    assert np.array_equal(a.poses, b.poses) and np.array_equal(a.velocities, b.velocities)


@pytest.mark.parametrize(
    "change, named",
    [({"friction": 0.5}, "friction"), ({}, "stabilisation")],
)
def test_what_it_does_not_model_is_refused_by_name(change, named):
    data = {
        "scene": {"name": "ts"},
        "simulation": {"duration": 1.0, "dt": H, "method": TS,
                       "stabilisation": named == "stabilisation"},
        "body": [{**FLOOR, **change}, {**_disc("d", 0.0, 0.2), **change}],
    }  # fmt: skip
    with pytest.raises(ValueError, match=named):
        runtime.World(scene_from_dict(data))


def test_a_disc_knocked_farther_than_its_margin_does_not_end_in_the_wall():
    """A 100 kg disc at 20 m/s pushes a 1 kg disc resting 15 mm from a wall, without gravity:
    the light disc's margin is 0 (it rests at the step's start), so the wall is not among that
    step's contacts, and the push moves it ~20 mm, into the wall. The overlap check cannot
    rely on the step's contacts then: the disc ends every step out of the wall and out of the
    heavy disc (within the projection's tolerance), and against the wall at the end."""
    wall = {"name": "wall", "fixed": True,
            "shape": {"type": "wall", "start": [0.115, -1.0], "end": [0.115, 1.0]}}  # fmt: skip
    heavy = _disc("heavy", -0.3, 0.0, vx=20.0, mass=100.0)
    world = runtime.World(_scene([wall, heavy, _disc("light", 0.0, 0.0)], gravity=(0.0, 0.0)))
    a, b = world.index("heavy"), world.index("light")
    tolerance = settings.PROJECTION_TOL * settings.TOUCH
    far = []  # the light disc's distance to the wall before each step
    for _ in range(10):
        far.append(0.115 - (world.poses[b, 0] + 0.1))
        world.step(H)
        gap = 0.115 - (world.poses[b, 0] + 0.1)
        assert gap >= -tolerance
        assert world.poses[b, 0] - world.poses[a, 0] >= 0.2 - tolerance
        if gap <= 1e-12:
            break
    assert far[-1] > 0.01  # it reached the wall from 1 cm or more in one step
    assert abs(gap) <= tolerance
