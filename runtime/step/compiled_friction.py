"""A step of a scene with Coulomb friction in compiled calls: frame, trial, quiet check, events.

Why: a scene with friction solves each island's friction LCP at its frame and at every
integrator stage (runtime.solve.friction), and from Python each solve cost ~100 us of calls
around a few microseconds of compiled work -- a rolling disc's step was 1.4 ms, 8 solves. These
are the same computations as the general path's, in the same order, as runtime.step.
compiled_frame, compiled_stages and quiet are for a frictionless scene:

* :func:`settle_frame` -- rows (normal and tangential, from the generated kernels), classify,
  impacts (with friction: :func:`frictional_impulses`, runtime.solve.friction_impulses' policy),
  the resting forces with each contact's mode decided (:func:`friction_forces`, runtime.solve.
  friction's), the press/lift rounds, the hold of sticking contacts (:func:`hold_sticking`,
  runtime.step.friction_hold's); :func:`frame` builds the stepper's Frame from it;
* :func:`step` -- the trial step, each stage's LCP solved from the bases its contacts had last,
  with the modes the frame decided;
* :func:`friction_quiet` -- whether a trial has no friction transition for the event search,
  and :func:`friction_state`, what that search asks at an instant (v_t, a_t, slips).

Each reports False where the general path must do it -- an island without a frictional
contact, an LCP that needs the held fallback or has no solution (a Painleve configuration,
which the general path names), an island above settings.DENSE_ISLAND, a non-finite term.
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve.friction_kernel_set import tangent_rows_by_case, tangent_velocity_by_case
from runtime.solve.friction_lcp import solve_islands
from runtime.solve.kernel_set import all_by_case, by_case, rows_by_case
from runtime.solve.lemke import SOLVED, lemke_perturbed
from runtime.step.classify import OPEN, RESTING, classify_modes
from runtime.step.compiled_frame import (
    PRESS,
    UNCHANGED,
    _add_velocity,
    _contact_labels,
    _groups,
    _kinetic,
    _press,
    impact_island,
    restitution_of,
    settle_round,
    touching_islands,
)
from runtime.step.compiled_stages import finite, rk4_sum, stage

_RESIDUAL = settings.STICK_SPEED * settings.STICK_LOCATE  # m/s: a slip the hold removes
_WAVES = settings.MAX_WAVES  # restitution waves before the final plastic pass
_ENERGY_SLACK = settings.IMPACT_ENERGY_SLACK
_EPS = 2.220446049250313e-16  # float64's machine epsilon: lstsq's rcond as NumPy's default
_COVERS = 0  # Lemke's other covering vectors here: none, a failure declines to the general
# path, which tries them (trying them here too doubled the cost of a failing path: a packed
# 60-disc pile's first frame, ~600 unknowns, 84 s here and 84 s again there)


@njit
def accelerations(
    q, v, members, body1, body2, geometry, static2, ends, offsets, islands, mu, slide, flags,
    inv_mass, fixed, free_acc, acc, scratch,
):  # fmt: skip
    """acc (n, 3) under the friction forces of the resting contacts (grouped by island,
    ``offsets``; ``islands``: every island's index; ``flags``: the warm-start bases, updated);
    False if an island needs the general path. ``scratch``: runtime.step.compiled_friction.
    scratch(m), written."""
    jac, bias, tangent_jac, tangent_bias, normal, tangent, slack, a_t, rates, slips = scratch
    acc[:, :] = free_acc
    if body1.size == 0:
        return True
    rows_by_case(q, v, members, body1, body2, geometry, static2, jac, bias)
    tangent_rows_by_case(q, v, members, body1, body2, geometry, static2, tangent_jac, tangent_bias)
    if not (finite(jac) and finite(bias) and finite(tangent_jac) and finite(tangent_bias)):
        return False
    failed = solve_islands(
        islands, offsets, jac, tangent_jac, ends, bias, tangent_bias, mu, slide, inv_mass,
        fixed, free_acc, normal, tangent, slack, a_t, rates, acc, flags, slips, True, _COVERS,
    )  # fmt: skip
    return failed[0] < 0


@njit
def scratch(m):
    """The arrays :func:`accelerations` writes, for m contacts."""
    return (np.empty((m, 6)), np.empty(m), np.empty((m, 6)), np.empty(m), np.empty(m),
            np.empty(m), np.empty(m), np.empty(m), np.empty(m), np.empty(m, np.bool_))  # fmt: skip


@njit
def step(
    method, q0, v0, h, a0, case, body1, body2, geometry, static2, ends, offsets, mu, slide,
    flags, inv_mass, fixed, free_acc, q_out, v_out,
):  # fmt: skip
    """(q_out, v_out) = one step of length h from (q0, v0) with first-stage accelerations a0
    (methods as runtime.step.compiled_stages.METHOD_ID); False if a stage needs the general
    path."""
    if method == 0:
        stage(q0, v0, v0, a0, h, q_out, v_out)
        return True
    work = scratch(case.size)
    islands = np.arange(offsets.size - 1)
    args = (by_case(case), body1, body2, geometry, static2, ends, offsets, islands, mu, slide,
            flags, inv_mass, fixed, free_acc)  # fmt: skip
    half = 0.5 * h
    q = np.empty_like(q0)
    v2, a2 = np.empty_like(v0), np.empty_like(a0)
    stage(q0, v0, v0, a0, half, q, v2)
    if not accelerations(q, v2, *args, a2, work):
        return False
    if method == 1:
        stage(q0, v0, v2, a2, h, q_out, v_out)
        return True
    v3, a3 = np.empty_like(v0), np.empty_like(a0)
    stage(q0, v0, v2, a2, half, q, v3)
    if not accelerations(q, v3, *args, a3, work):
        return False
    v4, a4 = np.empty_like(v0), np.empty_like(a0)
    stage(q0, v0, v3, a3, h, q, v4)
    if not accelerations(q, v4, *args, a4, work):
        return False
    rk4_sum(q0, v0, a0, v2, a2, v3, a3, v4, a4, h, q_out, v_out)
    return True


@njit
def friction_state(q, v, case, body1, body2, geometry, static2, ends, offsets, mu, slide, flags,
                   inv_mass, fixed, free_acc, v_t, a_t, slips):  # fmt: skip
    """v_t, a_t and the stick -> slip flags (runtime.solve.friction.FrictionSolution.slips) of
    the contacts at (q, v) with their modes ``slide``, solved from the bases ``flags`` (updated,
    as the general path's solve updates them): what the friction event search
    (runtime.step.friction_events) asks at each instant. False if the general path must solve."""
    m = case.size
    members = by_case(case)
    tangent_velocity_by_case(q, v, members, body1, body2, geometry, static2, v_t)
    work = scratch(m)
    acc = np.empty_like(free_acc)
    if not accelerations(q, v, members, body1, body2, geometry, static2, ends, offsets,
                         np.arange(offsets.size - 1), mu, slide, flags, inv_mass, fixed,
                         free_acc, acc, work):  # fmt: skip
        return False
    a_t[:] = work[7]
    slips[:] = work[9]
    return True


@njit
def friction_quiet(q, v, case, body1, body2, geometry, static2, ends, offsets, mu, slide, flags,
                   inv_mass, fixed, free_acc):  # fmt: skip
    """Whether a trial's end state (q, v) has no friction transition for the event search to
    locate: every sliding contact still slides the same way (s v_t > 0), and the friction LCP
    there (:func:`friction_state`, from a copy of the bases ``flags``: the search's solves
    leave them alone) lets no sticking contact slip. False where unsure."""
    m = case.size
    if m == 0:
        return True
    v_t, a_t, slips = np.empty(m), np.empty(m), np.empty(m, np.bool_)
    if not friction_state(q, v, case, body1, body2, geometry, static2, ends, offsets, mu, slide,
                          flags.copy(), inv_mass, fixed, free_acc, v_t, a_t, slips):  # fmt: skip
        return False
    for k in range(m):
        if slide[k] != 0.0 and not slide[k] * v_t[k] > 0.0:
            return False
    return not np.any(slips)


# -- the frame ----------------------------------------------------------------------------------


@njit
def _decide(v_t, mu, stick_speed):
    """Each contact's mode from its v_t (runtime.solve.friction): sliding against v_t (+-1) when
    faster than the stick speed, else 0 (sticking, or frictionless)."""
    slide = np.zeros(mu.size)
    for k in range(mu.size):
        if mu[k] > 0.0 and abs(v_t[k]) > stick_speed:
            slide[k] = np.sign(v_t[k])
    return slide


@njit
def friction_forces(rows, tangent, mu, stick_speed, inv_mass, fixed, free_acc, modes, flags,
                    slide, forces, friction, rates, acc, grouping):  # fmt: skip
    """The resting contacts' forces with friction, island by island, each contact's mode
    decided as runtime.solve.friction decides it (sticking contacts that the LCP lets slip slide
    the way they accelerate; decided again until none does). ``rows`` = (jac, bias, body1,
    body2), ``tangent`` = (v_t, J_t, tangent bias); ``flags`` the warm-start bases (updated);
    ``slide``, ``forces``, ``friction`` (f_t), ``rates`` (b) per contact, 0 where not resting;
    ``grouping`` as runtime.step.compiled_frame's. False if an island has no frictional
    contact or an LCP needs the general path (the held fallback, a Painleve configuration)."""
    jac, bias, body1, body2 = rows
    v_t, tangent_jac, tangent_bias = tangent
    n = acc.shape[0]
    acc[:, :] = free_acc
    for out in (slide, forces, friction, rates):
        out[:] = 0.0
    order, offsets_out, labels_out, counts = grouping
    rest = np.flatnonzero(modes == RESTING)
    counts[0], counts[1] = 0, 1
    offsets_out[0] = 0
    if rest.size == 0:
        return True
    labels = _contact_labels(n, body1, body2, fixed, rest)
    members, offsets = _groups(labels, rest)
    for g in range(offsets.size - 1):
        if not np.any(mu[members[offsets[g] : offsets[g + 1]]] > 0.0):
            return False  # a frictionless island: runtime.solve.forces, the general path
    counts[0], counts[1] = members.size, offsets.size
    order[: members.size] = members
    offsets_out[: offsets.size] = offsets
    labels_out[: members.size] = labels[members]
    m = members.size
    ends = np.empty((m, 2), np.int64)
    ends[:, 0], ends[:, 1] = body1[members], body2[members]
    sub_jac, sub_tangent = (
        np.ascontiguousarray(jac[members]),
        np.ascontiguousarray(tangent_jac[members]),
    )
    sub_bias, sub_tangent_bias, sub_mu = bias[members], tangent_bias[members], mu[members]
    sub_flags = flags[members]
    sub_slide = _decide(v_t[members], sub_mu, stick_speed)
    normal, tangential, slack, a_t, sub_rates = (np.empty(m), np.empty(m), np.empty(m),
                                                 np.empty(m), np.empty(m))  # fmt: skip
    slips = np.empty(m, np.bool_)
    islands = np.arange(offsets.size - 1)
    for _ in range(m + 1):
        acc[:, :] = free_acc
        if solve_islands(islands, offsets, sub_jac, sub_tangent, ends, sub_bias, sub_tangent_bias,
                         sub_mu, sub_slide, inv_mass, fixed, free_acc, normal, tangential, slack,
                         a_t, sub_rates, acc, sub_flags, slips, True, _COVERS)[0] >= 0:  # fmt: skip
            return False
        if not np.any(slips):
            break
        for i in range(m):
            if slips[i]:
                sub_slide[i] = np.sign(a_t[i])
    if np.any(slips):
        return False  # modes that never settle: the general path decides
    for q in range(m):
        k = members[q]
        slide[k], forces[k], friction[k], rates[k] = (
            sub_slide[q],
            normal[q],
            tangential[q],
            sub_rates[q],
        )
        flags[k] = sub_flags[q]
    return True


@njit
def dense_rows(jac, tangent_jac, body1, body2, fixed, inv_mass, rows, tangential):
    """(J, moving, w): the rows of the contacts ``rows`` -- tangential for the first
    ``tangential`` of them, normal for the rest -- over the moving bodies they touch
    (``moving``, sorted; 3 columns each), and those bodies' inverse masses w (3 each), for the
    small dense solves of impacts and holds (runtime.solve.friction_rows.dense_rows)."""
    local = np.full(fixed.size, -1, np.int64)
    found = []
    for k in rows:
        for b in (body1[k], body2[k]):
            if not fixed[b] and local[b] < 0:
                local[b] = 0
                found.append(b)
    moving = np.sort(np.array(found, np.int64))
    for i in range(moving.size):
        local[moving[i]] = i
    J = np.zeros((rows.size, 3 * moving.size))
    for r in range(rows.size):
        k = rows[r]
        row = tangent_jac[k] if r < tangential else jac[k]
        for side in range(2):
            b = body1[k] if side == 0 else body2[k]
            if not fixed[b]:
                for c in range(3):
                    J[r, 3 * local[b] + c] += row[3 * side + c]
    w = np.empty(3 * moving.size)
    for i in range(moving.size):
        for c in range(3):
            w[3 * i + c] = inv_mass[moving[i], c]
    return J, moving, w


@njit
def hold_sticking(jac, tangent_jac, body1, body2, v_t, mu, slide, rest, inv_mass, fixed, dv):
    """The impulse that sets the sticking contacts' residual v_t to 0 and leaves the normal d'
    of the resting contacts ``rest`` as it is (runtime.step.friction_hold, whose least-norm
    solve this is), its velocity change written to ``dv``; False (dv untouched) if no sticking
    contact slips faster than settings.STICK_SPEED x settings.STICK_LOCATE."""
    stick = np.array([k for k in rest if mu[k] > 0.0 and slide[k] == 0.0], np.int64)
    slipping = False
    for k in stick:
        slipping = slipping or abs(v_t[k]) > _RESIDUAL
    if not slipping:
        return False
    rows = np.concatenate((stick, rest))
    count = rows.size
    J, moving, w = dense_rows(jac, tangent_jac, body1, body2, fixed, inv_mass, rows, stick.size)
    target = np.zeros(count)
    for r in range(stick.size):
        target[r] = -v_t[stick[r]]
    p = np.linalg.lstsq((J * w) @ J.T, target, rcond=_EPS * count)[0]
    change = w * (J.T @ p)
    for i in range(moving.size):
        for c in range(3):
            dv[moving[i], c] = change[3 * i + c]
    return True


@njit
def cone_lcp(Jn, Jt, w, mu, vn, vt, normal, free_normal):
    """(solved, P_n, T) of the velocity-level friction LCP over these rows
    (runtime.solve.friction_impulses._cone_lcp, by Lemke's method): P_n unknown
    (``free_normal``) or ``normal``; T in the cone |T| <= mu P_n, opposing v_t after."""
    k = mu.size
    S = np.flatnonzero(mu > 0.0)
    s = S.size
    Jts = np.ascontiguousarray(Jt[S])
    kn = k if free_normal else 0
    n = kn + 3 * s
    M, q = np.zeros((n, n)), np.zeros(n)
    plus, minus, slack = kn, kn + s, kn + 2 * s
    Wts = Jts * w
    A_ss = Wts @ Jts.T
    if free_normal:
        Wn = Jn * w
        A_nn, A_ns = Wn @ Jn.T, Wn @ Jts.T
        A_sn = Wts @ Jn.T
        M[:k, :k] = A_nn
        M[:k, plus:minus], M[:k, minus:slack] = A_ns, -A_ns
        M[plus:minus, :k], M[minus:slack, :k] = A_sn, -A_sn
        for i in range(s):
            M[slack + i, S[i]] = mu[S[i]]
        q[:k] = vn
        for i in range(s):
            q[plus + i], q[minus + i] = vt[S[i]], -vt[S[i]]
    else:
        shift = Wts @ (Jn.T @ normal)
        for i in range(s):
            q[plus + i], q[minus + i] = vt[S[i]] + shift[i], -(vt[S[i]] + shift[i])
            q[slack + i] = mu[S[i]] * normal[S[i]]
    M[plus:minus, plus:minus], M[plus:minus, minus:slack] = A_ss, -A_ss
    M[minus:slack, plus:minus], M[minus:slack, minus:slack] = -A_ss, A_ss
    for i in range(s):
        M[plus + i, slack + i] = M[minus + i, slack + i] = 1.0
        M[slack + i, plus + i] = M[slack + i, minus + i] = -1.0
    z = np.zeros(n)
    solved = lemke_perturbed(M, q, z, np.zeros(n, np.bool_), _COVERS) == SOLVED
    P = z[:k].copy() if free_normal else normal.copy()
    T = np.zeros(k)
    for i in range(s):
        T[S[i]] = z[plus + i] - z[minus + i]
    return solved, P, T


@njit
def frictional_impulses(Jn, Jt, w, mu, vn, vt, e, resting_speed, creep, total):
    """The velocity change (3 per moving body, ``w``'s order) of one island's impacts with
    friction (runtime.solve.friction_impulses._waves: waves of the contacts approaching faster
    than the resting speed, each compression then restitution, then a plastic pass), the
    normal impulses added to ``total``; None if an LCP has no solution."""
    dv = np.zeros(w.size)
    vn, vt = vn.copy(), vt.copy()
    for count in range(_WAVES + 1):
        wave = np.flatnonzero(vn < -resting_speed)
        final = count == _WAVES or wave.size == 0
        if final:
            if not np.any(vn < -creep):
                break
            wave = np.arange(mu.size)
        Jn_w, Jt_w = np.ascontiguousarray(Jn[wave]), np.ascontiguousarray(Jt[wave])
        phases = 1 if final else 2
        P = np.zeros(wave.size)
        for phase in range(phases):
            e_w = e[wave]
            if phase == 1 and not np.any(e_w > 0.0):
                break
            if phase == 0:
                solved, R, T = cone_lcp(Jn_w, Jt_w, w, mu[wave], vn[wave], vt[wave], P, True)
                P = R
            else:
                solved, R, T = cone_lcp(Jn_w, Jt_w, w, mu[wave], vn[wave], vt[wave], e_w * P,
                                        False)  # fmt: skip
            if not solved:
                return None
            change = w * (Jn_w.T @ R + Jt_w.T @ T)
            dv += change
            vn += Jn @ change
            vt += Jt @ change
            for i in range(wave.size):
                total[wave[i]] += R[i]
        if final:
            break
    return dv


@njit
def _impacts(jac, tangent_jac, body1, body2, v_t, mu, mass, inv_mass, fixed, modes, rate,
             restitution, recent, limits, limit, v, impulses):  # fmt: skip
    """runtime.step.compiled_frame._impacts with friction: an island with a frictional contact
    by :func:`frictional_impulses`, done again plastic if its kinetic energy would rise
    (runtime.solve.friction_impulses.resolve_frictional); False if an island is too large or
    an impulse problem has no solution."""
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
        if not np.any(mu[island] > 0.0):
            if not impact_island(jac, body1, body2, inv_mass, fixed, rate, e, resting_speed,
                                 creep, island, v, impulses):  # fmt: skip
                return False
            continue
        K = island.size
        J, moving, w = dense_rows(jac, tangent_jac, body1, body2, fixed, inv_mass,
                                  np.concatenate((island, island)), K)  # fmt: skip
        Jt, Jn = np.ascontiguousarray(J[:K]), np.ascontiguousarray(J[K:])
        args = (Jn, Jt, w, mu[island], rate[island], v_t[island])
        total = np.zeros(K)
        change = frictional_impulses(*args, e, resting_speed, creep, total)
        if change is None:
            return False
        before, after = 0.0, 0.0
        for i in range(moving.size):
            for c in range(3):
                m, u = mass[moving[i], c], v[moving[i], c]
                before += 0.5 * m * u * u
                after += 0.5 * m * (u + change[3 * i + c]) ** 2
        if after > before * (1.0 + _ENERGY_SLACK):  # Kane's paradox: done again plastic
            total[:] = 0.0
            change = frictional_impulses(*args, np.zeros(K), resting_speed, creep, total)
            if change is None:
                return False
        dv = np.zeros(v.shape)
        for i in range(moving.size):
            for c in range(3):
                dv[moving[i], c] = change[3 * i + c]
        for q in range(K):
            impulses[island[q]] += total[q]
        _add_velocity(jac, body1, body2, dv, v, rate)
    return True


@njit
def _tangent_rows(q, v, members, body1, body2, geometry, static2, tangent):
    """v_t, J_t and the tangent bias (``tangent``) at (q, v)."""
    v_t, tangent_jac, tangent_bias = tangent
    tangent_velocity_by_case(q, v, members, body1, body2, geometry, static2, v_t)
    tangent_rows_by_case(q, v, members, body1, body2, geometry, static2, tangent_jac, tangent_bias)


@njit
def _friction_rows(q, v, members, body1, body2, geometry, static2, jac, bias, tangent):
    """The normal rows' J and bias (d and d' are kept as the impulses changed them), and the
    tangential rows, at (q, v) after a velocity change."""
    rows_by_case(q, v, members, body1, body2, geometry, static2, jac, bias)
    _tangent_rows(q, v, members, body1, body2, geometry, static2, tangent)


@njit
def settle_frame(
    q, case, body1, body2, geometry, static2, held, recent, restitution, mass, inv_mass, fixed,
    free_acc, limits, tol, limit, rounds, mu, stick_speed,
    v, gap, rate, jac, bias, tangent, modes, impulses, flags, slide, forces, friction, rates, acc,
    grouping,
):  # fmt: skip
    """runtime.step.compiled_frame.settle_frame with friction: rows, classify, the impacts of
    frictionless islands, the resting forces with friction (:func:`friction_forces`), the
    press/lift rounds, then the sticking contacts' residual slip removed
    (:func:`hold_sticking`) and the forces solved again -- the general path's order
    (runtime.step.classify, runtime.step.resting, runtime.step.friction_hold). ``tangent`` =
    (v_t, J_t, tangent bias), written; ``flags``, ``slide``, ``friction``: see
    :func:`friction_forces`. Returns (ok, the kinetic energy the impulses took out); not ok
    where the general path must do it (an impact with friction, an island without friction, a
    friction LCP it cannot solve, an island larger than ``limit``)."""
    touch, hold, resting_speed, separation, creep = limits
    members = by_case(case)
    all_by_case(q, v, members, body1, body2, geometry, static2, gap, rate, jac, bias)
    _tangent_rows(q, v, members, body1, body2, geometry, static2, tangent)
    before = _kinetic(mass, fixed, v)
    classify_modes(gap, rate, touch, hold, resting_speed, separation, held, modes)
    approach = False
    for k in range(gap.size):
        if modes[k] != OPEN and rate[k] < -creep:
            approach = True
    if approach:
        was_open = modes == OPEN
        if not _impacts(jac, tangent[1], body1, body2, tangent[0], mu, mass, inv_mass, fixed,
                        modes, rate, restitution, recent, limits, limit, v, impulses):  # fmt: skip
            return False, 0.0
        classify_modes(gap, rate, touch, hold, resting_speed, separation, held, modes)
        for k in range(gap.size):
            if was_open[k]:
                modes[k] = OPEN
        _friction_rows(q, v, members, body1, body2, geometry, static2, jac, bias, tangent)
    v_t, tangent_jac, tangent_bias = tangent
    rows, grouping_rows = (jac, bias, body1, body2), (v_t, tangent_jac, tangent_bias)
    args = (mu, stick_speed, inv_mass, fixed, free_acc, modes, flags, slide, forces, friction,
            rates, acc, grouping)  # fmt: skip
    if not friction_forces(rows, grouping_rows, *args):
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
            _friction_rows(q, v, members, body1, body2, geometry, static2, jac, bias, tangent)
        if not friction_forces(rows, grouping_rows, *args):
            return False, 0.0
    dv = np.zeros(v.shape)
    order, counts = grouping[0], grouping[3]
    if hold_sticking(jac, tangent_jac, body1, body2, v_t, mu, slide, order[: counts[0]],
                     inv_mass, fixed, dv):  # fmt: skip
        _add_velocity(jac, body1, body2, dv, v, rate)
        _friction_rows(q, v, members, body1, body2, geometry, static2, jac, bias, tangent)
        if not friction_forces(rows, grouping_rows, *args):
            return False, 0.0
    return True, before - _kinetic(mass, fixed, v)


def frame(stepper, contacts, keys, q, v, margin, limits):
    """(frame, resting solution) of a scene with friction by :func:`settle_frame`, as
    runtime.step.stepper's frictionless compiled frame; None where the general path must build
    it (then it also names a failure)."""
    from runtime.collide.contact_keys import member
    from runtime.solve.friction import FrictionProblem
    from runtime.solve.friction_rows import FrictionRows
    from runtime.step.classify import Frame
    from runtime.step.stepper import RestingSolution

    m = len(contacts)
    if m == 0:
        return None
    forces_of = stepper.forces
    held = member(keys, stepper.held)
    recent = held if stepper.recent is stepper.held else member(keys, stepper.recent)
    guess = forces_of.memory.get(keys)
    flags = forces_of.bases.get(keys)
    mu = stepper.evaluator.mu(contacts)
    gap, rate, bias = np.empty(m), np.empty(m), np.empty(m)
    jac = np.empty((m, 6))
    tangent = (np.empty(m), np.empty((m, 6)), np.empty(m))
    modes = np.empty(m, np.int64)
    impulses, slide, forces, friction, rates = (np.zeros(m) for _ in range(5))
    velocities, acc = v.copy(), np.empty_like(v)
    order, offsets, labels = np.empty(m, np.int64), np.empty(m + 1, np.int64), np.empty(m, np.int64)
    counts = np.zeros(2, np.int64)
    b = stepper.bodies
    ok, loss = stepper._friction_frame_call(
        q, contacts.case, contacts.body1, contacts.body2, contacts.geometry,
        np.ascontiguousarray(stepper.fixed[contacts.body2]), held, recent, b.restitution, b.mass,
        b.inverse_mass, b.fixed, forces_of.free_acceleration,
        (limits.touch, limits.hold_gap, limits.resting_speed, limits.separation_speed,
         limits.creep_speed),
        settings.LCP_TOL, settings.DENSE_ISLAND, settings.SETTLE_ROUNDS, mu,
        float(limits.stick_speed), velocities, gap, rate, jac, bias, tangent, modes, impulses,
        flags, slide, forces, friction, rates, acc, (order, offsets, labels, counts),
    )  # fmt: skip
    if not ok:
        return None
    v_t, tangent_jac, tangent_bias = tangent
    rows = FrictionRows(gap, rate, jac, bias, contacts.body1, contacts.body2, mu, v_t,
                        tangent_jac, tangent_bias)  # fmt: skip
    found = Frame(contacts, keys, rows, modes, velocities, margin, impulses, loss)
    rest = found.resting
    count, islands = counts.tolist()
    order = order[:count]
    problem = FrictionProblem(
        contacts.take(order), np.searchsorted(rest, order), offsets[:islands].copy(),
        guess[order], labels[:count].copy(), keys[order], slide=slide[order],
        basis=flags[order],
    )  # fmt: skip
    forces_of.remember(problem)
    solution = RestingSolution(problem, acc, forces[rest], rates[rest], friction[rest])
    return found, solution
