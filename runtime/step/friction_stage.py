"""The friction stage of a scene's step: its row evaluator, force solver and transition events.

Why a stage of its own: only a scene where some contact can have mu = sqrt(mu1 mu2) > 0 (two
bodies with friction) needs the tangential rows; every other scene must run exactly as before,
without importing a friction kernel (issue #15). The stepper asks :func:`friction_stage` once
and, when it gets a stage, uses its evaluator and forces in place of the frictionless ones and
adds its events to the impacts' and its hold of sticking contacts to the frame's settling
(runtime.step.stepper).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class FrictionStage:
    evaluator: object  # runtime.solve.friction_rows.FrictionRowEvaluator
    forces: object  # runtime.solve.friction.FrictionalForces
    events: object  # runtime.step.friction_events.FrictionEvents
    inconsistent: type  # runtime.solve.friction_lcp.FrictionInconsistent: no forces obey the modes

    def hold(self, frame, resting, bodies, solve):
        """The settled frame with its sticking contacts' residual slip removed
        (runtime.step.friction_hold)."""
        from runtime.step.friction_hold import hold_sticking

        return hold_sticking(frame, resting, bodies, solve)


def has_friction(scene) -> bool:
    """Whether some pair of the scene's bodies has a contact coefficient sqrt(mu1 mu2) > 0."""
    return int(np.count_nonzero(scene.friction > 0)) >= 2


def friction_stage(scene, fixed: np.ndarray, stabilisation, collision) -> FrictionStage | None:
    """The scene's friction stage, or None when no contact can have friction; ``collision``:
    the stepper's runtime.step.collision.Collision (its oval refresh)."""
    if not has_friction(scene):
        return None
    # imported here: a frictionless scene never loads them (nor the generated friction rows)
    from runtime.solve.friction import FrictionalForces
    from runtime.solve.friction_lcp import FrictionInconsistent
    from runtime.solve.friction_rows import FrictionRowEvaluator
    from runtime.step.friction_events import FrictionEvents

    evaluator = FrictionRowEvaluator(scene.contact_cases(), fixed, scene.friction)
    forces = FrictionalForces(scene, stabilisation)
    events = FrictionEvents(evaluator, forces, fixed, collision.refresh_ovals)
    return FrictionStage(evaluator, forces, events, FrictionInconsistent)
