"""Reflex joins of straight edges (runtime.collide.junctions): a corner in a V of two walls.

A box sliding down one wall of a V into its vertex used to reach the other wall only at that
wall's end, unwatched, and a corner pressed into the vertex left both walls' spans and sank
through (a box at 30 degrees: "left b/right overlapping by 0.0089 m" at t = 0.73 s). References
written here apart from the engine: the closed-form arrival of a frictionless slide, and the
plastic impact at the vertex as the projection of the velocity, in the kinetic-energy metric,
onto the velocities that do not enter either wall (hand-written contact rows, one active).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import runtime
from runtime.collide.contact_set import VERTEX
from runtime.collide.contacts import finder_for
from runtime.collide.features import C_WIDTH, HIDDEN, S_JOIN_END, S_JOIN_START, features
from runtime.io.scene_file import scene_from_dict

G = 9.81
W, H, DENSITY = 0.1, 0.08, 500.0  # the box
SLIDE = 0.3  # m up the right wall from the vertex to the box's lower corner, at rest


def _walls(slope: float, end_vertices: bool = False) -> list[dict]:
    c, s = math.cos(slope), math.sin(slope)
    return [
        {"name": "left", "fixed": True,
         "shape": {"type": "wall", "start": [-c, s], "end": [0.0, 0.0], "end_vertices": end_vertices}},
        {"name": "right", "fixed": True,
         "shape": {"type": "wall", "start": [0.0, 0.0], "end": [c, s], "end_vertices": end_vertices}},
    ]  # fmt: skip


def _box_on_right_wall(slope: float, along: float, speed: float = 0.0, **walls) -> runtime.Scene:
    """The box flat on the right wall, its lower corner ``along`` up it, sliding down at
    ``speed``."""
    t = np.array([math.cos(slope), math.sin(slope)])
    n = np.array([-t[1], t[0]])
    centre = (along + W / 2) * t + (H / 2) * n
    box = {
        "name": "b",
        "shape": {"type": "polygon", "points": [[-W / 2, -H / 2], [W / 2, -H / 2],
                                                [W / 2, H / 2], [-W / 2, H / 2]]},
        "density": DENSITY, "position": centre.tolist(), "angle": slope,
        "velocity": (-speed * t).tolist(),
    }  # fmt: skip
    data = {
        "scene": {"name": "box_in_v"},
        "simulation": {"duration": 1.0, "dt": 1e-3, "method": "rk4"},
        "body": [*_walls(slope, **walls), box],
    }
    return scene_from_dict(data)


def _deepest(world) -> float:
    found = world.stepper.collision.swept(world.poses, np.zeros(len(world.poses)), None)
    return float(-found.gap.min()) if len(found) else 0.0


def test_box_slides_into_the_vertex_at_the_closed_form_instant():
    slope = math.radians(30.0)
    world = runtime.World(_box_on_right_wall(slope, SLIDE))
    impacts: list[float] = []
    while not impacts:
        start = world.t
        impacts = [start + t for t in world.step(1e-3).impact_times]
    arrival = math.sqrt(2.0 * SLIDE / (G * math.sin(slope)))  # frictionless: a = g sin(slope)
    assert impacts[0] == pytest.approx(arrival, abs=1e-12)
    assert _deepest(world) <= 1e-12


@pytest.mark.parametrize("end_vertices", [False, True])
def test_box_tips_over_the_vertex_and_never_sinks(end_vertices):
    """1.5 s of sliding, tipping over the vertex onto the left wall, sliding back: the run used
    to stop with the box 8.9 mm into a wall; with end vertices at the vertex, a contact force
    solve failed ("infeasible"). The vertices at a reflex join are hidden, as in one chain."""
    world = runtime.World(_box_on_right_wall(math.radians(30.0), SLIDE, end_vertices=end_vertices))
    deepest = 0.0
    for _ in range(1500):
        world.step(1e-3)
        deepest = max(deepest, _deepest(world))
    assert deepest <= 1e-9
    if end_vertices:
        plain = runtime.World(_box_on_right_wall(math.radians(30.0), SLIDE))
        for _ in range(1500):
            plain.step(1e-3)
        np.testing.assert_array_equal(world.poses, plain.poses)


@pytest.mark.parametrize("slope", [40.0, 45.0])
def test_a_half_disc_tipping_in_the_vertex_keeps_its_arc_out_of_the_wall(slope):
    """A half disc sliding flat down one wall into the vertex tips about its corner there (the
    plastic impact lifts it off the wall it slid on). Its arc leaves that corner square to its
    flat side; tipping, the corner's direction to the other wall turns out of its normal cone
    onto the arc, which went into the wall unlocated: 7e-7 m at 40 degrees, 2.2e-5 m at 45 (the
    arc's end tangent to the wall from the start, its contact the corner's duplicate in d' and
    dropped). That instant is now located (runtime.step.clearance, the cone's room)."""
    a = math.radians(slope)
    t = np.array([math.cos(a), math.sin(a)])
    half = {"name": "b", "shape": {"type": "half_disc", "radius": 0.06}, "density": DENSITY,
            "position": ((SLIDE + 0.06) * t).tolist(), "angle": a}  # fmt: skip
    scene = scene_from_dict({"body": [*_walls(a), half]})
    world = runtime.World(scene)
    deepest = 0.0
    for _ in range(1500):
        world.step(1e-3)
        deepest = max(deepest, _deepest(world))
    assert deepest <= 1e-9


def _projected(slope: float, speed: float) -> np.ndarray:
    """Velocity (vx, vy, omega) after a plastic frictionless impact of the box's lower corner at
    the vertex: v0 minus M^-1 a lambda with a v = 0 for the left wall's row a, the only one
    active (the right wall's two rows then move apart, checked)."""
    t = np.array([math.cos(slope), math.sin(slope)])
    n_right = np.array([-t[1], t[0]])
    n_left = np.array([math.sin(slope), math.cos(slope)])
    mass = DENSITY * W * H
    inertia = mass * (W * W + H * H) / 12.0
    centre = (W / 2) * t + (H / 2) * n_right

    def row(p, n):
        r = p - centre
        return np.array([n[0], n[1], r[0] * n[1] - r[1] * n[0]])

    a = row(np.zeros(2), n_left)
    right = [row(np.zeros(2), n_right), row(W * t, n_right)]
    inverse = np.diag([1 / mass, 1 / mass, 1 / inertia])
    v0 = np.array([*(-speed * t), 0.0])
    v = v0 - inverse @ a * (a @ v0) / (a @ inverse @ a)
    assert all(r @ v > 1e-3 for r in right)
    return v


def test_plastic_impact_at_the_vertex_tips_the_box():
    slope, speed, dt = math.radians(30.0), 1.5, 1e-12
    world = runtime.World(_box_on_right_wall(slope, 0.0, speed))
    world.step(dt)  # the impact at t = 0, then 1 ps of gravity and the corner's contact force
    expected = _projected(slope, speed) + np.array([0.0, -G * dt, 0.0])
    np.testing.assert_allclose(world.velocities[-1], expected, rtol=0, atol=1e-9)


def test_fixed_walls_meeting_are_joined_and_their_end_vertices_hidden():
    scene = _box_on_right_wall(math.radians(30.0), SLIDE, end_vertices=True)
    shapes = [b.shape for b in scene.bodies]
    finder = finder_for(shapes, scene.fixed)
    finder.find(scene.poses())
    rows, start = finder.tables.rows, finder.tables.body_start
    for k in (0, 1):  # each wall's one segment joined at the vertex, its other end free
        segment = rows[start[k, 2] : start[k + 1, 2]]
        assert sorted(segment[0, [S_JOIN_START, S_JOIN_END]]) == pytest.approx([0, 2 * math.pi / 3])
        corners = rows[start[k, 0] : start[k + 1, 0]]
        assert list(corners[:, C_WIDTH] == HIDDEN).count(True) == 1  # the end vertex at (0, 0)
    # moved apart, the walls no longer meet: the tables are the walls' own again
    poses = scene.poses()
    poses[1, 0] += 0.01
    finder.find(poses)
    assert not np.any(rows[:, S_JOIN_START : S_JOIN_END + 1])
    assert not np.any(rows[: start[-1, 0], C_WIDTH] == HIDDEN)  # (the corners' rows)


def test_a_convex_join_and_a_chain():
    """Walls meeting as a roof (the vertex pointing into the free space) are no reflex join; a
    container's inner corners are (box_walls: pi / 2)."""
    roof = [
        {"name": "a", "fixed": True, "shape": {"type": "wall", "start": [-1.0, 0.0], "end": [0.0, 0.5]}},
        {"name": "b", "fixed": True, "shape": {"type": "wall", "start": [0.0, 0.5], "end": [1.0, 0.0]}},
        {"name": "disc", "shape": {"type": "disc", "radius": 0.1}, "density": 1.0,
         "position": [0.0, 1.0]},
    ]  # fmt: skip
    scene = scene_from_dict({"body": roof})
    finder = finder_for([b.shape for b in scene.bodies], scene.fixed)
    finder.find(scene.poses())
    assert not np.any(finder.tables.rows[:, S_JOIN_START : S_JOIN_END + 1])
    box = features(runtime.shapes.box_walls(1.0, 0.5)).tables[2]  # right side, floor, left side
    np.testing.assert_allclose(box[:, S_JOIN_START], [0.0, math.pi / 2, math.pi / 2], atol=1e-12)
    np.testing.assert_allclose(box[:, S_JOIN_END], [math.pi / 2, math.pi / 2, 0.0], atol=1e-12)


def test_only_corners_near_the_vertex_are_held_beyond_a_wall_end():
    """The box's corner pressed straight down from the vertex, behind both lines and outside
    both spans, is held by both walls; 1 cm down, far deeper than the contact tolerance, by
    neither (only corners near the join are held there)."""
    slope = math.radians(30.0)
    scene = _box_on_right_wall(slope, 0.0)
    finder = finder_for([b.shape for b in scene.bodies], scene.fixed)
    for depth, walls in ((1e-7, {0, 1}), (0.01, set())):
        poses = scene.poses()
        poses[2, 1] -= depth
        found = finder.find(poses, 1e-4)
        corner = (found.body1 == 2) & (found.feature[:, 0] == VERTEX) & (found.feature[:, 1] == 0)
        assert set(found.body2[corner].tolist()) == walls
        if walls:  # each the corner's distance behind that wall's line
            gaps = found.gap[corner]
            np.testing.assert_allclose(gaps, -depth * math.cos(slope), rtol=1e-6)
