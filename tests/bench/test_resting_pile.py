"""The resting pile the step benchmarks time (bench/steps.py, bench/targets.py) is at rest.

Why: a benchmark of "steps per second at rest" on a pile that is moving times something else.
The earlier resting pile (neighbours in a row 4 mm apart) was not in equilibrium: frictionless,
its discs slid into their gaps, and after ~80 steps the colliding rows made each step ~100
times dearer than the 20 steps the targets timed. Reference: equilibrium itself -- every
disc's acceleration 0, the poses unchanged after steps."""

from __future__ import annotations

import numpy as np
import pytest

import runtime
from bench.steps import GAP, pile_scene


@pytest.mark.parametrize("discs", [10, 50])
def test_the_packed_pile_is_at_rest(discs: int) -> None:
    world = runtime.World(pile_scene(discs, gap=0.0))
    start = world.poses.copy()
    _, resting = world.stepper.classify(world.poses, world.velocities, 1e-3)
    assert np.abs(resting.accelerations).max() < 1e-10  # m/s^2, from ~10 m/s^2 terms
    for _ in range(30):
        world.step(1e-3)
    assert np.abs(world.poses - start).max() < 1e-12  # m
    assert np.abs(world.velocities).max() < 1e-10  # m/s


def test_the_gapped_pile_is_not_at_rest() -> None:
    """What the docstring of pile_scene says of the default (gapped) pile."""
    world = runtime.World(pile_scene(50, gap=GAP))
    _, resting = world.stepper.classify(world.poses, world.velocities, 1e-3)
    assert np.abs(resting.accelerations).max() > 0.5  # m/s^2
