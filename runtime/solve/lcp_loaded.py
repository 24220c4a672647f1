"""A large island's contact forces from its loaded set: the least-norm forces in body space.

Why: a pile packed wall to wall is statically indeterminate (a third of its contacts depend on
the others). The pivoting solver's warm start then meets dependent rows, and its least-norm
stage costs O(q^3) in the q dependent rows: 28 ms a solve for a 200-disc pile, four solves a
step; in the compiled dense path a landing 50-disc pile's 112-row island cost ~1.5 ms a solve.
But the loaded set P, the contacts that carry a force, rarely changes from one solve to the
next. Once P is known, the least-norm forces take one sparse factorization of a matrix the size
of the moving bodies' degrees of freedom.

The method. Write A = B B^T with B = J W^(1/2) (runtime.solve.assembly.island_scaled_jacobian),
K = B_P^T B_P, and K^+ its pseudo-inverse.
- Every LCP solution has the same v = B^T f, because the accelerations are unique.
- On P, a = 0 reads B_P v = -b_P, and v = B_P^T f_P lies in the range of K: so v is the
  least-norm solution, v = -K^+ B_P^T b_P.
- Of all f >= 0 with B^T f = v that are 0 off the held rows, the least-norm one is f_P = B_P z
  with K z = v (every such z gives the same f_P; z = K^+ v here), 0 elsewhere, provided it is
  positive on P and every held row without force has B_i z <= 0. These are the KKT conditions
  of projecting 0 onto that set: -B_i z is the row's multiplier.
- K is singular where P leaves a body free to move (a disc on one contact slides along it):
  the envelope Cholesky factor of K (reverse Cuthill-McKee order, runtime.solve.lcp_envelope)
  leaves out each such column, which gives one vector of K's null space per column left out,
  and K^+ y is the factor's solution projected off that null space.

The result is accepted only if every LCP condition holds to settings.LCP_TOL -- as the dense
solver accepts its least-norm forces: a loaded set with near-redundant rows holds b in its range
only to ~1e-10 (a landing 50-disc pile) -- and the multipliers have their signs. Those checks
alone certify it: any z with f_P = B_P z that passes them proves f the least-norm solution,
however z was found. So the null-space bound (settings.LOADED_NULLITY) is an early exit, not a
safeguard. Otherwise the result is None (False from the compiled entry) and the pivoting solver
takes the island (runtime.solve.lcp, runtime.solve.lcp_dense).

The set tried first is the island's guess: the engine keeps a large island's loaded set as its
guess (runtime.solve.assembly), and a guess that also holds rows without force has them dropped
(:func:`solve_island`).
"""

from __future__ import annotations

import math

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_envelope as env
from runtime.solve.lcp_envelope import sort_row

_TOL, _DEPENDENT = settings.LCP_TOL, settings.LOADED_DEPENDENT
_NULLITY, _TRIES = settings.LOADED_NULLITY, settings.LOADED_TRIES


def solve_loaded(B: tuple, columns: int, A: tuple, b: np.ndarray, loaded: np.ndarray):
    """(f, clamped) of an island's LCP -- A = B B^T and b, both matrices as CSR arrays (data,
    indices, indptr) with sorted columns, B with ``columns`` columns -- whose least-norm forces
    are positive exactly on the rows ``loaded``, or on some of them (:func:`solve_island`);
    clamped: the held rows (settings.LCP_TOL). None if that set does not give the solution
    (see the module docstring)."""
    m = b.size
    f, clamped = np.empty(m), np.empty(m, np.bool_)
    if not solve_island(B, columns, A, b, loaded, f, clamped):
        return None
    return f, clamped


@njit
def solve_island(B, columns, A, b, loaded, f, clamped):
    """f and clamped of :func:`solve_loaded`, written; False where it returns None. A row of
    ``loaded`` whose force comes out <= 0 is dropped and the rest solved again (at most
    settings.LOADED_TRIES solves): so the clamped set of the last solve, which also holds the
    touching contacts without force, serves as the loaded set."""
    b_data, b_idx, b_ptr = B
    rows = loaded.copy()
    g = np.empty(b.size)  # B z: the forces on the loaded rows, minus the multipliers elsewhere
    for _ in range(_TRIES):
        if _free_directions(b_idx, b_ptr, rows, columns) > _NULLITY:
            return False
        K = normal_matrix(b_data, b_idx, b_ptr, rows, columns)
        order = env.reverse_cuthill_mckee(K[2], K[1])
        z = _body_space_solution(K, order, B, b, rows)
        if z.size == 0:
            return False
        positive = True
        for i in range(b.size):
            s = 0.0
            for p in range(b_ptr[i], b_ptr[i + 1]):
                s += b_data[p] * z[b_idx[p]]
            g[i] = s
            if rows[i] and not s > 0.0:
                rows[i] = positive = False
        if positive:
            for i in range(b.size):
                f[i] = g[i] if rows[i] else 0.0
            return _least_norm_solution(A, b, rows, f, g, clamped)
    return False


@njit
def _free_directions(indices, indptr, loaded, columns):
    """A lower bound on the dimension of K's null space: the columns the loaded rows touch less
    the rows (each row fixes at most one direction). Why: above settings.LOADED_NULLITY the
    solve is refused before K is built (a landing pile's islands: bodies on one contact each,
    ~0.1 ms a refused try that factored K first)."""
    touched = np.zeros(columns, np.bool_)
    rows, count = 0, 0
    for r in range(indptr.size - 1):
        if loaded[r]:
            rows += 1
            for p in range(indptr[r], indptr[r + 1]):
                if not touched[indices[p]]:
                    touched[indices[p]] = True
                    count += 1
    return count - rows


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
def _body_space_solution(K, order, B, b, loaded):
    """z = K^+ v with v = -K^+ B_P^T b_P (the module docstring), or an empty array if K's null
    space has more than settings.LOADED_NULLITY dimensions. K factored as D K D,
    D = diag(K)^-1/2, in ``order``."""
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
    if touched - count > _NULLITY:
        return np.zeros(0)
    factor = (first, offset, L, d, order, kept)
    null = _null_space(S, factor, used, touched - count)
    b_data, b_idx, b_ptr = B
    rhs = np.zeros(n)
    for i in range(b.size):
        if loaded[i]:
            for p in range(b_ptr[i], b_ptr[i + 1]):
                rhs[b_idx[p]] += b_data[p] * b[i]
    v = _least_norm_solve(K, factor, null, rhs)
    z = _least_norm_solve(K, factor, null, v)
    return -z


@njit
def _null_space(S, factor, used, nullity):
    """K's null space as orthonormal rows (original order and units): for each used column j
    the factor left out, e_j minus the kept columns' combination that equals column j, then
    orthonormalised (Gram-Schmidt, twice: the kept columns can be a poorly conditioned basis,
    and these vectors then nearly parallel)."""
    first, offset, L, d, order, kept = factor
    s_ptr, s_idx, s_val = S
    n = d.size
    null = np.zeros((nullity, n))
    rhs, x = np.empty(n), np.empty(n)
    c = 0
    for r in range(n):
        if kept[r] or not used[order[r]]:
            continue
        rhs[:] = 0.0
        for p in range(s_ptr[r], s_ptr[r + 1]):
            if kept[s_idx[p]]:
                rhs[s_idx[p]] = -s_val[p]
        env.solve(first, offset, L, rhs, x)
        x[r] = 1.0
        for t in range(n):
            null[c, order[t]] = d[order[t]] * x[t]
        for _ in range(2):
            for a in range(c):
                _remove_component(null, a, null[c])
        size = 0.0
        for t in range(n):
            size += null[c, t] * null[c, t]
        size = math.sqrt(size)
        for t in range(n):
            null[c, t] /= size
        c += 1
    return null


@njit
def _remove_component(null, a, y):
    """y -= (y . N_a) N_a for the unit row a of ``null``."""
    s = 0.0
    for t in range(y.size):
        s += null[a, t] * y[t]
    for t in range(y.size):
        y[t] -= s * null[a, t]


@njit
def _least_norm_solve(K, factor, null, rhs):
    """K^+ rhs for rhs in K's range: the factor's solution over the kept columns, projected
    off the null space -- and where there is one, refined twice against K's residual (the
    kept columns can then be a poorly conditioned basis)."""
    k_data, k_idx, k_ptr = K
    n = rhs.size
    out, residual = np.zeros(n), rhs.copy()
    rounds = 3 if null.shape[0] else 1
    for r in range(rounds):
        step = _basic_solve(factor, residual)
        for a in range(null.shape[0]):
            _remove_component(null, a, step)
        for t in range(n):
            out[t] += step[t]
        if r == rounds - 1:
            break  # (no residual for a round that does not follow)
        for i in range(n):
            s = rhs[i]
            for p in range(k_ptr[i], k_ptr[i + 1]):
                s -= k_data[p] * out[k_idx[p]]
            residual[i] = s
    return out


@njit
def _basic_solve(factor, rhs):
    """A solution of K x = rhs that is 0 on the columns the factor left out."""
    first, offset, L, d, order, kept = factor
    n = rhs.size
    permuted, x = np.empty(n), np.empty(n)
    for r in range(n):
        permuted[r] = d[order[r]] * rhs[order[r]] if kept[r] else 0.0
    env.solve(first, offset, L, permuted, x)
    out = np.empty(n)
    for r in range(n):
        out[order[r]] = d[order[r]] * x[r]
    return out


@njit
def _least_norm_solution(A, b, loaded, f, g, clamped):
    """Whether f (positive on the loaded rows, 0 elsewhere) solves the LCP to
    settings.LCP_TOL and is its least-norm solution: no held row without force has a g = B_i z
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
    if not env.valid(a_ptr, a_idx, s_data, bs, np.zeros(m, np.bool_), fs, _TOL, a, tol_a):
        return False
    env.residual(a_ptr, a_idx, s_data, bs, fs, _TOL, a, tol_a)
    for i in range(m):
        clamped[i] = loaded[i] or abs(a[i]) <= tol_a[i]
        if clamped[i] and not loaded[i] and g[i] > _TOL * largest:
            return False  # this row's force would lower the norm: the loaded set has changed
    return True
