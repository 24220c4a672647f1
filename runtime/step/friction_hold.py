"""Sticking contacts start with v_t = 0 exactly: their residual slip removed by an impulse.

Why: a sticking contact keeps its tangential acceleration at 0, so whatever tangential speed it
had when it started to stick stays, and the bodies creep at it for ever. A contact sticks when
|v_t| <= settings.STICK_SPEED (runtime.solve.friction), and frictionless impulses (impacts, the
presses of runtime.step.resting) can leave such a speed: a box landing flat crept at 5e-10 m/s.
So at a frame, the sticking contacts' v_t is set to 0 by tangential impulses while the normal
d' of the island's resting contacts stays as it is: the least-norm p with

    J W J^T p = -(v_t of the sticking rows, 0 for the normal rows),   dv = W J^T p,

an M-orthogonal projection of the velocities for the tangential rows, so the kinetic energy
does not rise (it changes by -p.(J W J^T)p / 2 <= 0 plus p_n d'_n of the resting rows, whose d'
is at the rounding level). Contacts sticking with |v_t| below settings.STICK_SPEED x
settings.STICK_LOCATE (a located slip -> stick) are left alone.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from runtime import settings
from runtime.solve.friction_rows import dense_rows, island_bodies


def hold_sticking(frame, resting, bodies, solve: Callable) -> tuple:
    """(frame, resting solution) with the sticking contacts' residual v_t removed, solved again
    (``solve(frame)``) if anything changed; ``bodies``: runtime.step.classify.Bodies."""
    problem = resting.problem
    slide = getattr(problem, "slide", None)
    if slide is None or len(slide) == 0:
        return frame, resting
    rows = frame.rows
    index = frame.resting[problem.order]  # frame index of each problem row
    stick = (rows.mu[index] > 0) & (slide == 0)
    residual = np.abs(rows.tangent_velocity[index])
    if not np.any(stick & (residual > settings.STICK_SPEED * settings.STICK_LOCATE)):
        return frame, resting
    fixed = bodies.fixed
    tangential = rows.take(index[stick])
    normal = rows.take(index)
    jac6 = np.concatenate([tangential.tangent_jacobian, normal.jacobian])
    b1 = np.concatenate([tangential.body1, normal.body1])
    b2 = np.concatenate([tangential.body2, normal.body2])
    moving, local = island_bodies(b1, b2, fixed)
    J = dense_rows(jac6, b1, b2, local, fixed, moving.size)
    w = bodies.inverse_mass[moving].ravel()
    target = np.concatenate([-tangential.tangent_velocity, np.zeros(len(index))])
    p = np.linalg.lstsq((J * w) @ J.T, target, rcond=None)[0]
    dv = np.zeros_like(frame.velocities)
    dv[moving] = (w * (J.T @ p)).reshape(-1, 3)
    velocities = frame.velocities + dv
    loss = bodies.kinetic(frame.velocities) - bodies.kinetic(velocities)
    frame = replace(
        frame,
        velocities=velocities,
        rows=rows.with_velocity_change(dv),
        impact_loss=frame.impact_loss + loss,
    )
    return frame, solve(frame)
