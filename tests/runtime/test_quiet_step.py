"""A quiet step (runtime.step.quiet: the event search skipped where it has nothing to find) is the
same step as the one the event search ends: scenes with bounces, simultaneous impacts, corners
that turn onto edges, fast bodies and piles step to the same states, bit for bit, with the check
on and off -- and the check does decide both ways, so the equality is not vacuous."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from stepping import states_and_impacts

import runtime
from bench.scenes import falling_pile
from runtime.step.stepper import Stepper

SCENES = Path(__file__).resolve().parents[2] / "scenes"


def _run(scene, steps: int, dt: float, quiet: bool, monkeypatch) -> tuple:
    """States after every step, impact times, and how often the check said quiet / not."""
    decided = {True: 0, False: 0}
    check = Stepper._quiet

    def counted(self, q, end, frame):
        said = check(self, q, end, frame)
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
    ("disc_over_cylinder.toml", 30, 0.05, "both"),  # fast over a disc, then flying off it
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
    frame, _ = stepper.settled_frame(q, v, 0.1, stepper.limits(0.1))
    assert len(frame.monitored) == 1 and abs(frame.rows.gap[0] - 0.01) < 1e-12  # the floor
    assert stepper._quiet(q, (q, v), frame)
    for change in ("nan", "through", "dip"):
        end, end_v = q.copy(), v.copy()
        if change == "nan":
            end[ball, 0] = np.nan
        elif change == "through":
            end[ball, 1] -= 0.01 + 1e-6
        else:
            end_v[ball, 1] = 1.0
        assert not stepper._quiet(q, (end, end_v), frame), change
    # at rest, steps of 0.01 s: a margin of g h^2 = 1 mm; 1 cm sideways outruns it, yet is
    # too little to make the ball fast (a quarter of its half width, 2.5 cm)
    v[:] = 0.0
    frame, _ = stepper.settled_frame(q, v, 0.01, stepper.limits(0.01))
    end = q.copy()
    end[ball, 0] += 0.01
    assert frame.margin[ball] < 0.01 < 0.025
    assert not stepper._quiet(q, (end, v), frame)
