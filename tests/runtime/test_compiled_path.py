"""The compiled stages (runtime.step.compiled_frame, compiled_stages) are the general path's
computation in one call: a landing pile -- one-contact islands, islands of several contacts,
impacts located in time, presses -- steps to the same state on either, to rounding (the two
solve the same small systems by different codes: 400 steps of this pile differ by 6e-29 m/s
in velocities near rest and 2e-19 s in impact times). So a shortcut in one (a one-contact
island solved on scalars, contacts already in island order not copied, stages written in
place) that changes more than a rounding shows here, not as a drift somewhere in a long run."""

from __future__ import annotations

import numpy as np

import runtime
from bench.scenes import falling_pile
from runtime import settings


def _run(compiled: bool, monkeypatch) -> tuple:
    monkeypatch.setattr(settings, "COMPILED", compiled)
    world = runtime.World(falling_pile(12))
    impacts, largest = [], 0
    for _ in range(400):
        impacts += world.step(1e-3).impact_times
        largest = max(largest, len(world.contacts))
    return world.poses, world.velocities, np.array(impacts), largest


def test_a_landing_pile_steps_to_the_same_state_compiled_or_not(monkeypatch):
    poses, velocities, impacts, contacts = _run(True, monkeypatch)
    general = _run(False, monkeypatch)
    assert len(impacts) > 20 and contacts > 12  # impacts, and islands of several contacts
    np.testing.assert_allclose(poses, general[0], rtol=0, atol=1e-13)
    np.testing.assert_allclose(velocities, general[1], rtol=0, atol=1e-13)
    assert len(impacts) == len(general[2])
    np.testing.assert_allclose(impacts, general[2], rtol=0, atol=1e-15)
