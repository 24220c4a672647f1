"""Compiled assembly of Baraff's contact problem from kernel rows, island by island.

For contacts k with Jacobian rows J_k (6 numbers: body 1's x, y, th, body 2's), bodies with
inverse masses W = diag(1/m, 1/m, 1/I) (0 for fixed bodies) and free accelerations a0 (gravity):

    A_kl = sum over the bodies shared by k and l of J_k(body) W(body) J_l(body)^T
    b_k  = J_k a0 + bias_k                (d'' of contact k if no contact pushed)
    acc  = a0 + W J^T f                   (the accelerations under the forces f)

so d'' = A f + b (note section 2). A is built per island (contacts [start, stop) of an order
grouped by island): O(K^2) per island instead of the O(m n) of a dense J, and the small dense
blocks are what the LCP solves. Nothing of a contact's geometry is here: J and bias come from the
generated kernels (runtime.solve.rows).
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_loaded
from runtime.solve.lcp_dense import OK, solve_dense
from runtime.solve.lcp_envelope import sort_row

_LOADED = settings.LOADED_ISLAND
MISSED, SOLVED, DEPENDENT = 0, 1, 2  # solve_with_guess


@njit
def _self_product(jac, body, side, inv_mass, fixed, k):
    """Contact k's row on one body times that body's inverse mass times the row (0 if fixed)."""
    s = 0.0
    if not fixed[body]:
        for c in range(3):
            s += jac[k, side + c] * inv_mass[body, c] * jac[k, side + c]
    return s


@njit
def _diagonal(jac, body1, body2, inv_mass, fixed, k):
    """A_kk: contact k's rows times its bodies' inverse masses times the rows."""
    return _self_product(jac, body1[k], 0, inv_mass, fixed, k) + _self_product(
        jac, body2[k], 3, inv_mass, fixed, k
    )


@njit
def island_matrix(jac, body1, body2, inv_mass, fixed, start, stop, A):
    """A[:K, :K] for the contacts start..stop-1 (K = stop - start): for each moving body, the
    products of the rows of the contacts that touch it (O(sum of degree^2), not O(K^2))."""
    K = stop - start
    if K == 1:  # one contact: no sort (and no arrays to allocate); the same sums
        A[0, 0] = _diagonal(jac, body1, body2, inv_mass, fixed, start)
        return
    A[:K, :K] = 0.0
    bodies = np.empty(2 * K, np.int64)
    for a in range(K):
        bodies[2 * a] = body1[start + a]
        bodies[2 * a + 1] = body2[start + a]
    order = np.argsort(bodies, kind="mergesort")
    first = 0
    while first < 2 * K:
        body = bodies[order[first]]
        last = first
        while last < 2 * K and bodies[order[last]] == body:
            last += 1
        if not fixed[body]:
            for p in range(first, last):
                ea = order[p]
                a, side_a = ea // 2, 3 * (ea % 2)
                for r in range(p, last):
                    eb = order[r]
                    b, side_b = eb // 2, 3 * (eb % 2)
                    s = 0.0
                    for c in range(3):
                        s += (
                            jac[start + a, side_a + c]
                            * inv_mass[body, c]
                            * jac[start + b, side_b + c]
                        )
                    A[a, b] += s
                    if a != b or side_a != side_b:
                        A[b, a] += s
        first = last


@njit
def island_csr(jac, body1, body2, inv_mass, fixed, start, stop):
    """The same A as island_matrix for contacts start..stop-1, as CSR arrays (data, indices,
    indptr) with sorted columns and every diagonal entry stored: a large island's A is sparse
    (a resting pile of 200 discs: 382 rows, ~6 entries a row), and converting the dense one
    cost 0.7 ms a solve, more than solving it."""
    K = stop - start
    bodies = np.empty(2 * K, np.int64)
    for a in range(K):
        bodies[2 * a] = body1[start + a]
        bodies[2 * a + 1] = body2[start + a]
    order = np.argsort(bodies, kind="mergesort")
    first_of, last_of = np.empty(2 * K, np.int64), np.empty(2 * K, np.int64)  # entry -> group
    first = 0
    while first < 2 * K:
        last = first
        while last < 2 * K and bodies[order[last]] == bodies[order[first]]:
            last += 1
        for p in range(first, last):
            first_of[order[p]], last_of[order[p]] = first, last
        first = last
    room = K
    for e in range(2 * K):
        if not fixed[bodies[e]]:
            room += last_of[e] - first_of[e]
    data, indices = np.empty(room), np.empty(room, np.int64)
    indptr = np.zeros(K + 1, np.int64)
    slot = np.full(K, -1, np.int64)  # where column b sits in the row being built
    n = 0
    for a in range(K):
        row_start = n
        indices[n], data[n], slot[a] = a, 0.0, n
        n += 1
        for side_a in range(2):
            ea = 2 * a + side_a
            body = bodies[ea]
            if fixed[body]:
                continue
            for p in range(first_of[ea], last_of[ea]):
                eb = order[p]
                b, side_b = eb // 2, 3 * (eb % 2)
                s = 0.0
                for c in range(3):
                    s += (
                        jac[start + a, 3 * side_a + c]
                        * inv_mass[body, c]
                        * jac[start + b, side_b + c]
                    )
                if slot[b] < row_start:
                    indices[n], data[n], slot[b] = b, 0.0, n
                    n += 1
                data[slot[b]] += s
        sort_row(indices, data, row_start, n)
        indptr[a + 1] = n
    return data[:n], indices[:n], indptr


@njit
def island_scaled_jacobian(jac, body1, body2, inv_mass, fixed, start, stop):
    """B = J W^(1/2) of the contacts start..stop-1, A = B B^T, as CSR arrays (data, indices,
    indptr) with sorted columns, its non-zero entries only, and its number of columns: three
    for each moving body of the island (3 * its rank among them + x, y, th). The factor that
    runtime.solve.lcp_loaded solves an island's forces in body space with."""
    K = stop - start
    bodies = np.empty(2 * K, np.int64)
    count = 0
    for a in range(K):
        for body in (body1[start + a], body2[start + a]):
            if not fixed[body]:
                bodies[count] = body
                count += 1
    moving = np.unique(bodies[:count])
    data, indices = np.empty(6 * K), np.empty(6 * K, np.int64)
    indptr = np.zeros(K + 1, np.int64)
    n = 0
    for a in range(K):
        k = start + a
        i, j = body1[k], body2[k]
        sides = (0, 3) if i < j else (3, 0)
        for side in sides:
            body = i if side == 0 else j
            if fixed[body]:
                continue
            column = 3 * np.searchsorted(moving, body)
            for c in range(3):
                value = jac[k, side + c] * np.sqrt(inv_mass[body, c])
                if value != 0.0:
                    data[n], indices[n] = value, column + c
                    n += 1
        indptr[a + 1] = n
    return data[:n], indices[:n], indptr, 3 * moving.size


@njit
def free_rates(jac, body1, body2, bias, free_acc, out):
    """out[k] = J_k a0 + bias_k: b of every contact."""
    for k in range(bias.size):
        s = bias[k]
        i, j = body1[k], body2[k]
        for c in range(3):
            s += jac[k, c] * free_acc[i, c] + jac[k, 3 + c] * free_acc[j, c]
        out[k] = s


@njit
def add_forces(jac, body1, body2, inv_mass, forces, acc):
    """acc += W J^T f (in place)."""
    for k in range(forces.size):
        f = forces[k]
        if f == 0.0:
            continue
        i, j = body1[k], body2[k]
        for c in range(3):
            acc[i, c] += inv_mass[i, c] * jac[k, c] * f
            acc[j, c] += inv_mass[j, c] * jac[k, 3 + c] * f


@njit
def _cholesky(A, idx, L):
    """L L^T = A[idx, idx]; False if a pivot is not clearly positive (dependent rows)."""
    k = idx.size
    for r in range(k):
        for c in range(r + 1):
            s = A[idx[r], idx[c]]
            for p in range(c):
                s -= L[r, p] * L[c, p]
            if r == c:
                if not s > 1e-12 * A[idx[r], idx[r]] or not s > 0.0:
                    return False
                L[r, r] = np.sqrt(s)
            else:
                L[r, c] = s / L[c, c]
    return True


@njit
def solve_with_guess(A, b, K, guess, tol, f):
    """Forces f[:K] >= 0 with a = A f + b = 0 on the guessed clamped set and >= 0 elsewhere, each
    to tol relative to the row's scale |b_k| + sum_j |A_kj| f_j. Returns SOLVED, or why the guess
    does not give such a solution (then the pivoting solver must find the set): DEPENDENT (the
    guessed rows are linearly dependent: a packed or landing pile, whose least-norm forces the
    loaded set may give) or MISSED."""
    if K == 1:  # one contact (most islands of a scattered scene): no index array to allocate
        f[0], solved = _solve_one(A[0, 0], b[0], guess[0], tol)
        return SOLVED if solved else MISSED
    count = 0
    for k in range(K):
        if guess[k]:
            count += 1
    idx = np.empty(count, np.int64)
    p = 0
    for k in range(K):
        f[k] = 0.0
        if guess[k]:
            idx[p] = k
            p += 1
    if count == 1:  # one clamped row: f = -b/A exactly (one rounding, as the closed form)
        k = idx[0]
        if not A[k, k] > 0.0:
            return MISSED
        f[k] = -b[k] / A[k, k]
        if f[k] < 0.0:
            return MISSED
    elif count:
        L = np.zeros((count, count))
        if not _cholesky(A, idx, L):
            return DEPENDENT
        y = np.empty(count)
        for r in range(count):
            s = -b[idx[r]]
            for c in range(r):
                s -= L[r, c] * y[c]
            y[r] = s / L[r, r]
        for r in range(count - 1, -1, -1):
            s = y[r]
            for c in range(r + 1, count):
                s -= L[c, r] * y[c]
            y[r] = s / L[r, r]
        for r in range(count):
            if y[r] < 0.0:
                return MISSED
            f[idx[r]] = y[r]
    for k in range(K):
        a = b[k]
        scale = abs(b[k])
        for j in range(K):
            a += A[k, j] * f[j]
            scale += abs(A[k, j]) * f[j]
        if guess[k]:
            if abs(a) > tol * scale:
                return MISSED
        elif a < -tol * scale:
            return MISSED
    return SOLVED


@njit
def _solve_one(A, b, held, tol):
    """(f, solved): solve_with_guess for one row, the same arithmetic in the same order, on
    scalars (an array view per island costs more than the arithmetic of one row)."""
    f = 0.0
    if held:
        if not A > 0.0:
            return 0.0, False
        f = -b / A
        if f < 0.0:
            return f, False
    a = b + A * f
    scale = abs(b) + abs(A) * f
    if held:
        return f, not abs(a) > tol * scale
    return f, not a < -tol * scale


@njit
def island_scratch(offsets, limit):
    """An (s, s) array for A of every island of at most ``limit`` contacts, s the largest such."""
    largest = 0
    for g in range(offsets.size - 1):
        size = offsets[g + 1] - offsets[g]
        if size <= limit:
            largest = max(largest, size)
    return np.empty((largest, largest))


@njit
def solve_small_islands(
    jac,
    body1,
    body2,
    bias,
    inv_mass,
    fixed,
    free_acc,
    offsets,
    guess,
    tol,
    limit,
    forces,
    rates,
    ok,
):
    """Every island of offsets (contacts grouped by island) with at most ``limit`` contacts:
    assemble A and b and solve with the warm-start guess. ``rates`` gets b (all contacts),
    ``ok[g]`` whether island g was solved (False: larger than the limit, or the guess failed;
    the caller solves it)."""
    free_rates(jac, body1, body2, bias, free_acc, rates)
    A = island_scratch(offsets, limit)
    for g in range(offsets.size - 1):
        start, stop = offsets[g], offsets[g + 1]
        if stop - start > limit:
            ok[g] = False
            continue
        K = stop - start
        if K == 1:  # most islands of a scattered scene: on scalars, no views
            diagonal = _diagonal(jac, body1, body2, inv_mass, fixed, start)
            forces[start], ok[g] = _solve_one(diagonal, rates[start], guess[start], tol)
            if ok[g]:
                continue
        b, f = rates[start:stop], forces[start:stop]
        island_matrix(jac, body1, body2, inv_mass, fixed, start, stop, A)
        tried = solve_with_guess(A, b, K, guess[start:stop], tol, f) if K > 1 else MISSED
        if tried == SOLVED:  # (one row: tried above)
            ok[g] = True
        elif (tried == DEPENDENT and K >= _LOADED
              and _from_loaded_set(jac, body1, body2, inv_mass, fixed, start, stop, b,
                                   guess[start:stop], f)):  # fmt: skip
            ok[g] = True  # a packed or landing pile: the least-norm forces, sparse
        else:  # the clamped set changed: the dense solver finds the new one
            ok[g] = dense_lcp(
                np.ascontiguousarray(A[:K, :K]), b.copy(), np.zeros(K, np.bool_),
                guess[start:stop], f,
            )  # fmt: skip
            if ok[g] and K >= _LOADED:  # the loaded set: the next solve's first try
                _loaded_guess(f, guess[start:stop])


@njit
def _from_loaded_set(jac, body1, body2, inv_mass, fixed, start, stop, b, guess, f):
    """Whether the island's forces came from its guess taken as the loaded set
    (runtime.solve.lcp_loaded: a packed or landing pile's least-norm forces in body space, one
    sparse factor instead of the dense solver's least-norm stage); ``guess`` then gets the new
    loaded set (:func:`_loaded_guess`)."""
    data, indices, indptr, columns = island_scaled_jacobian(
        jac, body1, body2, inv_mass, fixed, start, stop
    )
    A = island_csr(jac, body1, body2, inv_mass, fixed, start, stop)
    clamped = np.empty(b.size, np.bool_)
    if not lcp_loaded.solve_island((data, indices, indptr), columns, A, b, guess, f, clamped):
        return False
    _loaded_guess(f, guess)
    return True


@njit
def _loaded_guess(f, guess):
    """guess = the rows with a force. Why: the next solve of a large island tries its guess as
    the loaded set (:func:`_from_loaded_set`), and the clamped set also holds the touching rows
    without force, which that try must first find and drop (a packed pile has dozens). For the
    dense solver's warm start it is as good: a held row without force is a free row with a = 0."""
    for k in range(f.size):
        guess[k] = f[k] > 0.0


@njit
def dense_lcp(A, b, joint, guess, f):
    """The mixed LCP of one small island (joint rows bilateral) by the compiled dense solver
    (runtime.solve.lcp_dense, warm-started from ``guess``, which gets the new clamped set),
    written to f; False if it has no solution."""
    clamped = np.empty(b.size, np.bool_)
    if solve_dense(A, b, joint, guess, 0.0, f, clamped) != OK:
        return False
    guess[:] = clamped
    return True
