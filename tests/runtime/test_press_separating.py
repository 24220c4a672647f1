"""A press must not leave a touching contact closing: a landing pile never overlaps.

The press (runtime.step.resting) moves an island's bodies to bring its resting contacts to
rest, and in a pile's near-mechanisms by far more than the d' it removes, which can slow or
turn a touching contact that was separating. Left free, such a contact was watched for an
impact that had already happened (gap ~0, closing at t = 0) or that never comes while gravity
pushes it in; a landing pile of 30 discs overlapped by 2.8e-7 m (50 discs: 7e-6 m) where every
closing contact is located to 1e-12 m. References: non-penetration (every gap >= -TOUCH) and,
after every frame, d' >= 0 at every touching contact (the frame's impulses and presses are
plastic: nothing touching may still approach)."""

from __future__ import annotations

import numpy as np

import runtime
from bench.scenes import falling_pile
from runtime import settings
from runtime.step import stepper
from runtime.step.classify import OPEN


def test_a_landing_pile_never_overlaps_and_no_frame_leaves_a_touching_contact_closing(
    monkeypatch,
) -> None:
    closing: list[float] = []
    settled_frame = stepper.Stepper.settled_frame

    def checked(self, q, v, h, limits, active=None, margin=None):
        frame, solution = settled_frame(self, q, v, h, limits, active, margin)
        rate = self.evaluator.rows(frame.contacts, q, frame.velocities).gap_velocity
        touching = frame.modes != OPEN
        if np.any(rate[touching] < -limits.resting_speed):
            closing.append(float(rate[touching].min()))
        return frame, solution

    monkeypatch.setattr(stepper.Stepper, "settled_frame", checked)
    world = runtime.World(falling_pile(30))
    deepest, touching = 0.0, 0
    for _ in range(400):
        world.step(1e-3)
        if len(world.contacts):
            touching += len(world.contacts)
            deepest = max(deepest, -float(world.contacts.gap.min()))
    assert touching > 1000  # the pile landed and rests on itself
    assert closing == []
    assert deepest <= settings.TOUCH, deepest
