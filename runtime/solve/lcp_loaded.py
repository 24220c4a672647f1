"""A large island's contact forces from its loaded set: the least-norm forces in body space.

Why: a pile packed wall to wall is statically indeterminate (a third of its contacts depend on
the others). The pivoting solver's warm start then meets dependent rows, and its least-norm
stage costs O(q^3) in the q dependent rows: 28 ms a solve for a 200-disc pile, four solves a
step. But the loaded set P, the contacts that carry a force, rarely changes from one solve to
the next. Once P is known, the least-norm forces take one sparse factorization of a matrix the
size of the moving bodies' degrees of freedom.

The method. Write A = B B^T with B = J W^(1/2) (runtime.solve.assembly.island_scaled_jacobian).
- Every LCP solution has the same v = B^T f, because the accelerations are unique.
- On P, a = 0 reads B_P v = -b_P. If B_P has full column rank over the columns it touches, then
  v = -K^-1 B_P^T b_P with K = B_P^T B_P.
- Of all f >= 0 with B^T f = v that are 0 off the held rows, the least-norm one is f_P = B_P z
  with K z = v, 0 elsewhere, provided it is positive on P and every held row without force has
  B_i z <= 0. These are the KKT conditions of projecting 0 onto that set: -B_i z is the row's
  multiplier.
- So the work is one envelope Cholesky factor of K (reverse Cuthill-McKee order,
  runtime.solve.lcp_envelope), two solves, and the checks.

The result is accepted only if every LCP condition holds to settings.LCP_SHARP, as a warm start
must, and the multipliers have their signs. Those checks alone certify it: any z with f_P = B_P z
that passes them proves f the least-norm solution, however z was found. So the singular-K and
row-count tests are early exits, not safeguards. Otherwise the result is None and the pivoting
solver takes the island (runtime.solve.lcp).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_envelope as env
from runtime.solve.assembly import sort_row

_SHARP, _TOL, _DEPENDENT = settings.LCP_SHARP, settings.LCP_TOL, settings.LCP_DEPENDENT


def solve_loaded(B: tuple, columns: int, A: tuple, b: np.ndarray, loaded: np.ndarray):
    """(f, clamped) of an island's LCP -- A = B B^T and b, both matrices as CSR arrays (data,
    indices, indptr) with sorted columns, B with ``columns`` columns -- whose least-norm forces
    are positive exactly on the rows ``loaded``; clamped: the held rows (settings.LCP_TOL).
    None if that set does not give the solution (see the module docstring)."""
    if not _enough_rows(B[1], B[2], loaded, columns):
        return None
    K = normal_matrix(*B, loaded, columns)
    order = _fill_reducing_order(K[1].tobytes(), K[2].tobytes(), columns)
    m = b.size
    f, clamped = np.empty(m), np.empty(m, np.bool_)
    if not _solve(K, order, B, A, b, loaded, f, clamped):
        return None
    return f, clamped


@lru_cache(maxsize=16)
def _fill_reducing_order(indices: bytes, indptr: bytes, columns: int) -> np.ndarray:
    """The reverse Cuthill-McKee order of K's pattern (CSR index arrays as bytes). Cached: a
    resting island's pattern stays the same from solve to solve, and the ordering cost 0.12 ms
    of a 200-disc pile's 0.42 ms solve (most of the rest is the factor)."""
    idx, ptr = np.frombuffer(indices, np.int64), np.frombuffer(indptr, np.int64)
    pattern = sp.csr_matrix((np.ones(idx.size), idx, ptr), shape=(columns, columns))
    return reverse_cuthill_mckee(pattern, symmetric_mode=True).astype(np.int64)


@njit
def _enough_rows(indices, indptr, loaded, columns):
    """Whether the loaded rows are at least as many as the columns they touch: else K is
    singular (a landing pile's loaded rows are independent, fewer than its bodies' degrees of
    freedom) and building and factoring it would be wasted (it was: 0.25 ms a solve, 13 % of a
    landing 200-disc pile's step)."""
    touched = np.zeros(columns, np.bool_)
    rows, count = 0, 0
    for r in range(indptr.size - 1):
        if loaded[r]:
            rows += 1
            for p in range(indptr[r], indptr[r + 1]):
                if not touched[indices[p]]:
                    touched[indices[p]] = True
                    count += 1
    return rows >= count


@njit
def normal_matrix(data, indices, indptr, loaded, columns):
    """K = B_P^T B_P as CSR arrays (data, indices, indptr), sorted columns: B's rows ``loaded``
    only (row by row products through B_P's columns: O(sum over rows of entries^2))."""
    m = indptr.size - 1
    count = np.zeros(columns + 1, np.int64)
    room = 0
    for r in range(m):
        if loaded[r]:
            for p in range(indptr[r], indptr[r + 1]):
                count[indices[p] + 1] += 1
                room += indptr[r + 1] - indptr[r]
    column_ptr = np.cumsum(count)
    column_row, column_value = (
        np.empty(column_ptr[columns], np.int64),
        np.empty(column_ptr[columns]),
    )
    fill = column_ptr[:-1].copy()
    for r in range(m):
        if loaded[r]:
            for p in range(indptr[r], indptr[r + 1]):
                c = indices[p]
                column_row[fill[c]], column_value[fill[c]] = r, data[p]
                fill[c] += 1
    out_val, out_idx = np.empty(room), np.empty(room, np.int64)
    out_ptr = np.zeros(columns + 1, np.int64)
    slot = np.full(columns, -1, np.int64)
    n = 0
    for c in range(columns):
        row_start = n
        for q in range(column_ptr[c], column_ptr[c + 1]):
            r, v = column_row[q], column_value[q]
            for p in range(indptr[r], indptr[r + 1]):
                j = indices[p]
                if slot[j] < row_start:
                    slot[j], out_idx[n], out_val[n] = n, j, 0.0
                    n += 1
                out_val[slot[j]] += v * data[p]
        sort_row(out_idx, out_val, row_start, n)
        out_ptr[c + 1] = n
    return out_val[:n], out_idx[:n], out_ptr


@njit
def _solve(K, order, B, A, b, loaded, f, clamped):
    """f and clamped of :func:`solve_loaded`; False where it returns None."""
    z = _body_space_solution(K, order, B, b, loaded)
    if z.size == 0:
        return False
    b_data, b_idx, b_ptr = B
    g = np.empty(b.size)  # B z: the forces on the loaded rows, minus the multipliers elsewhere
    for i in range(b.size):
        s = 0.0
        for p in range(b_ptr[i], b_ptr[i + 1]):
            s += b_data[p] * z[b_idx[p]]
        if loaded[i] and not s > 0.0:
            return False
        g[i] = s
        f[i] = s if loaded[i] else 0.0
    return _least_norm_solution(A, b, loaded, f, g, clamped)


@njit
def _body_space_solution(K, order, B, b, loaded):
    """z = K^-1 v with v = -K^-1 B_P^T b_P (the module docstring), or an empty array if K is
    singular on the columns it touches. K factored as D K D, D = diag(K)^-1/2, in ``order``."""
    k_data, k_idx, k_ptr = K
    n = k_ptr.size - 1
    d, used = np.zeros(n), np.zeros(n, np.bool_)
    touched = 0
    for i in range(n):
        for p in range(k_ptr[i], k_ptr[i + 1]):
            if k_idx[p] == i and k_data[p] > 0.0:
                d[i], used[i] = 1.0 / math.sqrt(k_data[p]), True
                touched += 1
    position = np.empty(n, np.int64)
    position[order] = np.arange(n)
    S = env.scaled(k_ptr, k_idx, k_data, d, position)
    first, offset, values = env.envelope(S[0], S[1], S[2])
    L, kept = np.empty(values.size), np.zeros(n, np.bool_)
    count, _ = env.factor(first, offset, values, used[order], _DEPENDENT, L, kept)
    if count < touched:
        return np.zeros(0)
    b_data, b_idx, b_ptr = B
    rhs = np.zeros(n)
    for i in range(b.size):
        if loaded[i]:
            for p in range(b_ptr[i], b_ptr[i + 1]):
                rhs[b_idx[p]] += b_data[p] * b[i]
    v = _scaled_solve(first, offset, L, d, order, rhs)
    z = _scaled_solve(first, offset, L, d, order, v)
    return -z


@njit
def _scaled_solve(first, offset, L, d, order, rhs):
    """K^-1 rhs from the factor of D K D in ``order``."""
    n = rhs.size
    permuted, x = np.empty(n), np.empty(n)
    for r in range(n):
        permuted[r] = d[order[r]] * rhs[order[r]]
    env.solve(first, offset, L, permuted, x)
    out = np.empty(n)
    for r in range(n):
        out[order[r]] = d[order[r]] * x[r]
    return out


@njit
def _least_norm_solution(A, b, loaded, f, g, clamped):
    """Whether f (positive on the loaded rows, 0 elsewhere) solves the LCP to
    settings.LCP_SHARP and is its least-norm solution: no held row without force has a g = B_i z
    (its negated multiplier) above settings.LCP_TOL of the largest force. Checked on the scaled
    problem D A D, D = diag(A)^-1/2, as the pivoting solver checks (runtime.solve.lcp_sparse);
    ``clamped`` gets the held rows, found as it finds them."""
    a_data, a_idx, a_ptr = A
    m = b.size
    d = np.zeros(m)
    top = 0.0
    for i in range(m):
        for p in range(a_ptr[i], a_ptr[i + 1]):
            if a_idx[p] == i:
                d[i] = a_data[p]
        top = max(top, d[i])
    for i in range(m):
        if not d[i] > settings.LCP_ZERO_ROW * top:
            return False  # a row no force moves: left to the pivoting solver's rules
        d[i] = 1.0 / math.sqrt(d[i])
    s_data = np.empty(a_data.size)
    for i in range(m):
        for p in range(a_ptr[i], a_ptr[i + 1]):
            s_data[p] = d[i] * a_data[p] * d[a_idx[p]]
    bs, fs = np.empty(m), np.empty(m)
    largest = 0.0
    for i in range(m):
        bs[i], fs[i] = d[i] * b[i], f[i] / d[i]
        largest = max(largest, f[i])
    a, tol_a = np.empty(m), np.empty(m)
    if not env.valid(a_ptr, a_idx, s_data, bs, np.zeros(m, np.bool_), fs, _SHARP, a, tol_a):
        return False
    env.residual(a_ptr, a_idx, s_data, bs, fs, _TOL, a, tol_a)
    for i in range(m):
        clamped[i] = loaded[i] or abs(a[i]) <= tol_a[i]
        if clamped[i] and not loaded[i] and g[i] > _TOL * largest:
            return False  # this row's force would lower the norm: the loaded set has changed
    return True
