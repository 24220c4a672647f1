"""The compiled dense contact-force solver: warm start, pivoting, fallbacks, least norm.

    status = solve_dense(A, b, joint, guess, tol, f_out, clamped_out)

A (m, m) float64 C-contiguous, symmetric positive semi-definite (1/kg); b (m,) float64 (m/s^2);
joint, guess (m,) bool: bilateral rows, and the clamped set of the previous solve (all False:
a cold start); tol: the relative row tolerance (<= 0: settings.LCP_TOL). Writes f_out (m,)
float64 (N) and clamped_out (m,) bool -- the held rows, a_i = 0 (joints and touching contacts),
the guess for the next solve. Returns OK (0), INFEASIBLE (1), STUCK (2), NOT_FINITE (3) or
BAD_INPUT (4) and never raises; after a failure f_out is the best point found and clamped_out
marks the rows to blame. No Python objects: callable from Python and from compiled code.

Why this order, cheapest first:
1. the guess (the engine solves at every RK stage and step, and the clamped set rarely
   changes): factor S_GG once, solve, check the conditions -- a hit costs one small
   factorization;
2. a miss hands its valid part (the guessed rows with f >= 0) to Baraff's pivoting
   (runtime.solve.lcp_baraff), which needs only a few pivots from there;
3. if pivoting is stuck (cycling, lost accuracy): pivoting again from scratch with a fresh
   factorization at every pivot, then projected Gauss-Seidel from the best point with its
   clamped set solved exactly;
4. the least-norm forces over the held rows when some are redundant (runtime.solve.lcp_minnorm),
   kept only if they pass the same check.
Everything runs on S = D A D, D = diag(A)^-1/2 (unit diagonal), so no threshold depends on the
units; rows with A_ii = 0 (no force moves them) are checked on their own.
"""

from __future__ import annotations

import math

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_factor as fac
from runtime.solve.lcp_baraff import (
    BAD_INPUT,
    CLAMPED,
    FREE,
    INFEASIBLE,
    MIN_NORM,
    N_COUNTS,
    NOT_FINITE,
    OK,
    PATH,
    STUCK,
    baraff,
    is_solution,
    refine,
    residual,
)
from runtime.solve.lcp_minnorm import DONE, FAILED, least_norm, least_norm_factored

__all__ = ["solve_dense", "solve_dense_counted", "OK", "INFEASIBLE", "STUCK", "NOT_FINITE"]
__all__ += ["BAD_INPUT", "N_COUNTS"]

WARM_HIT, PIVOTED, PIVOTED_FRESH, POLISHED, SINGLE = 1, 2, 3, 4, 5  # counts[PATH]
_DEPENDENT, _NOISE = settings.LCP_DEPENDENT, settings.LCP_NOISE
_ZERO_ROW, _SWEEPS, _TOL = settings.LCP_ZERO_ROW, settings.LCP_PGS_SWEEPS, settings.LCP_TOL
_SHARP, _REDUNDANT = settings.LCP_SHARP, settings.LCP_REDUNDANT
_SYMMETRIC = settings.LCP_SYMMETRY


@njit
def solve_dense(A, b, joint, guess, tol, f_out, clamped_out):
    """See the module docstring."""
    counts = np.zeros(N_COUNTS, np.int64)
    return solve_dense_counted(A, b, joint, guess, tol, f_out, clamped_out, counts)


@njit
def solve_dense_counted(A, b, joint, guess, tol, f_out, clamped_out, counts):
    """solve_dense, also counting drives, pivots, fresh factorizations, the path taken (1 warm
    hit, 2 pivoting, 3 pivoting afresh, 4 polished, 5 single row) and the least-norm stage
    (0 not needed, 1 done, 2 failed: the forces are a valid solution, not the least-norm one)."""
    budgets = np.zeros(2)
    return solve_dense_limited(A, b, joint, guess, tol, f_out, clamped_out, counts, budgets)


@njit
def solve_dense_limited(A, b, joint, guess, tol, f_out, clamped_out, counts, budgets):
    """solve_dense_counted with pivot budgets for the first and the fresh pivoting attempt
    (0: none): tests use them to drive the solve down its fallback chain."""
    m = b.size
    if A.shape[0] != m or A.shape[1] != m:
        return BAD_INPUT
    if joint.size != m or guess.size != m or f_out.size != m or clamped_out.size != m:
        return BAD_INPUT
    f_out[:] = 0.0
    clamped_out[:] = False
    if not tol > 0.0:
        tol = _TOL
    top, b_max = 0.0, 0.0
    for i in range(m):
        if not (np.isfinite(b[i]) and A[i, i] >= 0.0):
            return BAD_INPUT
        top = max(top, A[i, i])
        b_max = max(b_max, abs(b[i]))
    d = np.empty(m)
    for i in range(m):
        d[i] = 1.0 / math.sqrt(A[i, i]) if A[i, i] > _ZERO_ROW * top else 0.0
    S = np.empty((m, m))
    for i in range(m):
        for j in range(m):
            if not np.isfinite(A[i, j]):
                return BAD_INPUT
            if abs(A[i, j] - A[j, i]) > _SYMMETRIC * math.sqrt(A[i, i] * A[j, j]):
                return BAD_INPUT
            S[i, j] = 0.5 * d[i] * d[j] * (A[i, j] + A[j, i])
            if abs(S[i, j]) > 1.0 + _SYMMETRIC:  # |A_ij| <= sqrt(A_ii A_jj) for PSD A
                return BAD_INPUT
    for i in range(m):  # rows no force moves: a_i = b_i whatever f is
        if d[i] == 0.0:
            if b[i] < -tol * b_max or (joint[i] and b[i] > tol * b_max):
                clamped_out[i] = True
                return INFEASIBLE
            clamped_out[i] = joint[i] or b[i] <= tol * b_max
    if m == 1:  # one row: f = -b / A (unscaled, so A f + b is 0 exactly), never pulling
        counts[PATH] = SINGLE
        if d[0] > 0.0:
            f_out[0] = -b[0] / A[0, 0] if joint[0] or b[0] < 0.0 else 0.0
            a = A[0, 0] * f_out[0] + b[0]
            clamped_out[0] = joint[0] or abs(a) <= tol * (abs(b[0]) + abs(A[0, 0] * f_out[0]))
        return OK
    bs, inv_w, fs = d * b, np.empty(m), np.zeros(m)
    for i in range(m):
        inv_w[i] = A[i, i] / top if top > 0.0 else 0.0
    status = _solve_scaled(S, bs, joint, guess, tol, inv_w, fs, clamped_out, counts, budgets)
    for i in range(m):
        f_out[i] = d[i] * fs[i]
    return status


@njit
def _solve_scaled(S, b, joint, guess, tol, inv_w, f, held, counts, budgets):
    """The chain of the module docstring on the scaled problem (rows with S_ii = 0 are inert)."""
    m = b.size
    a, tol_a = np.empty(m), np.empty(m)
    sharp = min(tol, _SHARP)  # what pivoting and a warm hit aim for; tol is what is accepted
    tune = np.array((_DEPENDENT, _NOISE, 0.0, budgets[0]))
    L, rows = np.empty((m, m)), np.empty(m, np.int64)
    state, culprit = np.zeros(m, np.int8), np.zeros(m, np.bool_)
    k, status, settled = 0, STUCK, False
    if np.any(guess):
        k, hit, settled = _warm(S, b, joint, guess, sharp, tol, inv_w, f, L, rows, state, a, tol_a)
        if hit:
            status = OK
            counts[PATH] = WARM_HIT
    if status != OK:
        counts[PATH] = PIVOTED
        status, k = _pivot(S, b, joint, sharp, tol, tune, f, state, L, rows, k, culprit, counts)
    if status != OK:
        first, best, blame = status, f.copy(), culprit.copy()
        counts[PATH] = PIVOTED_FRESH
        tune[2], tune[3] = 1.0, budgets[1]  # a fresh factorization for every direction
        f[:] = 0.0
        state[:] = FREE
        culprit[:] = False
        status, k = _pivot(S, b, joint, sharp, tol, tune, f, state, L, rows, 0, culprit, counts)
        if status != OK:
            counts[PATH] = POLISHED
            f[:] = best
            pgs(S, b, joint, f, _SWEEPS)
            support = joint | (f > 0.0)
            k, hit, settled = _warm(
                S, b, joint, support, sharp, tol, inv_w, f, L, rows, state, a, tol_a
            )
            if hit or is_solution(S, b, joint, f, tol, a, tol_a):
                status = OK
        if status != OK:
            f[:] = best
            for i in range(m):
                held[i] = held[i] or blame[i]
            return first
    residual(S, b, f, tol, a, tol_a)
    members = np.empty(m, np.int64)
    count = 0
    for i in range(m):
        if S[i, i] > 0.0 and (joint[i] or f[i] > 0.0 or abs(a[i]) <= tol_a[i]):
            members[count] = i
            count += 1
    same = settled and counts[PATH] == WARM_HIT  # a hit over the same set: no least-norm stage
    for c in range(count):
        same = same and (guess[members[c]] or joint[members[c]])
    if count > 1 and not same:
        trial = np.empty(m)
        outcome = _least_norm(S, b, joint, inv_w, members, count, tol, trial)
        counts[MIN_NORM] = outcome
        if outcome == DONE:
            f[:] = trial
            residual(S, b, f, tol, a, tol_a)
    for i in range(m):
        held[i] = held[i] or (S[i, i] > 0.0 and (joint[i] or f[i] > 0.0 or abs(a[i]) <= tol_a[i]))
    return OK


@njit
def _pivot(S, b, joint, sharp, tol, tune, f, state, L, rows, k, culprit, counts):
    """Baraff's method from the given state, driving every row violated beyond ``sharp``,
    refined, and accepted within ``tol``: (status, k)."""
    status, k = baraff(S, b, joint, sharp, tune, f, state, L, rows, k, culprit, counts)
    if status == OK:
        refine(S, b, f, L, rows, k)
    a, tol_a = np.empty(b.size), np.empty(b.size)
    trial = f.copy()
    if is_solution(S, b, joint, trial, tol, a, tol_a):  # (also when only ``sharp`` fails)
        f[:] = trial
        return OK, k
    return (STUCK if status == OK else status), k  # accuracy lost: let the fallbacks try


@njit
def _warm(S, b, joint, guess, sharp, tol, inv_w, f, L, rows, state, a, tol_a):
    """Try the guessed clamped set: factor S_GG (joints first; dependent rows left out), solve,
    check -- with redundant rows in G, the least-norm forces over G (what the last solve
    returned), since a basic solution over an arbitrary basis may need a negative force. On a
    miss, leave a valid state for pivoting: the guessed rows with f >= 0, dropping the most
    negative force and solving again until none is negative. A hit meets ``sharp`` (the
    least-norm forces: ``tol``, as the solve that returned them). Returns (k, hit, settled):
    settled when the hit's forces are already the least-norm ones over G (G has no
    near-redundant row, or they are its least-norm forces)."""
    m = b.size
    candidates = np.empty(m, np.int64)
    n = 0
    for i in range(m):
        if joint[i]:
            candidates[n] = i
            n += 1
    for i in range(m):
        if guess[i] and not joint[i]:
            candidates[n] = i
            n += 1
    work = np.empty(m)
    k = fac.factor_basis(S, candidates, n, L, rows, _REDUNDANT)
    unique = k == n
    _solve_clamped(S, b, f, L, rows, k)
    if not unique:  # some guessed rows (nearly) depend on others: the least norm, as last time
        # a off the guessed rows is the same for every solution over them (A is PSD), so a
        # basic one (over the basis of the least-norm stage) tells whether the guess can still
        # hold; only then is its least norm sought (over a set that no longer holds, the
        # least-norm stage's Newton method runs out its 100 steps: 9 ms of a landing pile's
        # 88-row island, where pivoting takes 1)
        if _holds_outside(S, b, f, guess, joint, tol, a, tol_a):
            outcome = least_norm_factored(S, b, joint, inv_w, candidates, n, L, rows, k, tol, f)
            if outcome == FAILED:  # as _least_norm: then with only the truly dependent rows
                outcome = least_norm(S, b, joint, inv_w, candidates, n, _DEPENDENT, tol, f)
            if outcome == DONE:
                return k, True, True
        k = fac.factor_basis(S, candidates, n, L, rows, _DEPENDENT)  # for pivoting from here
        _solve_clamped(S, b, f, L, rows, k)
    trial = f.copy()
    if is_solution(S, b, joint, trial, sharp, a, tol_a):
        f[:] = trial
        _clamp(state, rows, k)
        return k, True, unique
    while True:
        worst, at = 0.0, -1
        for c in range(k):
            i = rows[c]
            if not joint[i] and f[i] < worst:
                worst, at = f[i], c
        if at < 0:
            break
        k = fac.remove(L, rows, k, at, work)
        _solve_clamped(S, b, f, L, rows, k)
    _clamp(state, rows, k)
    return k, False, False


@njit
def _holds_outside(S, b, f, guess, joint, tol, a, tol_a):
    """Whether a = S f + b >= 0 within the row tolerances on every row outside the guess."""
    residual(S, b, f, tol, a, tol_a)
    for i in range(b.size):
        if not (guess[i] or joint[i]) and a[i] < -tol_a[i]:
            return False
    return True


@njit
def _least_norm(S, b, joint, inv_w, held, count, tol, f_out):
    """The least-norm forces over the held rows (runtime.solve.lcp_minnorm), first with rows
    within settings.LCP_REDUNDANT of the others' span counted as redundant -- near-redundant
    pairs otherwise pin huge opposed forces that the tolerance cannot tell from small ones --
    then, if that misses the tolerance, with only the truly dependent ones."""
    outcome = least_norm(S, b, joint, inv_w, held, count, _REDUNDANT, tol, f_out)
    if outcome == FAILED:
        outcome = least_norm(S, b, joint, inv_w, held, count, _DEPENDENT, tol, f_out)
    return outcome


@njit
def _clamp(state, rows, k):
    """State: the k rows of the factor clamped, every other row unprocessed."""
    state[:] = FREE
    for c in range(k):
        state[rows[c]] = CLAMPED


@njit
def _solve_clamped(S, b, f, L, rows, k):
    """f = 0 off C and S_CC f_C = -b_C (refined), by the factor of C."""
    rhs, x = np.empty(k), np.empty(k)
    for c in range(k):
        rhs[c] = -b[rows[c]]
    fac.solve(L, k, rhs, x)
    f[:] = 0.0
    for c in range(k):
        f[rows[c]] = x[c]
    refine(S, b, f, L, rows, k)


@njit
def pgs(S, b, joint, f, sweeps):
    """Projected Gauss-Seidel sweeps on the scaled problem, in place from f (a fallback that
    only has to find the clamped set; the caller solves that set exactly)."""
    m = b.size
    a = b.copy()
    for j in range(m):
        if f[j] != 0.0:
            for i in range(m):
                a[i] += S[i, j] * f[j]
    for _ in range(sweeps):
        for i in range(m):
            if S[i, i] > 0.0:
                fi = f[i] - a[i] / S[i, i]
                if not joint[i] and fi < 0.0:
                    fi = 0.0
                step = fi - f[i]
                if step != 0.0:
                    for t in range(m):
                        a[t] += step * S[t, i]
                    f[i] = fi
