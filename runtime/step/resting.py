"""Resting contacts that move apart: pressed back to rest, or lifting off.

Why this module exists: the contact forces are an LCP on accelerations, which assumes every
resting contact has d' = 0. After impacts in a pile, neighbouring resting contacts are left
moving apart at tiny speeds (d' > 0, below the separation speed). Kept in the LCP, such a contact
is pushed while it moves apart: the force does work f d' > 0 and feeds energy in, and it hovers
(d'' = 0 keeps it drifting apart). Left out, it lifts, falls back within microseconds and lands
again -- thousands of located impacts per second in a pile. The physical outcome of such a hop
is a plastic landing, so it is applied at once:

* a resting contact moving apart that the forces press (force > 0), or that nothing lifts
  (force 0 and d'' = 0, a redundant contact), is *pressed*: impulses make its d' exactly 0
  (bilateral rows of the LCP; >= 0 impulses and d' >= 0 on the other resting contacts of its
  island). The kinetic energy can only go down;
* one moving apart with d'' > 0 and no force really lifts off: it is marked ``LIFTING``, left
  out of the force computation of the step and watched for its return (an impact located in
  time); a lifting contact that the new forces would press, or that a press has turned to
  approach, is brought back and pressed.

This repeats until it settles; contacts pressed once stay pressed in the later rounds (else
pressing one set lets the last one drift apart again, and the rounds go back and forth).

With stabilisation (runtime.solve.forces.Stabilisation) a penetrating contact is *meant* to move
apart: the Baumgarte term drives it out along a critically damped path, whose speed never
exceeds depth / T = depth x k_d / 2. Such a contact is not pressed (``recovery`` = k_d / 2), or the
press would take that speed away at every step and the penetration would barely decay.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import assembly
from runtime.solve.islands import body_islands, contact_islands, grouped
from runtime.step.classify import LIFTING, RESTING, Bodies, Frame


def settle(
    frame: Frame,
    solve: Callable[[Frame], object],
    bodies: Bodies,
    creep_speed: float,
    recovery: float = 0.0,
    rounds: int = settings.SETTLE_ROUNDS,
):
    """(frame, resting solution): ``frame`` with pressed contacts at rest and lifting ones
    marked, and ``solve(frame)`` of its resting set (an object with ``forces`` and
    ``free_rates`` per resting contact, in frame.resting order, and ``accelerations``).
    ``recovery`` (1/s): a penetrating contact moving apart at up to this x its depth is
    recovering under the stabilisation, not moving apart (see the module docstring)."""
    solution = solve(frame)
    if len(frame.contacts) == 0:
        return frame, solution
    held = np.zeros(len(frame.contacts), dtype=bool)  # pressed so far: they stay pressed
    for _ in range(rounds):
        modes, rate = frame.modes, frame.rows.gap_velocity
        rest, lift = frame.resting, frame.lifting
        apart = rate[rest] > np.maximum(creep_speed, -recovery * frame.rows.gap[rest])
        if not apart.any() and lift.size == 0:
            break
        tol = settings.LCP_TOL * float(np.max(np.abs(solution.free_rates), initial=1.0))
        acc = solution.accelerations
        lifts = apart & (solution.forces <= 0.0) & (_gap_acceleration(frame, rest, acc) > tol)
        back = np.zeros(lift.size, dtype=bool)
        if lift.size:  # pressed by the current forces, or pulled back by a press
            back = (_gap_acceleration(frame, lift, acc) < -tol) | (rate[lift] < -creep_speed)
        to_press = np.concatenate([rest[apart & ~lifts], lift[back]])
        to_lift = rest[lifts]
        if to_press.size == 0 and to_lift.size == 0:
            break
        modes = modes.copy()
        modes[to_lift] = LIFTING
        modes[lift[back]] = RESTING
        frame = replace(frame, modes=modes)
        held[to_lift] = False
        if to_press.size:
            held[to_press] = True
            pressed = _press(frame, np.flatnonzero(held & (modes == RESTING)), bodies)
            if pressed is None:
                break
            frame = pressed
        solution = solve(frame)
    return frame, solution


def _gap_acceleration(frame: Frame, which: np.ndarray, acc: np.ndarray) -> np.ndarray:
    """d'' = J acc + bias of the contacts ``which`` under the accelerations ``acc``."""
    rows = frame.rows.take(which)
    out = np.zeros(which.size)
    assembly.free_rates(
        np.ascontiguousarray(rows.jacobian), rows.body1, rows.body2, rows.bias, acc, out
    )
    return out


@njit
def press_island(A, rate, joint, p):
    """Impulses p (written) of one island of resting contacts with effective-mass matrix A and
    rates ``rate``: d' = 0 on the ``joint`` rows (the pressed contacts: impulses of either
    sign), d' >= 0 with impulses >= 0 on the others -- the mixed LCP (A, rate), warm-started
    with the pressed rows clamped. False if the pressed rows are inconsistent (dependent rows
    asked for different speeds)."""
    return assembly.dense_lcp(A, rate, joint, joint.copy(), p)


def _press(frame: Frame, which: np.ndarray, bodies: Bodies) -> Frame | None:
    """The frame with d' = 0 on the contacts ``which`` and d' >= 0 on the other resting
    contacts of their islands, by normal impulses (press_island, island by island); None if
    the pressed contacts are inconsistent."""
    rest = frame.resting
    rows = frame.rows.take(rest)
    n = len(bodies.fixed)
    labels = contact_islands(
        body_islands(n, rows.body1, rows.body2, bodies.fixed), rows.body1, rows.body2, bodies.fixed
    )
    touched = np.isin(labels, labels[np.isin(rest, which)])
    members = np.flatnonzero(touched)
    order, offsets = grouped(labels[members])
    members = members[order]
    jac = np.ascontiguousarray(rows.jacobian[members])
    b1, b2 = rows.body1[members], rows.body2[members]
    rate = rows.gap_velocity[members]
    joint = np.isin(rest[members], which)
    p = np.zeros(members.size)
    for g in range(len(offsets) - 1):
        start, stop = int(offsets[g]), int(offsets[g + 1])
        A = np.empty((stop - start, stop - start))
        assembly.island_matrix(jac, b1, b2, bodies.inverse_mass, bodies.fixed, start, stop, A)
        part = np.zeros(stop - start)
        if not press_island(A, rate[start:stop].copy(), joint[start:stop].copy(), part):
            return None
        p[start:stop] = part
    dv = np.zeros((n, 3))
    assembly.add_forces(jac, b1, b2, bodies.inverse_mass, p, dv)
    impulses = frame.impulses.copy()
    impulses[rest[members]] += p
    velocities = frame.velocities + dv
    loss = bodies.kinetic(frame.velocities) - bodies.kinetic(velocities)
    return replace(
        frame,
        velocities=velocities,
        rows=frame.rows.with_velocity_change(dv),
        impulses=impulses,
        impact_loss=frame.impact_loss + loss,
    )
