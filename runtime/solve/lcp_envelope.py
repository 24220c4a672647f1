"""Compiled sparse kernels of the contact-force solve: the scaled matrix, its envelope factor.

Why: a pile's A has a handful of non-zeros per row, and in reverse Cuthill-McKee order they
sit in a narrow band (the envelope, or profile). A Cholesky factor keeps the envelope of the
matrix (fill stays inside it), so it is stored the same way -- row i from its first non-zero
column to the diagonal, packed -- and costs O(m * bandwidth^2) instead of O(m^3). Like the
dense factor (runtime.solve.lcp_factor) it leaves out a row whose pivot is below ``dependent``
of its diagonal plus the pivot's own rounding: such a row depends on the rows kept before it
(a redundant contact), and gets an identity row and a zero column, so the factor solves the
block of the kept rows. scipy's splu cannot do that: on a singular block it fails or returns
garbage.

Also here: the reverse Cuthill-McKee order itself, compiled (the engine's compiled stages order
a large island's body-space matrix at every solve; runtime.solve.lcp_loaded); building S = D A D
from the lower triangle of A (mirrored, so S is exactly symmetric) in a given order; and checking
a CSR matrix as runtime.solve.lcp_problem.prepare does a dense one, without scipy's temporaries.
"""

from __future__ import annotations

import math

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve.lcp_baraff import tolerance_floor

_ROUNDING = settings.LCP_PIVOT_ROUNDING
_SYMMETRIC = settings.LCP_SYMMETRY
FINE, NOT_FINITE, NEGATIVE_DIAGONAL, NOT_SYMMETRIC, NOT_PSD = 0, 1, 2, 3, 4  # check_csr


@njit
def check_csr(indptr, indices, data, diag):
    """FINE, or the first problem of a CSR matrix with sorted indices: a value not finite, a
    negative diagonal, A_ij != A_ji (beyond 1e-8 sqrt(A_ii A_jj)), |A_ij| > sqrt(A_ii A_jj)."""
    m = indptr.size - 1
    for i in range(m):
        if not np.isfinite(diag[i]):
            return NOT_FINITE
        if diag[i] < 0.0:
            return NEGATIVE_DIAGONAL
    for i in range(m):
        for p in range(indptr[i], indptr[i + 1]):
            j, v = indices[p], data[p]
            if not np.isfinite(v):
                return NOT_FINITE
            bound = math.sqrt(diag[i] * diag[j])
            lo, hi = indptr[j], indptr[j + 1]  # A_ji by bisection in row j
            while lo < hi:
                mid = (lo + hi) // 2
                if indices[mid] < i:
                    lo = mid + 1
                else:
                    hi = mid
            mirror = data[lo] if lo < indptr[j + 1] and indices[lo] == i else 0.0
            if abs(v - mirror) > _SYMMETRIC * bound:
                return NOT_SYMMETRIC
            if abs(v) > (1.0 + _SYMMETRIC) * bound:
                return NOT_PSD
    return FINE


@njit
def scaled(indptr, indices, data, d, position):
    """CSR of S = D A D with rows and columns renumbered (row i of A is row position[i] of S),
    built from A's lower triangle and its mirror image."""
    m = d.size
    count = np.zeros(m + 1, np.int64)
    for i in range(m):
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j <= i:
                count[position[i] + 1] += 1
                if j < i:
                    count[position[j] + 1] += 1
    out_ptr = np.cumsum(count)
    fill = out_ptr[:-1].copy()
    out_idx = np.empty(out_ptr[m], np.int64)
    out_val = np.empty(out_ptr[m])
    for i in range(m):
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if j <= i:
                v = d[i] * data[p] * d[j]
                r, c = position[i], position[j]
                out_idx[fill[r]], out_val[fill[r]] = c, v
                fill[r] += 1
                if j < i:
                    out_idx[fill[c]], out_val[fill[c]] = r, v
                    fill[c] += 1
    return out_ptr, out_idx, out_val


@njit
def envelope(indptr, indices, data):
    """The lower envelope of a symmetric CSR matrix: first column of each row, offsets and the
    values S[i, first[i]..i] of each row, packed (the factor has the same envelope)."""
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
    """Skyline Cholesky of S over the rows in ``member``, leaving out each row whose pivot is
    below ``dependent`` of its diagonal plus its rounding (runtime.solve.lcp_factor.trial) --
    it depends on the rows kept before it -- and rows with S_ii = 0. Returns the number of rows
    kept and the smallest pivot / diagonal among them (1 if none). ``scales``: each kept row's
    1 / L_jj and S_jj / L_jj^2, so the inner loop multiplies instead of dividing (measured:
    4-10 % of a 500-row factorization)."""
    m = first.size
    scales = np.empty((m, 2))
    count, smallest = 0, 1.0
    for i in range(m):
        base, lo = offset[i], first[i]
        diag = values[base + i - lo]
        kept[i] = False
        for j in range(lo, i):
            L[base + j - lo] = 0.0
        L[base + i - lo] = 1.0
        if not member[i] or not diag > 0.0:
            continue
        pivot, noise = diag, diag
        for j in range(lo, i):
            if not kept[j]:
                continue
            bj, lj = offset[j], first[j]
            s = values[base + j - lo]
            for p in range(max(lo, lj), j):
                s -= L[base + p - lo] * L[bj + p - lj]
            s *= scales[j, 0]
            L[base + j - lo] = s
            pivot -= s * s
            noise += s * s * scales[j, 1]
        if pivot > dependent * diag + _ROUNDING * noise:
            root = math.sqrt(pivot)
            L[base + i - lo] = root
            scales[i, 0], scales[i, 1] = 1.0 / root, diag / pivot
            kept[i] = True
            count += 1
            smallest = min(smallest, pivot / diag)
        else:
            for j in range(lo, i):
                L[base + j - lo] = 0.0
    return count, smallest


@njit
def refactor_members(indptr, indices, data, member, dependent, start, packed, L, kept, scales):
    """:func:`factor` of S (CSR) over the rows in ``member`` alone, packed: row w of the factor
    is S's row rows[w], its envelope over member rows only (``packed`` = (pos, rows, first,
    offset); pos[i]: the number of member rows before row i; ``kept`` and ``scales`` per packed
    row). Redone from S's row ``start`` on, the rows before it left as the last call made them:
    a factor row depends only on the rows before it, so a set changed from ``start`` on needs no
    more. Returns the number of member rows. Equal to the bit to :func:`factor`'s rows and
    columns of the members (the rows it leaves out only add zeros). Why packed: the primal method
    leaves a quarter of a falling pile's rows out, and their zeros were in every dot product
    (measured: the method 4-6 % faster on the falling 200-disc pile's islands). The row's loop
    is factor's again, in place: as one shared function it cost 9 %."""
    pos, rows, first, offset = packed
    w = pos[start]
    for i in range(start, member.size):
        pos[i] = w
        if not member[i]:
            continue
        rows[w], lo = i, w  # S's row i over the member columns: its envelope, its values
        for q in range(indptr[i], indptr[i + 1]):
            j = indices[q]
            if j < i and member[j]:
                lo = min(lo, pos[j])
        base = offset[w]
        first[w], offset[w + 1] = lo, base + w - lo + 1
        for c in range(base, offset[w + 1]):
            L[c] = 0.0
        for q in range(indptr[i], indptr[i + 1]):
            j = indices[q]
            if j <= i and member[j]:
                L[base + pos[j] - lo] = data[q]  # (pos[i] = w)
        diag = L[base + w - lo]
        kept[w] = False
        pivot, noise = diag, diag
        for j in range(lo, w):
            if not kept[j] or not diag > 0.0:
                L[base + j - lo] = 0.0
                continue
            bj, lj = offset[j], first[j]
            s = L[base + j - lo]
            for p in range(max(lo, lj), j):
                s -= L[base + p - lo] * L[bj + p - lj]
            s *= scales[j, 0]
            L[base + j - lo] = s
            pivot -= s * s
            noise += s * s * scales[j, 1]
        if diag > 0.0 and pivot > dependent * diag + _ROUNDING * noise:
            root = math.sqrt(pivot)
            L[base + w - lo] = root
            scales[w, 0], scales[w, 1] = 1.0 / root, diag / pivot
            kept[w] = True
        else:
            for c in range(base, base + w - lo):
                L[c] = 0.0
            L[base + w - lo] = 1.0
        w += 1
    pos[member.size] = w
    return w


@njit
def remove_member(first, offset, L, kept, scales, n, k, rotations):
    """Packed row k (of n) out of :func:`refactor_members`'s factor, as a row that left the
    member set: it becomes an identity row, and the rows after it take the rank-one update
    L' L'^T = L L^T + l l^T with l its column (a Givens rotation per row, row by row, each
    row's from the rotations of the rows before it; ``rotations``: (n, 2) scratch). Why: an
    update is stable (not a downdate) and costs O(the envelope after k) against O(envelope x
    bandwidth) to refactor from k -- the primal method's rounds that only free rows are most
    of its rounds (measured: the falling 200-disc pile's islands 25 % faster). A row left out
    as dependent stays out (its column is 0) until a factorization from before it."""
    base, lo = offset[k], first[k]
    for c in range(base, base + k - lo):
        L[c] = 0.0
    L[base + k - lo] = 1.0
    kept[k] = False
    for i in range(k + 1, n):
        base, lo = offset[i], first[i]
        rotations[i, 0], rotations[i, 1] = 1.0, 0.0
        if not kept[i]:
            continue
        x = 0.0  # l's entry in row i, rotated by the rows before it
        if lo <= k:
            x = L[base + k - lo]
            L[base + k - lo] = 0.0
        for j in range(max(lo, k + 1), i):
            cos, sin = rotations[j, 0], rotations[j, 1]
            if sin != 0.0:
                l_ij = L[base + j - lo]
                L[base + j - lo] = cos * l_ij + sin * x
                x = cos * x - sin * l_ij
        if x != 0.0:
            d = L[base + i - lo]
            r = math.sqrt(d * d + x * x)
            rotations[i, 0], rotations[i, 1] = d / r, x / r
            L[base + i - lo] = r
            scales[i, 0], scales[i, 1] = 1.0 / r, scales[i, 1] * (d * d) / (r * r)


@njit
def solve(first, offset, L, rhs, x):
    """x = (L L^T)^-1 rhs (rhs must be 0 at rows left out: x is 0 there)."""
    forward(first, offset, L, rhs, x, 0)
    backward(first, offset, L, x)


@njit
def forward(first, offset, L, rhs, z, start):
    """z = L^-1 rhs from row ``start`` on (z before it as the last call left it: row i of z
    depends on rhs and L up to row i alone, so an unchanged head needs no work)."""
    for i in range(start, first.size):
        base, lo = offset[i], first[i]
        s = rhs[i]
        for p in range(lo, i):
            s -= L[base + p - lo] * z[p]
        z[i] = s / L[base + i - lo]


@njit
def backward(first, offset, L, x):
    """x = L^-T x in place (a row whose x is 0 adds nothing to the rows before it)."""
    for i in range(first.size - 1, -1, -1):
        if x[i] == 0.0:
            continue
        base, lo = offset[i], first[i]
        x[i] /= L[base + i - lo]
        for p in range(lo, i):
            x[p] -= L[base + p - lo] * x[i]


@njit
def residual(indptr, indices, data, b, f, tol, a, tol_a):
    """a = S f + b and each row's tolerance tol * (sum_j |S_ij f_j| + |b_i|) + the floor
    (runtime.solve.lcp_baraff.residual), S in CSR."""
    floor = tolerance_floor(b, f)
    for i in range(b.size):
        s, size = b[i], abs(b[i])
        for p in range(indptr[i], indptr[i + 1]):
            t = data[p] * f[indices[p]]
            s += t
            size += abs(t)
        a[i] = s
        tol_a[i] = tol * size + floor


@njit
def valid(indptr, indices, data, b, joint, f, tol, a, tol_a):
    """Every LCP condition within the row tolerances (f must be >= 0 at contacts already)."""
    residual(indptr, indices, data, b, f, tol, a, tol_a)
    for i in range(b.size):
        if joint[i] or f[i] > 0.0:
            if not abs(a[i]) <= tol_a[i]:
                return False
        elif not a[i] >= -tol_a[i]:
            return False
    return True


@njit
def row_of(indptr, indices, data, r, kept, out):
    """out = row r of S (= column r), kept entries only."""
    out[:] = 0.0
    for p in range(indptr[r], indptr[r + 1]):
        if kept[indices[p]]:
            out[indices[p]] = data[p]


@njit
def sort_row(indices, data, start, stop):
    """Entries start..stop-1 of a CSR row being built, sorted by column in place (insertion
    sort: a row has a handful of entries)."""
    for p in range(start + 1, stop):
        col, val, q = indices[p], data[p], p
        while q > start and indices[q - 1] > col:
            indices[q], data[q] = indices[q - 1], data[q - 1]
            q -= 1
        indices[q], data[q] = col, val


@njit
def reverse_cuthill_mckee(indptr, indices):
    """A fill-reducing order of a symmetric pattern (CSR, the diagonal ignored): each connected
    part breadth first from a pseudo-peripheral node (George and Liu's search), every node's new
    neighbours by increasing degree, the whole order reversed. Rows of the matrix in this order
    keep their entries near the diagonal, so the envelope factor's work is small."""
    n = indptr.size - 1
    degree = np.zeros(n, np.int64)
    for i in range(n):
        for p in range(indptr[i], indptr[i + 1]):
            if indices[p] != i:
                degree[i] += 1
    order = np.empty(n, np.int64)
    placed = np.zeros(n, np.bool_)
    depth = np.full(n, -1, np.int64)  # scratch of the level search
    queue = np.empty(n, np.int64)
    count = 0
    for seed in np.argsort(degree, kind="mergesort"):
        if placed[seed]:
            continue
        start = _peripheral(indptr, indices, degree, seed, depth, queue)
        placed[start] = True
        order[count] = start
        head, count = count, count + 1
        while head < count:
            i = order[head]
            head += 1
            first = count
            for p in range(indptr[i], indptr[i + 1]):
                j = indices[p]
                if not placed[j]:
                    placed[j] = True
                    order[count] = j
                    count += 1
            for a in range(first + 1, count):  # new neighbours by degree (insertion, stable)
                j, b = order[a], a
                while b > first and degree[order[b - 1]] > degree[j]:
                    order[b] = order[b - 1]
                    b -= 1
                order[b] = j
    return order[::-1].copy()


@njit
def _levels(indptr, indices, root, depth, queue):
    """Breadth-first levels from ``root`` in ``depth`` (-1: not reached; reset by the caller
    through ``queue``); returns the number of nodes reached (queue[:count], by level)."""
    depth[root] = 0
    queue[0] = root
    head, count = 0, 1
    while head < count:
        i = queue[head]
        head += 1
        for p in range(indptr[i], indptr[i + 1]):
            j = indices[p]
            if depth[j] < 0:
                depth[j] = depth[i] + 1
                queue[count] = j
                count += 1
    return count


@njit
def _peripheral(indptr, indices, degree, root, depth, queue):
    """A node of ``root``'s connected part far from the others: from root, move to the
    lowest-degree node of the deepest level while that makes the levels deeper."""
    count = _levels(indptr, indices, root, depth, queue)
    height = depth[queue[count - 1]]
    while True:
        best = root
        for a in range(count - 1, -1, -1):
            j = queue[a]
            if depth[j] < height:
                break
            if best == root or degree[j] < degree[best]:
                best = j
        for a in range(count):
            depth[queue[a]] = -1
        if best == root:
            return root
        count = _levels(indptr, indices, best, depth, queue)  # kept if best becomes the root
        if not depth[queue[count - 1]] > height:
            for a in range(count):
                depth[queue[a]] = -1
            return best
        root, height = best, depth[queue[count - 1]]
