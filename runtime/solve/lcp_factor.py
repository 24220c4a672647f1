"""The clamped set's Cholesky factor, compiled: built greedily, updated as rows enter and leave.

Why: every step of the contact-force solve (runtime.solve.lcp) solves a system with A_CC, the
block of the clamped rows C. A_CC is symmetric positive definite when C holds no redundant
(linearly dependent) row, and the solver keeps it so by refusing a row whose Schur complement
against C -- its new Cholesky pivot, the squared distance of its row from the span of C's rows
in the metric of A -- is below ``dependent`` times its diagonal. For a positive semi-definite A
that test is exact in exact arithmetic: a row of A is a combination of the rows of C exactly
when its pivot is zero. So a greedy factorization over any set G is also a rank-revealing one:
it returns a basis B of G's rows and leaves out the rows that depend on B. In floating point a
pivot is "zero" below its rounding, estimated as it is computed (:func:`trial`), and the basis
of a set is found with diagonal pivoting (:func:`factor_basis`), largest pivot first.

Storage: ``L`` (m, m) lower triangular with its first k rows and columns in use, ``rows[:k]``
the matrix rows of C in the order of L. A row enters by one forward substitution (O(k^2)) and
leaves by a rank-one update of the trailing block (O(k^2)), so a pivot of Baraff's method costs
O(k^2) instead of a fresh O(k^3) factorization.
"""

from __future__ import annotations

import math

import numpy as np

from runtime import settings
from runtime.compiled import njit

_ROUNDING = settings.LCP_PIVOT_ROUNDING


@njit
def trial(S, L, rows, k, j, row):
    """Fill ``row[:k]`` with the bottom row L would get if j joined C; return its squared pivot
    (the Schur complement S_jj - S_jC S_CC^-1 S_Cj) and the rounding that pivot may carry: an
    entry row_i divided by a small pivot L_ii inherits that pivot's relative error, ~eps
    S_ii / L_ii^2, so a row near the span of C after a near-dependent entrant looks
    independent by ~eps S_ii / L_ii^2 row_i^2 (the greedy order's trap)."""
    pivot = S[j, j]
    noise = S[j, j]
    for i in range(k):
        s = S[j, rows[i]]
        for p in range(i):
            s -= L[i, p] * row[p]
        s /= L[i, i]
        row[i] = s
        pivot -= s * s
        noise += s * s * S[rows[i], rows[i]] / (L[i, i] * L[i, i])
    return pivot, _ROUNDING * noise


@njit
def independent(S, j, pivot, noise, dependent):
    """Whether row j with this pivot is independent of C: above ``dependent`` of S_jj and above
    the pivot's rounding (a row with S_jj = 0 never is)."""
    return S[j, j] > 0.0 and pivot > dependent * S[j, j] + noise


@njit
def add(L, rows, k, j, row, pivot):
    """Append row j to C (with ``row`` and ``pivot`` from :func:`trial`); return the new k."""
    for p in range(k):
        L[k, p] = row[p]
    L[k, k] = math.sqrt(pivot)
    rows[k] = j
    return k + 1


@njit
def remove(L, rows, k, p, work):
    """Delete the p-th row of C: fold L's column p into the trailing block (a stable rank-one
    update, L L^T + x x^T = L' L'^T) and shift the rows below up. Returns the new k."""
    n = k - p - 1
    x = work[:n]
    for i in range(n):
        x[i] = L[p + 1 + i, p]
    for i in range(n):  # Givens-style update of the trailing block rows p+1..k-1
        ii = p + 1 + i
        lii = L[ii, p + 1 + i]
        r = math.hypot(lii, x[i])
        c, s = r / lii, x[i] / lii
        L[ii, p + 1 + i] = r
        for t in range(i + 1, n):
            tt = p + 1 + t
            L[tt, p + 1 + i] = (L[tt, p + 1 + i] + s * x[t]) / c
            x[t] = c * x[t] - s * L[tt, p + 1 + i]
    for i in range(p, k - 1):  # shift: row i+1 becomes row i, column p is dropped
        for t in range(p):
            L[i, t] = L[i + 1, t]
        for t in range(p, i + 1):
            L[i, t] = L[i + 1, t + 1]
        rows[i] = rows[i + 1]
    for t in range(k):
        L[k - 1, t] = 0.0
    return k - 1


@njit
def solve(L, k, rhs, out):
    """out[:k] = (L L^T)^-1 rhs[:k] by a forward and a backward substitution."""
    for i in range(k):
        s = rhs[i]
        for p in range(i):
            s -= L[i, p] * out[p]
        out[i] = s / L[i, i]
    for i in range(k - 1, -1, -1):
        s = out[i]
        for p in range(i + 1, k):
            s -= L[p, i] * out[p]
        out[i] = s / L[i, i]


@njit
def factor_basis(S, candidates, count, L, rows, dependent):
    """A basis of the rows ``candidates[:count]`` and the factor of its block: Cholesky with
    diagonal pivoting -- at each step the candidate of largest relative Schur complement --
    stopping when every remaining one depends on those taken (rank-revealing: the largest
    pivot first keeps the rounding of the later ones small). Returns k, the basis in
    ``rows[:k]`` with L (k x k) its factor in that order."""
    columns = np.empty((count, count))
    schur, noise = np.empty(count), np.empty(count)
    taken = np.zeros(count, np.bool_)
    for c in range(count):
        schur[c] = S[candidates[c], candidates[c]]
        noise[c] = schur[c]
    k = 0
    while k < count:
        best, at = -1.0, -1
        for c in range(count):  # ties to the lowest row: the basis ignores the listing order
            j = candidates[c]
            if taken[c] or not S[j, j] > 0.0:
                continue
            ratio = schur[c] / S[j, j]
            if ratio > best or (ratio == best and j < candidates[at]):
                best, at = ratio, c
        if at < 0 or not independent(
            S, candidates[at], schur[at], _ROUNDING * noise[at], dependent
        ):
            break
        taken[at] = True
        j = candidates[at]
        pivot = math.sqrt(schur[at])
        for p in range(k):
            L[k, p] = columns[at, p]
        L[k, k] = pivot
        rows[k] = j
        weight = S[j, j] / schur[at]
        for c in range(count):
            if not taken[c]:
                s = S[candidates[c], j]
                for p in range(k):
                    s -= columns[c, p] * L[k, p]
                s /= pivot
                columns[c, k] = s
                schur[c] -= s * s
                noise[c] += s * s * weight
        k += 1
    return k


@njit
def refactor(S, L, rows, k, scratch):
    """A fresh factorization of S_CC (to shed the rounding of many updates); keeps the old
    factor and returns False if the fresh one meets a non-positive pivot."""
    for i in range(k):
        for t in range(i + 1):
            s = S[rows[i], rows[t]]
            for p in range(t):
                s -= scratch[i, p] * scratch[t, p]
            if t == i:
                if not s > 0.0:
                    return False
                scratch[i, i] = math.sqrt(s)
            else:
                scratch[i, t] = s / scratch[t, t]
    for i in range(k):
        for t in range(i + 1):
            L[i, t] = scratch[i, t]
    return True


@njit
def cholesky_solve(H, rhs, out, scratch):
    """out = H^-1 rhs for a small symmetric positive definite H (n = len(rhs)); False if a
    pivot is not positive."""
    if not cholesky(H, rhs.size, scratch):
        return False
    solve(scratch, rhs.size, rhs, out)
    return True


@njit
def cholesky(H, n, scratch):
    """scratch[:n, :n] = L with L L^T = H[:n, :n] (its lower triangle), for a symmetric positive
    definite H; False if a pivot is not positive. Factor once, then :func:`solve` for each
    right-hand side (an inverse: n solves, not n factorizations)."""
    for i in range(n):
        for t in range(i + 1):
            s = H[i, t]
            for p in range(t):
                s -= scratch[i, p] * scratch[t, p]
            if t == i:
                if not s > 0.0:
                    return False
                scratch[i, i] = math.sqrt(s)
            else:
                scratch[i, t] = s / scratch[t, t]
    return True


def empty_factor(m: int) -> tuple[np.ndarray, np.ndarray]:
    """(L, rows) for up to m clamped rows (for tests and Python callers)."""
    return np.zeros((m, m)), np.zeros(m, np.int64)
