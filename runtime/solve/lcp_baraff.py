"""Baraff's pivoting method for the frictionless contact LCP, compiled, on the scaled problem.

D. Baraff, "Fast Contact Force Computation for Nonpenetrating Rigid Bodies", SIGGRAPH 1994:
the procedures compute-forces, drive-to-zero, fdirection and maxstep. Rows are made valid one at
a time; processed rows are clamped, C (a_i = 0, f_i >= 0), or not clamped, NC (f_i = 0,
a_i >= 0). To fix a row d: Delta f_d = 1 (-1 for a joint with a_d > 0), Delta f_C solves
S_CC x = -S_Cd, so a stays 0 on C while a_d moves at the rate of d's Schur complement; the step
is the largest that keeps the invariants -- a_d reaching 0 (d joins C), a clamped force falling
to 0 (it moves to NC), a not-clamped a_i falling to 0 (it joins C).

Why it never fails on a solvable positive semi-definite problem: a row that depends on C (zero
Schur complement, a redundant contact) also has Delta a = 0 (for PSD S), so it never limits a
step and never joins C, and S_CC stays nonsingular (runtime.solve.lcp_factor refuses such rows
explicitly in floating point). If nothing limits a step, then S Delta f = 0 with Delta f >= 0 on
contacts and Delta f.b = Delta f.a < 0, a certificate that no valid force exists: the solver
reports INFEASIBLE and marks the rows of the certificate. The method starts from any state that
keeps the invariants, which is how a warm start that missed hands over (runtime.solve.lcp_dense).

Floating point: Delta f and Delta a entries at rounding level (``noise``) count as 0; a direction
whose a_C is not 0 to rounding triggers a fresh factorization; a run of zero-length steps longer
than the problem (a degenerate cycle) or too many pivots ends with STUCK, for the fallbacks.
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_factor as fac

_FLOOR = settings.LCP_FLOOR
OK, INFEASIBLE, STUCK, NOT_FINITE, BAD_INPUT = 0, 1, 2, 3, 4  # solve_dense's status codes
FREE, CLAMPED, NOT_CLAMPED = 0, 1, 2  # row states: unprocessed, C, NC
DRIVES, PIVOTS, REFACTORS, PATH, MIN_NORM, N_COUNTS = 0, 1, 2, 3, 4, 5  # entries of ``counts``


@njit
def residual(S, b, f, tol, a, tol_a):
    """a = S f + b and each row's tolerance tol * (sum_j |S_ij f_j| + |b_i|) + the floor."""
    m = b.size
    floor = tolerance_floor(b, f)
    for i in range(m):
        s = b[i]
        size = abs(b[i])
        for j in range(m):
            if f[j] != 0.0:
                t = S[i, j] * f[j]
                s += t
                size += abs(t)
        a[i] = s
        tol_a[i] = tol * size + floor


@njit
def tolerance_floor(b, f):
    """settings.LCP_FLOOR of the largest scaled b or f: rounding that a row's own terms may not
    show (b built from terms that cancelled, forces moved elsewhere by the least-norm stage)."""
    top = 0.0
    for i in range(b.size):
        top = max(top, abs(b[i]), abs(f[i]))
    return _FLOOR * top


@njit
def is_solution(S, b, joint, f, tol, a, tol_a):
    """Clip contact forces at 0, then check every LCP condition to the row tolerances."""
    for i in range(b.size):
        if not joint[i] and f[i] < 0.0:
            f[i] = 0.0
        if not np.isfinite(f[i]):
            return False
    residual(S, b, f, tol, a, tol_a)
    for i in range(b.size):
        if joint[i] or f[i] > 0.0:
            if not abs(a[i]) <= tol_a[i]:
                return False
        elif not a[i] >= -tol_a[i]:
            return False
    return True


@njit
def _try_clamp(S, state, L, rows, k, j, dependent, row, scratch, counts, fresh):
    """Add j to C unless its Schur complement says it depends on C; (added, k, fresh)."""
    pivot, noise = fac.trial(S, L, rows, k, j, row)
    if not fac.independent(S, j, pivot, noise, dependent) and not fresh:
        if fac.refactor(S, L, rows, k, scratch):  # the updated factor may have drifted
            counts[REFACTORS] += 1
            fresh = True
            pivot, noise = fac.trial(S, L, rows, k, j, row)
    if not fac.independent(S, j, pivot, noise, dependent):
        return False, k, fresh
    k = fac.add(L, rows, k, j, row, pivot)
    state[j] = CLAMPED
    return True, k, False


@njit
def _direction(S, L, rows, k, d, sigma, noise, df, da, rhs, x, scratch, counts, always_fresh):
    """fdirection: Delta f (Delta f_d = sigma, S_CC Delta f_C = -sigma S_Cd) and Delta a."""
    m = df.size
    for attempt in range(2):
        if k > 0 and (always_fresh or attempt == 1):
            if fac.refactor(S, L, rows, k, scratch):
                counts[REFACTORS] += 1
        df[:] = 0.0
        df[d] = sigma
        for i in range(k):
            rhs[i] = -sigma * S[rows[i], d]
        fac.solve(L, k, rhs, x)
        big = 1.0
        for i in range(k):
            df[rows[i]] = x[i]
            big = max(big, abs(x[i]))
        for i in range(m):
            s = sigma * S[i, d]
            for c in range(k):
                s += S[i, rows[c]] * x[c]
            da[i] = s
        drift = 0.0
        for c in range(k):
            drift = max(drift, abs(da[rows[c]]))
        if drift <= noise * big or always_fresh:
            break
    for c in range(k):
        da[rows[c]] = 0.0  # exact in exact arithmetic; keep rounding out of a_C


@njit
def _max_step(f, a, df, da, d, joint, state, noise_a, noise_f):
    """maxstep: the largest step keeping the invariants, and the row limiting it (-1: none)."""
    best_s, best_j = np.inf, -1
    if da[d] * df[d] > noise_a:  # a_d moves toward 0
        best_s, best_j = max(-a[d] / da[d], 0.0), d
    for i in range(f.size):
        if state[i] == CLAMPED and not joint[i] and df[i] < -noise_f:
            s = max(f[i], 0.0) / -df[i]
        elif state[i] == NOT_CLAMPED and da[i] < -noise_a:
            s = max(a[i], 0.0) / -da[i]
        else:
            continue
        if s < best_s:
            best_s, best_j = s, i
    return best_s, best_j


@njit
def _drive_to_zero(
    S, joint, d, a, f, state, L, rows, k, tune, limit, culprit, counts, work, scratch
):
    """Move f along fdirection, swapping rows between C and NC, until a_d = 0 (STUCK when
    counts[PIVOTS] reaches ``limit``)."""
    dependent, noise, always_fresh = tune[0], tune[1], tune[2] > 0.0
    m = f.size
    df, da, rhs, x, row = work[0], work[1], work[2], work[3], work[4]
    sigma = 1.0 if a[d] < 0.0 else -1.0
    fresh = False
    idle = 0
    for _ in range(10 * m + 10):
        if counts[PIVOTS] >= limit:
            return STUCK, k
        counts[PIVOTS] += 1
        _direction(S, L, rows, k, d, sigma, noise, df, da, rhs, x, scratch, counts, always_fresh)
        for i in range(m):
            if not (np.isfinite(df[i]) and np.isfinite(da[i])):
                culprit[d] = True
                return NOT_FINITE, k
        noise_f = noise * max(1.0, np.max(np.abs(df)))
        leaving = False
        while True:  # a refused entrant depends on C: it has Delta a = 0
            s, j = _max_step(f, a, df, da, d, joint, state, noise_f, noise_f)
            if j < 0:
                culprit[d] = True
                for c in range(k):
                    if abs(df[rows[c]]) > noise_f:
                        culprit[rows[c]] = True
                return INFEASIBLE, k
            leaving = state[j] == CLAMPED
            if leaving:
                break
            added, k, fresh = _try_clamp(
                S, state, L, rows, k, j, dependent, row, scratch, counts, fresh
            )
            if added:
                break
            da[j] = 0.0
        for i in range(m):
            f[i] += s * df[i]
            a[i] += s * da[i]
        idle = idle + 1 if s == 0.0 else 0
        if idle > 2 * m + 10:  # a cycle of degenerate pivots
            return STUCK, k
        if leaving:  # f_j fell to 0: C -> NC
            f[j] = 0.0
            p = 0
            while rows[p] != j:
                p += 1
            k = fac.remove(L, rows, k, p, x)
            state[j] = NOT_CLAMPED
            fresh = False
        else:  # a_j reached 0: NC -> C, or j = d and the drive is done
            a[j] = 0.0
            if j == d:
                return OK, k
    return STUCK, k


@njit
def baraff(S, b, joint, tol, tune, f, state, L, rows, k, culprit, counts):
    """compute-forces from the state (f, state, the factor of C in L, rows, k): drive violated
    joints, then violated contacts, one at a time. ``tune`` = (dependent, noise, always_fresh,
    pivot budget: <= 0 for none).
    Returns (status, k); on INFEASIBLE ``culprit`` marks the rows of the certificate."""
    m = b.size
    a, tol_a = np.empty(m), np.empty(m)
    work = np.empty((5, m))
    scratch = np.empty((m, m))
    residual(S, b, f, tol, a, tol_a)
    limit = counts[PIVOTS] + int(tune[3]) if tune[3] > 0 else np.iinfo(np.int64).max
    fresh = False
    for j in range(m):  # satisfied joints are clamped at once: they stay satisfied
        if joint[j] and state[j] != CLAMPED and abs(a[j]) <= tol_a[j]:
            _, k, fresh = _try_clamp(
                S, state, L, rows, k, j, tune[0], work[4], scratch, counts, fresh
            )
    for _ in range(4 * m + 4):
        residual(S, b, f, tol, a, tol_a)  # fresh each drive: no drift of a
        d, worst = -1, 0.0
        for i in range(m):  # joints first, the most violated
            if joint[i] and state[i] != CLAMPED and abs(a[i]) > tol_a[i] and abs(a[i]) > worst:
                d, worst = i, abs(a[i])
        if d < 0:
            for i in range(m):  # then contacts, the most violated (S has a unit diagonal)
                if not joint[i] and state[i] != CLAMPED and a[i] < -tol_a[i] and -a[i] > worst:
                    d, worst = i, -a[i]
        if d < 0:
            return OK, k
        counts[DRIVES] += 1
        state[d] = FREE
        status, k = _drive_to_zero(
            S, joint, d, a, f, state, L, rows, k, tune, limit, culprit, counts, work, scratch
        )
        if status != OK:
            return status, k
    return STUCK, k


@njit
def refine(S, b, f, L, rows, k):
    """Iterative refinement of f on C with the factor (two rounds at most, kept only while
    the residual on C falls): the solution's a_C down to rounding of the sums."""
    r, x = np.empty(k), np.empty(k)
    before = _clamped_residual(S, b, f, rows, k, r)
    for _ in range(2):
        if k == 0 or before == 0.0:
            return
        fac.solve(L, k, r, x)
        old = f.copy()
        for c in range(k):
            f[rows[c]] -= x[c]
        after = _clamped_residual(S, b, f, rows, k, r)
        if not after < before:
            f[:] = old
            return
        before = after


@njit
def _clamped_residual(S, b, f, rows, k, r):
    """r = (S f + b)_C; returns max |r|."""
    worst = 0.0
    for c in range(k):
        i = rows[c]
        s = b[i]
        for j in range(f.size):
            if f[j] != 0.0:
                s += S[i, j] * f[j]
        r[c] = s
        worst = max(worst, abs(s))
    return worst
