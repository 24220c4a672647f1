"""Resting contacts that move apart: pressed back to rest, or lifting off.

Why this module exists: the contact forces (runtime.solve.dynamics) are an LCP on accelerations,
which assumes every resting contact has d' = 0. After impacts in a pile, neighbouring resting
contacts are left moving apart at tiny speeds (d' > 0, below the separation speed). Kept in the
LCP, such a contact is pushed while it moves apart: the force does work f d' > 0 and feeds
energy in, and it hovers (d'' = 0 keeps it drifting apart). Left out, it lifts, falls back
within microseconds and lands again -- thousands of located impacts per second in a pile. The
physical outcome of such a hop is a plastic landing, so it is applied at once:

* a resting contact moving apart that the forces press (force > 0), or that nothing lifts
  (force 0 and d'' = 0, a redundant contact), is *pressed*: impulses make its d' exactly 0
  (bilateral rows of the runtime.solve.lcp solver; >= 0 impulses and d' >= 0 on the other resting
  contacts). The kinetic energy can only go down (by p.A p / 2);
* one moving apart with d'' > 0 and no force really lifts off: it is marked ``LIFTING``, left
  out of the force computation of the step and watched for its return (an impact located in
  time); a lifting contact that the new forces would press, or that a press has turned to
  approach, is brought back and pressed.

This repeats until it settles; contacts pressed once stay pressed in the later rounds (else
pressing one set lets the last one drift apart again, and the rounds go back and forth).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from runtime.solve import lcp
from runtime.step.collisions import Frame, Mode, subset

_RESTING, _LIFTING = int(Mode.RESTING), int(Mode.LIFTING)


def settle(
    dynamics,
    frame: Frame,
    solve: Callable[[list, np.ndarray], object],
    creep_speed: float,
    rounds: int = 8,
):
    """(frame, solution): ``frame`` with pressed contacts at rest and lifting ones marked, and
    the contact forces of its resting set (``solve(resting, velocities) -> ContactSolution``)."""
    solution = solve(frame.resting, frame.velocities)
    if frame.rows is None:
        return frame, solution
    held = np.zeros(len(frame.contacts), dtype=bool)  # pressed so far: they stay pressed
    for _ in range(rounds):
        modes, dv = frame.modes, frame.rows.gap_velocity
        rest = np.flatnonzero(modes == _RESTING)
        lift = np.flatnonzero(modes == _LIFTING)
        apart = dv[rest] > creep_speed
        if not apart.any() and lift.size == 0:
            break
        forces, b = solution.forces, solution.free_gap_acceleration
        tol = lcp.DEFAULT_TOL * float(np.max(np.abs(b), initial=1.0))
        if rest.size:
            a_matrix = dynamics.effective_mass_matrix(subset(frame.rows, rest))[0]
            lifts = apart & (forces <= 0.0) & (a_matrix @ forces + b > tol)
        else:
            lifts = np.zeros(0, dtype=bool)
        back = np.zeros(lift.size, dtype=bool)
        if lift.size:  # pressed by the current forces, or pulled back by a press
            rows = subset(frame.rows, lift)
            acc = solution.accelerations.ravel()
            back = rows.dense_jacobian(len(frame.velocities)) @ acc + rows.bias < -tol
            back |= rows.gap_velocity < -creep_speed
        to_press = np.concatenate([rest[apart & ~lifts], lift[back]])
        to_lift = rest[lifts]
        if to_press.size == 0 and to_lift.size == 0:
            break
        modes = modes.copy()
        modes[to_lift] = _LIFTING
        modes[lift[back]] = _RESTING
        frame = replace(frame, modes=modes)
        held[to_lift] = False
        if to_press.size:
            held[to_press] = True  # pressing one set must not let the last one drift apart
            pressed = _press(dynamics, frame, np.flatnonzero(held & (modes == _RESTING)))
            if pressed is None:
                break
            frame = pressed
        solution = solve(frame.resting, frame.velocities)
    return frame, solution


def _press(dynamics, frame: Frame, which: np.ndarray) -> Frame | None:
    """The frame with d' = 0 on the contacts ``which`` and d' >= 0 on its other resting
    contacts, by normal impulses (of either sign on ``which``); None if the solver finds the
    pressed contacts inconsistent (dependent rows asked for different speeds)."""
    rest = np.flatnonzero(frame.modes == _RESTING)
    rows = subset(frame.rows, rest)
    a_matrix, _, jm = dynamics.effective_mass_matrix(rows)
    joint, b = np.isin(rest, which), rows.gap_velocity
    p = _active_set(a_matrix, b, joint)
    if p is None:
        try:
            p = lcp.solve(a_matrix, b, joint=joint)
        except lcp.ContactSolverError:
            return None
    change = (jm.T @ p).ravel()
    velocities = frame.velocities + change.reshape(frame.velocities.shape)
    every = frame.rows
    moved = every.gap_velocity + every.dense_jacobian(len(velocities)) @ change
    return replace(frame, velocities=velocities, rows=replace(every, gap_velocity=moved))


def _active_set(
    a_matrix: np.ndarray, b: np.ndarray, joint: np.ndarray, tries: int = 8
) -> np.ndarray | None:
    """The press problem by a few block pivots (linear solves): start with impulses on the
    pressed ``joint`` rows only, add the resting rows left approaching, drop those with a
    negative impulse, until the solution checks; None if it does not within ``tries``."""
    scale = lcp.DEFAULT_TOL * float(np.max(np.abs(b), initial=0.0))
    active = joint.copy()
    for _ in range(tries):
        try:
            p_active = np.linalg.solve(a_matrix[np.ix_(active, active)], -b[active])
        except np.linalg.LinAlgError:
            return None
        p = np.zeros_like(b)
        p[active] = p_active
        a = a_matrix @ p + b
        negative = active & ~joint & (p < 0.0)
        approach = ~active & (a < -scale)
        if not negative.any() and not approach.any():
            return p if np.all(np.abs(a[active]) <= scale) else None
        active = (active & ~negative) | approach
    return None
