"""The sparse path of the contact-force solve, for islands of hundreds to thousands of contacts.

Why: a pile's A = J M^-1 J^T has a handful of non-zeros per row (a contact couples only to the
contacts of its two bodies), so a dense O(m^3) factorization wastes almost all of its work. Here
the rows are put in reverse Cuthill-McKee order (scipy.sparse.csgraph), which gathers a pile's
non-zeros into a narrow envelope (profile), and the clamped block is factored within that
envelope, O(m * bandwidth^2), by a compiled skyline Cholesky that leaves out dependent rows
exactly as the dense factor does (runtime.solve.lcp_factor): a row whose pivot falls below
settings.LCP_DEPENDENT of its diagonal is redundant and is dropped, so redundant contacts never
make the factor singular. scipy's splu cannot do that (it fails or returns garbage on a singular
block), and the envelope keeps everything in flat arrays that compiled code can walk.

The clamped set is found by block principal pivoting (the primal-dual active-set method):
solve on the current set G; drop contacts with f < 0, add those outside with a < 0; repeat.
Warm-started from the previous set it usually ends after one factorization. A set that stops
shrinking its violations for three rounds switches to one exchange per round (Murty's rule, the
Judice-Pires safeguard); if that too fails, the island goes to the dense compiled solver
(runtime.solve.lcp_dense), warm-started from the best set. The least-norm policy for redundant
rows is the dense path's (runtime.solve.lcp_minnorm), on the same basis/dependent split.
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_dense
from runtime.solve.lcp_baraff import INFEASIBLE, MIN_NORM, OK, STUCK, _floor
from runtime.solve.lcp_minnorm import DONE, FAILED, UNIQUE, dual_newton

_ROUNDS = 50  # block pivoting rounds before the dense fallback (a warm start needs 1-3)
_PATIENCE = 3  # rounds without fewer violations before one exchange per round


@njit
def envelope(indptr, indices, data):
    """The lower envelope of a symmetric CSR matrix: first column fc[i] of row i, offsets and
    the values S[i, fc[i]..i] of each row, packed (the factor has the same envelope)."""
    m = indptr.size - 1
    first = np.arange(m)
    for i in range(m):
        for p in range(indptr[i], indptr[i + 1]):
            first[i] = min(first[i], indices[p])
    offset = np.zeros(m + 1, np.int64)
    for i in range(m):
        offset[i + 1] = offset[i] + i - first[i] + 1
    values = np.zeros(offset[m])
    for i in range(m):
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j <= i:
                values[offset[i] + j - first[i]] += data[p]
    return first, offset, values


@njit
def factor(first, offset, values, member, dependent, L, kept):
    """Skyline Cholesky of S over the rows in ``member``, leaving out rows that depend on the
    rows kept before them (and rows with S_ii = 0): such a row gets an identity row in L and a
    zero column. Returns the number of rows kept."""
    m = first.size
    count = 0
    for i in range(m):
        base, lo = offset[i], first[i]
        diag = values[base + i - lo]
        kept[i] = False
        for j in range(lo, i):
            L[base + j - lo] = 0.0
        L[base + i - lo] = 1.0
        if not member[i] or not diag > 0.0:
            continue
        pivot = diag
        for j in range(lo, i):
            if not kept[j]:
                continue
            bj, lj = offset[j], first[j]
            s = values[base + j - lo]
            for p in range(max(lo, lj), j):
                s -= L[base + p - lo] * L[bj + p - lj]
            s /= L[bj + j - lj]
            L[base + j - lo] = s
            pivot -= s * s
        if pivot > dependent * diag:
            L[base + i - lo] = math.sqrt(pivot)
            kept[i] = True
            count += 1
        else:
            for j in range(lo, i):
                L[base + j - lo] = 0.0
    return count


@njit
def solve(first, offset, L, rhs, x):
    """x = (L L^T)^-1 rhs (rhs must be 0 at rows left out: x is 0 there)."""
    m = first.size
    for i in range(m):
        base, lo = offset[i], first[i]
        s = rhs[i]
        for p in range(lo, i):
            s -= L[base + p - lo] * x[p]
        x[i] = s / L[base + i - lo]
    for i in range(m - 1, -1, -1):
        base, lo = offset[i], first[i]
        x[i] /= L[base + i - lo]
        for p in range(lo, i):
            x[p] -= L[base + p - lo] * x[i]


@njit
def residual(indptr, indices, data, b, f, tol, a, tol_a):
    """a = S f + b and each row's tolerance tol * (sum_j |S_ij f_j| + |b_i|) + the floor
    (runtime.solve.lcp_baraff.residual), S in CSR."""
    floor = _floor(b, f)
    for i in range(b.size):
        s, size = b[i], abs(b[i])
        for p in range(indptr[i], indptr[i + 1]):
            t = data[p] * f[indices[p]]
            s += t
            size += abs(t)
        a[i] = s
        tol_a[i] = tol * size + floor


@njit
def _violations(joint, member, kept, f, a, tol_a, out):
    """Mark the rows to exchange: held contacts with f < 0, others with a < 0, and dependent
    held rows whose a is not 0 (their set is inconsistent). Returns their number."""
    n = 0
    for i in range(f.size):
        if member[i] and not joint[i] and kept[i] and f[i] < 0.0:
            bad = True
        elif not member[i] and not joint[i] and a[i] < -tol_a[i]:
            bad = True
        else:
            bad = member[i] and not kept[i] and abs(a[i]) > tol_a[i] and (joint[i] or a[i] < 0)
        out[i] = bad
        n += bad
    return n


@njit
def pivot_blocks(indptr, indices, data, first, offset, values, b, joint, member, tol, counts, f):
    """Block principal pivoting from ``member`` (updated in place), exchanging rows violated
    beyond settings.LCP_SHARP and accepting within ``tol``; f on success. Status."""
    m = b.size
    L = np.empty(values.size)
    kept, bad = np.zeros(m, np.bool_), np.zeros(m, np.bool_)
    a, tol_a, rhs = np.empty(m), np.empty(m), np.empty(m)
    best, idle = m + 1, 0
    sharp = min(tol, settings.LCP_SHARP)
    for _ in range(_ROUNDS):
        counts[1] += 1
        factor(first, offset, values, member, settings.LCP_DEPENDENT, L, kept)
        for i in range(m):
            rhs[i] = -b[i] if kept[i] else 0.0
        solve(first, offset, L, rhs, f)
        residual(indptr, indices, data, b, f, sharp, a, tol_a)
        n = _violations(joint, member, kept, f, a, tol_a, bad)
        clipped = f.copy()
        for i in range(m):
            if not joint[i] and clipped[i] < 0.0:
                clipped[i] = 0.0
        if _valid(indptr, indices, data, b, joint, clipped, sharp, a, tol_a):
            f[:] = clipped
            return OK
        if n == 0:  # the set looks right: the forces are as good as this factor makes them
            f[:] = clipped
            return OK if _valid(indptr, indices, data, b, joint, f, tol, a, tol_a) else STUCK
        if n < best:
            best, idle = n, 0
        else:
            idle += 1
        last = -1
        for i in range(m):
            if bad[i]:
                last = i
        for i in range(m):
            if bad[i] and (idle < _PATIENCE or i == last):
                if member[i] and kept[i]:
                    member[i] = False
                elif not member[i]:
                    member[i] = True
    return STUCK


@njit
def _valid(indptr, indices, data, b, joint, f, tol, a, tol_a):
    residual(indptr, indices, data, b, f, tol, a, tol_a)
    for i in range(b.size):
        if joint[i] or f[i] > 0.0:
            if not abs(a[i]) <= tol_a[i]:
                return False
        elif not a[i] >= -tol_a[i]:
            return False
    return True


def solve_sparse(A: sp.csr_array, b: np.ndarray, joint, guess, tol: float, counts):
    """(f, clamped, status, blame) of one island by the sparse path (see the module docstring)."""
    m = b.size
    diag = A.diagonal()
    top = float(np.max(diag, initial=0.0))
    live = diag > settings.LCP_ZERO_ROW * top
    d = np.where(live, 1.0 / np.sqrt(np.where(live, diag, 1.0)), 0.0)
    b_max = float(np.max(np.abs(b), initial=0.0))
    dead = ~live & ((b < -tol * b_max) | (joint & (b > tol * b_max)))
    if dead.any():
        return np.zeros(m), dead, INFEASIBLE, dead
    scale = sp.diags_array(d)
    S = sp.csr_array(scale @ A @ scale)
    S = sp.csr_array(0.5 * (S + S.T))
    order = reverse_cuthill_mckee(sp.csr_matrix(S), symmetric_mode=True)
    S = sp.csr_array(S[order][:, order])
    S.sort_indices()
    bs, js = (d * b)[order], joint[order]
    member = (js | guess[order] | (bs < 0.0)) & live[order]
    if not guess.any():
        member |= live[order]  # cold: everything clamped first (a resting pile mostly is)
    first, offset, values = envelope(S.indptr, S.indices, S.data)
    fs = np.zeros(m)
    status = pivot_blocks(
        S.indptr, S.indices, S.data, first, offset, values, bs, js, member, tol, counts, fs
    )
    if status != OK:  # the dense solver, warm-started from the best set
        dense = np.ascontiguousarray(A.toarray())
        f, clamped = np.empty(m), np.empty(m, np.bool_)
        start = np.zeros(m, np.bool_)
        start[order] = member
        status = lcp_dense.solve_dense_counted(dense, b, joint, start, tol, f, clamped, counts)
        return f, clamped, status, clamped if status != OK else None
    a, tol_a = np.empty(m), np.empty(m)
    sharp = min(tol, settings.LCP_SHARP)
    residual(S.indptr, S.indices, S.data, bs, fs, sharp, a, tol_a)
    held = (js | (fs > 0) | (np.abs(a) <= tol_a)) & live[order]
    outcome, trial = _least_norm(first, offset, values, S, bs, js, held, (diag / top)[order], tol)
    counts[MIN_NORM] = outcome
    if outcome == DONE:
        fs = trial
        residual(S.indptr, S.indices, S.data, bs, fs, sharp, a, tol_a)
        held = (js | (fs > 0) | (np.abs(a) <= tol_a)) & live[order]
    f, clamped = np.zeros(m), ~live & (joint | (b <= tol * b_max))
    f[order] = fs
    clamped[order] |= held
    return d * f, clamped, OK, None


def _least_norm(first, offset, values, S, b, joint, held, inv_w, tol):
    """(outcome, f): the least-norm forces over the held rows (lcp_minnorm's UNIQUE, DONE or
    FAILED; f only with DONE)."""
    m = b.size
    L, kept = np.empty(values.size), np.zeros(m, np.bool_)
    if factor(first, offset, values, held, settings.LCP_DEPENDENT, L, kept) == held.sum():
        return UNIQUE, None
    basis, others = np.flatnonzero(kept), np.flatnonzero(held & ~kept)
    T = np.empty((basis.size, others.size))
    rhs, x = np.zeros(m), np.empty(m)
    for c, r in enumerate(others):
        column = S[:, [r]].toarray().ravel()
        rhs[:] = np.where(kept, column, 0.0)
        solve(first, offset, L, rhs, x)
        T[:, c] = x[basis]
    rhs[:] = np.where(kept, -b, 0.0)
    solve(first, offset, L, rhs, x)
    f_basis, f_others = np.empty(basis.size), np.empty(others.size)
    done = dual_newton(
        T, x[basis].copy(), inv_w[basis], inv_w[others], joint[basis], joint[others], f_basis,
        f_others,
    )  # fmt: skip
    if not done:
        return FAILED, None
    f = np.zeros(m)
    f[basis], f[others] = f_basis, f_others
    f = np.where(joint, f, np.maximum(f, 0.0))
    f[np.abs(f) <= settings.LCP_NOISE * np.max(np.abs(f))] = 0.0  # rounding, as in lcp_minnorm
    a, tol_a = np.empty(m), np.empty(m)
    if _valid(S.indptr, S.indices, S.data, b, joint, f, tol, a, tol_a):
        return DONE, f
    worst = np.max(np.abs(S @ f + b)[kept])
    for _ in range(2):  # T may be ill-conditioned: refine a_B = 0 with the basis factor
        rhs[:] = np.where(kept, S @ f + b, 0.0)
        solve(first, offset, L, rhs, x)
        trial = f - x
        after = np.max(np.abs(S @ trial + b)[kept])
        if not after < worst:
            break
        f, worst = trial, after
    f = np.where(joint, f, np.maximum(f, 0.0))
    if _valid(S.indptr, S.indices, S.data, b, joint, f, tol, a, tol_a):
        return DONE, f
    return FAILED, None
