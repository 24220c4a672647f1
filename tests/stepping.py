"""Stepping a World by hand, for tests that compare two ways of taking the same steps."""

from __future__ import annotations

import numpy as np


def states_and_impacts(world, steps: int, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """(steps, 2n, 3) poses and velocities after every step of ``dt``, and the impact times
    located on the way: what two runs that should be the same, bit for bit, must agree on."""
    states, impacts = [], []
    for _ in range(steps):
        impacts += world.step(dt).impact_times
        states.append(np.concatenate([world.poses, world.velocities]))
    return np.array(states), np.array(impacts)
