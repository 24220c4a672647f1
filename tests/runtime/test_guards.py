"""The guards of runtime/guards.py: a spoilt run stops with a SimulationError.

Why: a too-large step fails silently otherwise (bodies sink in or pass through walls, energy
grows). The messages and the bad-input catalogue are in test_bad_input.py; here the geometry of
the tunnelling check against exact answers, and a disc made to pass through a wall.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import runtime
from runtime.collide import sweep
from runtime.step import pair_scan
from runtime.step.guards import FixedEdges

SCENES = Path(__file__).resolve().parents[2] / "scenes"


def _scene(shape: dict, position=(0.0, 0.0), angle=0.0) -> runtime.Scene:
    return runtime.scene_from_dict(
        {
            "body": [
                {"name": "fixed", "fixed": True, "shape": shape, "position": list(position),
                 "angle": angle},
                {"name": "disc", "shape": {"type": "disc", "radius": 0.01}, "density": 1.0,
                 "position": [5.0, 5.0]},
            ]
        },
        source="guards",
    )  # fmt: skip


def test_paths_across_a_turned_wall():
    """A wall from (-1, 0) to (1, 0) turned by 30 degrees about (2, 1): a path crosses it iff
    it passes the line between the wall's ends (closed-form intersection of two lines)."""
    wall = _scene(
        {"type": "wall", "start": [-1.0, 0.0], "end": [1.0, 0.0]}, (2.0, 1.0), math.pi / 6
    )
    edges = FixedEdges(wall)
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    rng = np.random.default_rng(1)
    p0, p1 = rng.uniform(-1, 5, (400, 2)), rng.uniform(-1, 5, (400, 2))
    for a, b in zip(p0, p1, strict=True):
        # the path in the wall's frame: crossing y = 0 at |x| <= 1
        la = np.array([[c, s], [-s, c]]) @ (a - [2.0, 1.0])
        lb = np.array([[c, s], [-s, c]]) @ (b - [2.0, 1.0])
        expected = la[1] * lb[1] < 0 and abs(la[0] + (lb[0] - la[0]) * la[1] / (la[1] - lb[1])) <= 1
        found = edges.crossing(a[None], b[None])
        assert (found == (0, 0)) if expected else found is None


def test_paths_across_a_bowl_arc_but_not_its_open_top():
    """The shipped bowl (radius 1, centre (0, 0), arc from -150 to -30 degrees): a path from the
    centre crosses the arc iff it leaves the circle inside the arc's span."""
    scene = runtime.load_scene(SCENES / "disc_in_bowl.toml")
    edges = FixedEdges(scene)
    bowl = scene.index("bowl")
    for degrees in range(-180, 180, 7):
        a = math.radians(degrees + 0.5)
        end = 1.5 * np.array([[math.cos(a), math.sin(a)]])
        expected = -150 <= degrees + 0.5 <= -30
        found = edges.crossing(np.zeros((1, 2)), end)
        assert (found == (0, bowl)) if expected else found is None, degrees
        assert edges.crossing(np.zeros((1, 2)), 0.5 * end) is None  # stays inside the circle


def test_a_disc_made_to_pass_through_a_wall_is_stopped(monkeypatch):
    """With the swept contact search switched off (and the search for fast pairs that no
    contact watches), the disc of wall_shot (100 m/s, dt = 1/60 s) jumps over the 1 cm wall in
    one step; the guard names it and keeps the state before."""
    monkeypatch.setattr(sweep, "margins", lambda v, h, radii, moving, g: np.zeros(len(radii)))
    monkeypatch.setattr(sweep, "outran", lambda *args: False)
    monkeypatch.setattr(pair_scan, "unwatched_meetings", lambda *args: {})
    scene = runtime.load_scene(SCENES / "wall_shot.toml")
    with pytest.raises(runtime.SimulationError) as info:
        runtime.simulate(scene, duration=0.05, dt=1.0 / 60.0)
    assert str(info.value).startswith(
        "step 0 at t = 0 s moved the centre of mass of disc through wall (it tunnelled)"
    )
    np.testing.assert_array_equal(info.value.state[0], scene.poses())
    off = runtime.Guards(penetration=None)
    run = runtime.simulate(scene, duration=0.05, dt=1.0 / 60.0, guards=off)
    assert run.poses[-1][scene.index("disc"), 0] > 1.0  # without the guard: through, silently


def test_a_disc_past_the_swept_search_is_still_stopped_at_the_wall(monkeypatch):
    """The swept contact search switched off, but not the search for fast pairs that no contact
    watches: the disc of wall_shot (100 m/s, dt = 1/60 s, 1.7 m a step) is not seen next to
    the wall at any step's start, yet its first touch is located and it bounces off the 1 cm
    wall at t = 0.975 m / 100 m/s (restitution 0.5: -50 m/s after), never through it."""
    monkeypatch.setattr(sweep, "margins", lambda v, h, radii, moving, g: np.zeros(len(radii)))
    monkeypatch.setattr(sweep, "outran", lambda *args: False)
    scene = runtime.load_scene(SCENES / "wall_shot.toml")
    run = runtime.simulate(scene, duration=0.05, dt=1.0 / 60.0)
    disc = scene.index("disc")
    assert run.impact_times.tolist() == pytest.approx([0.975 / 100.0], abs=1e-12)
    assert run.velocities[-1][disc, 0] == pytest.approx(-50.0, rel=1e-12)
    assert run.max_penetration <= 1e-9
