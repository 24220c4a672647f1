"""Resting contacts that move apart: pressed back to rest, or lifting off.

Why this module exists: the contact forces are an LCP on accelerations, which assumes every
resting contact has d' = 0. After impacts in a pile, neighbouring resting contacts are left
moving apart at tiny speeds (d' > 0, below the separation speed). Kept in the LCP, such a contact
is pushed while it moves apart: the force does work f d' > 0 and feeds energy in, and it hovers
(d'' = 0 keeps it drifting apart). Left out, it lifts, falls back within microseconds and lands
again -- thousands of located impacts per second in a pile. The physical outcome of such a hop
is a plastic landing, so it is applied at once:

* a resting contact moving apart that the forces press (force > 0), or that nothing lifts
  (force 0 and d'' = 0, a redundant contact), is *pressed*: impulses make its d' exactly 0, and
  with it that of every other resting contact of its island (bilateral rows of the LCP: the
  velocities projected onto those that keep the island's resting contacts at rest, always
  possible since rest itself is one). The kinetic energy can only go down. Pressing only the
  contacts moving apart, with d' >= 0 on the others, let each press set the next contacts
  moving apart: in a landing pile of 50 discs, 6-8 rounds of two ~90-row solves each, and
  pressed sets whose rounding made them look inconsistent;
* one moving apart with d'' > 0 and no force really lifts off: it is marked ``LIFTING``, left
  out of the force computation of the step and watched for its return (an impact located in
  time); a lifting contact that the new forces would press, or that a press has turned to
  approach, is brought back and pressed;
* a touching contact separating before a press and no longer after it (the press moves the
  island's bodies, and a near-mechanism moves them by far more than the d' it removes) rests,
  and is pressed if it now approaches. Left free it was watched for an impact that had
  already happened (gap ~0, closing at t = 0), or for one that never comes while gravity
  pushes it in (gap ~0, d' = 0, d'' < 0): landing piles overlapped by 5e-6 and 3e-7 m.

This repeats until it settles (a press can change the forces, and so what lifts); islands
pressed once stay pressed in the later rounds (else the rounds go back and forth).

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
from runtime.step.classify import LIFTING, RESTING, SEPARATING, Bodies, Frame


def settle(
    frame: Frame,
    solve: Callable[[Frame], object],
    bodies: Bodies,
    creep_speed: float,
    separation_speed: float,
    recovery: float = 0.0,
    rounds: int = settings.SETTLE_ROUNDS,
):
    """(frame, resting solution): ``frame`` with pressed contacts at rest and lifting ones
    marked, and ``solve(frame)`` of its resting set (an object with ``forces`` and
    ``free_rates`` per resting contact, in frame.resting order, and ``accelerations``).
    ``recovery`` (1/s): a penetrating contact moving apart at up to this x its depth is
    recovering under the stabilisation, not moving apart (see the module docstring).
    ``separation_speed``: a touching contact that a press leaves moving apart no faster than
    this rests (runtime.step.classify)."""
    solution = solve(frame)
    if len(frame.contacts) == 0:
        return frame, solution
    held = np.zeros(len(frame.contacts), dtype=bool)  # pressed so far: they stay pressed
    for _ in range(rounds):
        modes, rate = frame.modes, frame.rows.gap_velocity
        rest, lift = frame.resting, frame.lifting
        apart = rate[rest] > np.maximum(creep_speed, -recovery * frame.rows.gap[rest])
        turned = np.flatnonzero((modes == SEPARATING) & (rate <= separation_speed))
        if not apart.any() and lift.size == 0 and turned.size == 0:
            break
        tol = settings.LCP_TOL * float(np.max(np.abs(solution.free_rates), initial=1.0))
        acc = solution.accelerations
        lifts = apart & (solution.forces <= 0.0) & (_gap_acceleration(frame, rest, acc) > tol)
        back = np.zeros(lift.size, dtype=bool)
        if lift.size:  # pressed by the current forces, or pulled back by a press
            back = (_gap_acceleration(frame, lift, acc) < -tol) | (rate[lift] < -creep_speed)
        closing = turned[rate[turned] < -creep_speed]  # the others rest as they are
        to_press = np.concatenate([rest[apart & ~lifts], lift[back], closing])
        to_lift = rest[lifts]
        if to_press.size == 0 and to_lift.size == 0 and turned.size == 0:
            break
        modes = modes.copy()
        modes[to_lift] = LIFTING
        modes[lift[back]] = RESTING
        modes[turned] = RESTING
        frame = replace(frame, modes=modes)
        held[to_lift] = False
        if to_press.size:
            held[to_press] = True
            recovering = rest[(rate[rest] > creep_speed) & ~apart]
            pressed = _press(frame, np.flatnonzero(held & (modes == RESTING)), bodies, recovering)
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
def press_island(jac, body1, body2, inv_mass, fixed, rate, joint, p, dv):
    """Impulses p (written) of one island of resting contacts (their rows ``jac``, bodies and
    rates ``rate``), and the velocity change they make (added to ``dv``, per body): d' = 0 on
    the ``joint`` rows (the pressed contacts: impulses of either sign), d' >= 0 with impulses
    >= 0 on the others. With every row pressed, the projection (:func:`project_island`); else
    the mixed LCP with A = J M^-1 J^T, warm-started with the pressed rows clamped. False if
    that LCP has no solution."""
    if np.all(joint):
        return project_island(jac, body1, body2, inv_mass, fixed, rate, p, dv)
    K = rate.size
    A = np.empty((K, K))
    assembly.island_matrix(jac, body1, body2, inv_mass, fixed, 0, K, A)
    if not assembly.dense_lcp(A, rate, joint, joint.copy(), p):
        return False
    assembly.add_forces(jac, body1, body2, inv_mass, p, dv)
    return True


@njit
def project_island(jac, body1, body2, inv_mass, fixed, rate, p, dv):
    """The velocity change (added to ``dv``) that leaves d' = J v = 0 at every contact of the
    island, and its impulses p: the velocities projected, in the kinetic-energy metric, onto
    those that keep the contacts at rest.

    Why not A p = -d' with A = J M^-1 J^T: a pile holds near-mechanisms (contacts almost
    dependent), where A's smallest eigenvalues are ~1e-12 of its largest -- at the rounding of
    A -- while those of B = J M^-1/2 are ~1e-6 of its largest, well resolved. So the change
    comes from the SVD B = U S V^T, in u = M^1/2 v: du = -V S^-1 U^T d' over the singular
    values above settings.PRESS_RANK of the largest (d' = B u has no part beyond them but
    rounding), and p = -U S^-2 U^T d' (not used to make du: near-mechanisms make p large, and
    J^T p would cancel to rounding of it). Returns False if the data are not finite."""
    K = rate.size
    n = inv_mass.shape[0]
    column = np.full(n, -1, np.int64)
    width = 0
    for k in range(K):
        for side in range(2):
            b = body2[k] if side else body1[k]
            if not fixed[b] and column[b] < 0:
                column[b] = width
                width += 3
    p[:] = 0.0
    if width == 0:
        return True
    B = np.zeros((K, width))
    for k in range(K):
        for side in range(2):
            b = body2[k] if side else body1[k]
            if not fixed[b]:
                for c in range(3):
                    B[k, column[b] + c] += jac[k, 3 * side + c] * np.sqrt(inv_mass[b, c])
    if not (np.all(np.isfinite(B)) and np.all(np.isfinite(rate))):
        return False
    # columns that no row moves are left out of the SVD: a disc's turn (its normals all pass
    # through its centre) is a third of a disc pile's columns, and the SVD's cost grows with them
    used = np.zeros(width, np.bool_)
    for j in range(width):
        used[j] = np.any(B[:, j] != 0.0)
    kept = np.flatnonzero(used)
    if kept.size == 0:
        return True
    U, sv, Vt = np.linalg.svd(np.ascontiguousarray(B[:, kept]), full_matrices=False)
    du = np.zeros(width)
    for i in range(sv.size):
        if sv[i] > settings.PRESS_RANK * sv[0]:
            c = 0.0
            for k in range(K):
                c += U[k, i] * rate[k]
            for j in range(kept.size):
                du[kept[j]] -= Vt[i, j] * c / sv[i]
            for k in range(K):
                p[k] -= U[k, i] * c / (sv[i] * sv[i])
    for b in range(n):
        if column[b] >= 0:
            for c in range(3):
                j = column[b] + c
                if used[j]:  # du is in B's row space: exactly 0 off it
                    dv[b, c] += np.sqrt(inv_mass[b, c]) * du[j]
    return True


def _press(frame: Frame, which: np.ndarray, bodies: Bodies, recovering: np.ndarray) -> Frame | None:
    """The frame with d' = 0 on every resting contact of the islands of the contacts ``which``
    (d' >= 0 on the ``recovering`` ones: see the module docstring), by normal impulses
    (press_island, island by island); None if that has no solution."""
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
    joint = ~np.isin(rest[members], recovering)
    p, dv = np.zeros(members.size), np.zeros((n, 3))
    for g in range(len(offsets) - 1):
        k = slice(int(offsets[g]), int(offsets[g + 1]))
        if not press_island(
            jac[k], b1[k], b2[k], bodies.inverse_mass, bodies.fixed, rate[k].copy(),
            joint[k].copy(), p[k], dv,
        ):  # fmt: skip
            return None
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
