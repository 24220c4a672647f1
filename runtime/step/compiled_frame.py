"""The frame of an instant -- classify, impacts, settle, resting forces -- in one compiled call.

Why: at every step (and at every located impact) the contacts are classified, the impacts among
the touching ones resolved island by island, resting contacts that move apart pressed or let
lift, and the resting forces solved. For scenes of small islands (a ball, a bowl, a few bodies
in contact) that is microseconds of arithmetic, which stage by stage from Python cost hundreds
of microseconds of calls. This is the same policy as runtime.step.classify (modes, restitution
waves, the plastic pass) and runtime.step.resting (press and lift rounds) -- the island-level
algorithms are shared: runtime.step.classify.classify_modes, runtime.solve.impulses.resolve_
island and runtime.step.resting.project_island are the compiled functions both paths call -- for
scenes whose every island has at most settings.DENSE_ISLAND contacts. It reports False when an
island is larger or a contact problem has no solution, and the caller builds the frame the
general way (which names the failure).

Outputs per contact: gap, rate (d' after the impacts), jacobian, bias, modes, impulses, forces
(of the resting contacts; 0 elsewhere), free rates b (resting contacts); per body: velocities
after the impacts and presses, accelerations under the resting forces; the kinetic energy the
impacts and presses took out; and ``guess``, the clamped state of each contact after its last
solve (the warm start of the next; a large island's loaded set, runtime.solve.assembly).
"""

from __future__ import annotations

import numpy as np

from runtime.compiled import njit
from runtime.solve import assembly
from runtime.solve.impulses import resolve_island
from runtime.solve.islands import _labels
from runtime.solve.kernel_set import all_by_case, by_case
from runtime.step.classify import LIFTING, OPEN, RESTING, SEPARATING, classify_modes
from runtime.step.resting import project_island


@njit
def _groups(labels, members):
    """(grouped, offsets): ``members`` grouped by their labels (stable), and where each group
    starts. Labels already in order (contacts come by pair, so often) are not sorted again."""
    sub = labels[members]
    ordered = True
    for k in range(1, sub.size):
        if sub[k] < sub[k - 1]:
            ordered = False
            break
    order = np.arange(sub.size) if ordered else np.argsort(sub, kind="mergesort")
    grouped = members[order]
    starts = [0]
    for k in range(1, grouped.size):
        if sub[order[k]] != sub[order[k - 1]]:
            starts.append(k)
    starts.append(grouped.size)
    return grouped, np.array(starts, np.int64)


@njit
def _contact_labels(n, body1, body2, fixed, members):
    """Island label of each of ``members`` (contacts), from the bodies they join."""
    labels = _labels(n, body1[members], body2[members], fixed)
    out = np.full(body1.size, -1, np.int64)
    for k in range(members.size):
        c = members[k]
        out[c] = labels[body2[c]] if fixed[body1[c]] else labels[body1[c]]
    return out


@njit
def _kinetic(mass, fixed, v):
    e = 0.0
    for i in range(v.shape[0]):
        if not fixed[i]:
            for c in range(3):
                e += 0.5 * mass[i, c] * v[i, c] * v[i, c]
    return e


@njit
def _velocity_change(jac, body1, body2, inv_mass, members, p, v, rate):
    """v += W J^T p for the contacts ``members`` with impulses p, and rate (d' of every
    contact) += J dv."""
    dv = np.zeros(v.shape)
    for q in range(members.size):
        k, f = members[q], p[q]
        if f == 0.0:
            continue
        i, j = body1[k], body2[k]
        for c in range(3):
            dv[i, c] += inv_mass[i, c] * jac[k, c] * f
            dv[j, c] += inv_mass[j, c] * jac[k, 3 + c] * f
    _add_velocity(jac, body1, body2, dv, v, rate)


@njit
def _add_velocity(jac, body1, body2, dv, v, rate):
    """v += dv, and rate (d' of every contact) += J dv."""
    for k in range(rate.size):
        i, j = body1[k], body2[k]
        s = 0.0
        for c in range(3):
            s += jac[k, c] * dv[i, c] + jac[k, 3 + c] * dv[j, c]
        rate[k] += s
    for i in range(v.shape[0]):
        for c in range(3):
            v[i, c] += dv[i, c]


@njit
def _block(jac, body1, body2, inv_mass, fixed, members, start, stop):
    """A of the contacts members[start:stop] (copied contiguous for the island matrix)."""
    idx = members[start:stop]
    A = np.empty((idx.size, idx.size))
    assembly.island_matrix(
        np.ascontiguousarray(jac[idx]), body1[idx], body2[idx], inv_mass, fixed, 0, idx.size, A
    )
    return A


@njit
def touching_islands(body1, body2, fixed, modes, rate, creep, n):
    """The touching contacts grouped by island (members, offsets), and whether each island has
    a contact approaching faster than ``creep`` (it has impacts to resolve)."""
    touching = np.flatnonzero(modes != OPEN)
    labels = _contact_labels(n, body1, body2, fixed, touching)
    members, offsets = _groups(labels, touching)
    approaching = np.zeros(offsets.size - 1, np.bool_)
    for g in range(offsets.size - 1):
        for k in members[offsets[g] : offsets[g + 1]]:
            if rate[k] < -creep:
                approaching[g] = True
    return members, offsets, approaching


@njit
def restitution_of(body1, body2, rate, restitution, recent, resting_speed, island):
    """e of each contact of an island: the larger of its bodies', 0 for a resting contact
    (``recent``) that drifted open and now approaches (not a collision)."""
    e = np.empty(island.size)
    for q in range(island.size):
        k = island[q]
        e[q] = max(restitution[body1[k]], restitution[body2[k]])
        if recent[k] and rate[k] < -resting_speed:
            e[q] = 0.0
    return e


@njit
def impact_island(jac, body1, body2, inv_mass, fixed, rate, e, resting_speed, creep, island, v,
                  impulses):  # fmt: skip
    """Resolve one island's impacts (resolve_island), v and rate updated; False if its impulse
    problem has no solution."""
    A = _block(jac, body1, body2, inv_mass, fixed, island, 0, island.size)
    p = np.zeros(island.size)
    if resolve_island(A, rate[island].copy(), e, resting_speed, creep, p) < 0:
        return False
    for q in range(island.size):
        impulses[island[q]] += p[q]
    _velocity_change(jac, body1, body2, inv_mass, island, p, v, rate)
    return True


@njit
def _impacts(jac, body1, body2, inv_mass, fixed, modes, rate, restitution, recent, limits,
             limit, v, impulses):  # fmt: skip
    """Resolve the impacts among the touching contacts, island by island (resolve_island);
    False if an island is too large or its impulse problem has no solution."""
    touch, hold, resting_speed, separation, creep = limits
    members, offsets, approaching = touching_islands(body1, body2, fixed, modes, rate, creep,
                                                     v.shape[0])  # fmt: skip
    for g in range(offsets.size - 1):
        if not approaching[g]:
            continue
        if offsets[g + 1] - offsets[g] > limit:
            return False
        island = members[offsets[g] : offsets[g + 1]]
        e = restitution_of(body1, body2, rate, restitution, recent, resting_speed, island)
        if not impact_island(jac, body1, body2, inv_mass, fixed, rate, e, resting_speed, creep,
                             island, v, impulses):  # fmt: skip
            return False
    return True


@njit
def _forces(jac, body1, body2, bias, inv_mass, fixed, free_acc, modes, guess, tol, limit,
            forces, rates, acc, grouping):  # fmt: skip
    """Resting forces per island with the guess; False if an island is too large or has no
    solution. ``forces``/``rates`` per contact (0 where not resting), ``acc`` per body;
    ``grouping`` = (order, offsets, labels, counts): the resting contacts in island order,
    where each island starts, each one's island, and (contacts, islands + 1)."""
    n = acc.shape[0]
    acc[:, :] = free_acc
    forces[:] = 0.0
    rates[:] = 0.0
    order, offsets_out, labels_out, counts = grouping
    rest = np.flatnonzero(modes == RESTING)
    counts[0], counts[1] = 0, 1
    offsets_out[0] = 0
    if rest.size == 0:
        return True
    labels = _contact_labels(n, body1, body2, fixed, rest)
    members, offsets = _groups(labels, rest)
    counts[0], counts[1] = members.size, offsets.size
    order[: members.size] = members
    offsets_out[: offsets.size] = offsets
    labels_out[: members.size] = labels[members]
    every = members.size == modes.size  # all resting and in island order already: no copies
    for q in range(members.size if every else 0):
        if members[q] != q:
            every = False
            break
    if every:
        sub_jac, sub_b1, sub_b2, sub_bias, sub_guess = jac, body1, body2, bias, guess
        sub_f, sub_b = forces, rates
    else:
        sub_jac = np.ascontiguousarray(jac[members])
        sub_b1, sub_b2, sub_bias = body1[members], body2[members], bias[members]
        sub_f, sub_b = np.zeros(members.size), np.zeros(members.size)
        sub_guess = guess[members]
    ok = np.zeros(offsets.size - 1, np.bool_)
    assembly.solve_small_islands(
        sub_jac, sub_b1, sub_b2, sub_bias, inv_mass, fixed, free_acc, offsets, sub_guess,
        tol, limit, sub_f, sub_b, ok,
    )  # fmt: skip
    if not np.all(ok):
        return False
    assembly.add_forces(sub_jac, sub_b1, sub_b2, inv_mass, sub_f, acc)
    if not every:
        for q in range(members.size):
            k = members[q]
            forces[k], rates[k] = sub_f[q], sub_b[q]
            guess[k] = sub_guess[q]
    return True


@njit
def _gap_acceleration(jac, body1, body2, bias, acc, k):
    s = bias[k]
    i, j = body1[k], body2[k]
    for c in range(3):
        s += jac[k, c] * acc[i, c] + jac[k, 3 + c] * acc[j, c]
    return s


@njit
def _press(jac, body1, body2, inv_mass, fixed, modes, pressed, rate, limit, v, impulses):
    """d' = 0 on every resting contact of the islands of the ``pressed`` ones, by impulses
    (project_island, the policy of runtime.step.resting); False if it cannot."""
    n = v.shape[0]
    rest = np.flatnonzero(modes == RESTING)
    labels = _contact_labels(n, body1, body2, fixed, rest)
    members, offsets = _groups(labels, rest)
    for g in range(offsets.size - 1):
        start, stop = offsets[g], offsets[g + 1]
        island = members[start:stop]
        if not np.any(pressed[island]):
            continue
        if stop - start > limit:
            return False
        p, dv = np.zeros(island.size), np.zeros(v.shape)
        if not project_island(np.ascontiguousarray(jac[island]), body1[island], body2[island],
                              inv_mass, fixed, rate[island].copy(), p, dv):  # fmt: skip
            return False
        for q in range(island.size):
            impulses[island[q]] += p[q]
        _add_velocity(jac, body1, body2, dv, v, rate)
    return True


UNCHANGED, MODES, PRESS = 0, 1, 2  # what a settle round changed


@njit(inline="always")  # (no call, no reference counting per step)
def settle_round(jac, body1, body2, bias, acc, forces, rates, rate, tol, creep, separation,
                 modes, pressed):  # fmt: skip
    """One press/lift round (the policy of runtime.step.resting) on the resting forces and
    accelerations of the round before: ``modes`` and ``pressed`` updated. Returns UNCHANGED
    (settled), MODES (modes changed, nothing to press) or PRESS (contacts ``pressed`` and
    resting are to be pressed)."""
    scale = 1.0
    for k in range(rate.size):
        if modes[k] == RESTING:
            scale = max(scale, abs(rates[k]))
    threshold = tol * scale
    lift_now = np.zeros(rate.size, np.bool_)
    press_now = np.zeros(rate.size, np.bool_)
    turned = np.zeros(rate.size, np.bool_)
    for k in range(rate.size):
        if modes[k] == RESTING and rate[k] > creep:
            dd = _gap_acceleration(jac, body1, body2, bias, acc, k)
            if forces[k] <= 0.0 and dd > threshold:
                lift_now[k] = True
            else:
                press_now[k] = True
        elif modes[k] == LIFTING:
            dd = _gap_acceleration(jac, body1, body2, bias, acc, k)
            if dd < -threshold or rate[k] < -creep:
                press_now[k] = True
        elif modes[k] == SEPARATING and rate[k] <= separation:  # a press slowed it
            turned[k] = True
    if not (np.any(lift_now) or np.any(press_now) or np.any(turned)):
        return UNCHANGED
    for k in range(rate.size):
        if lift_now[k]:
            modes[k] = LIFTING
            pressed[k] = False
        elif press_now[k]:
            modes[k] = RESTING
            pressed[k] = True
        elif turned[k]:  # touching, no longer moving apart: it rests, pressed if closing
            modes[k] = RESTING
            if rate[k] < -creep:
                press_now[k] = True
                pressed[k] = True
    return PRESS if np.any(press_now) else MODES


@njit
def settle_frame(
    q, case, body1, body2, geometry, static2, held, recent, restitution, mass,
    inv_mass, fixed, free_acc, limits, tol, limit, rounds,
    v, gap, rate, jac, bias, modes, impulses, guess, forces, rates, acc, grouping,
):  # fmt: skip
    """The frame at (q, v): rows (runtime.solve.kernel_set.all_by_case), classify, the impacts,
    classify again, then the press/lift rounds with the resting forces (the policy of runtime.step.classify and runtime.step.
    resting). ``v`` becomes the velocities after the impulses; the other arrays after it are
    written, and ``grouping`` (see _forces) describes the resting contacts' islands. Returns
    (ok, the kinetic energy the impacts and presses took out)."""
    touch, hold, resting_speed, separation, creep = limits
    scratch_gap, scratch_rate = np.empty(gap.size), np.empty(gap.size)
    members = by_case(case)
    all_by_case(q, v, members, body1, body2, geometry, static2, gap, rate, jac, bias)
    before = _kinetic(mass, fixed, v)
    classify_modes(gap, rate, touch, hold, resting_speed, separation, held, modes)
    approach = False
    for k in range(gap.size):
        if modes[k] != OPEN and rate[k] < -creep:
            approach = True
    if approach:
        was_open = modes == OPEN
        if not _impacts(jac, body1, body2, inv_mass, fixed, modes, rate, restitution, recent,
                        limits, limit, v, impulses):  # fmt: skip
            return False, 0.0
        classify_modes(gap, rate, touch, hold, resting_speed, separation, held, modes)
        for k in range(gap.size):
            if was_open[k]:
                modes[k] = OPEN
        all_by_case(
            q,
            v,
            members,
            body1,
            body2,
            geometry,
            static2,
            scratch_gap,
            scratch_rate,
            jac,
            bias,
        )  # fmt: skip  (the bias at the new velocities)
    if not _forces(jac, body1, body2, bias, inv_mass, fixed, free_acc, modes, guess, tol, limit,
                   forces, rates, acc, grouping):  # fmt: skip
        return False, 0.0
    pressed = np.zeros(gap.size, np.bool_)  # pressed once: they stay pressed
    for _ in range(rounds):
        change = settle_round(jac, body1, body2, bias, acc, forces, rates, rate, tol, creep,
                              separation, modes, pressed)  # fmt: skip
        if change == UNCHANGED:
            break
        if change == PRESS:
            target = pressed & (modes == RESTING)
            if not _press(jac, body1, body2, inv_mass, fixed, modes, target, rate, limit, v,
                          impulses):  # fmt: skip
                return False, 0.0
            all_by_case(q, v, members, body1, body2, geometry, static2,
                        scratch_gap, scratch_rate, jac, bias)  # fmt: skip
        if not _forces(jac, body1, body2, bias, inv_mass, fixed, free_acc, modes, guess, tol,
                       limit, forces, rates, acc, grouping):  # fmt: skip
            return False, 0.0
    return True, before - _kinetic(mass, fixed, v)
