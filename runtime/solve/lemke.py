"""Lemke's complementary pivoting method for a small LCP that need not be symmetric.

Problem: M (n, n), q (n,); find z >= 0 with w = M z + q >= 0 and z.w = 0.

Why this and not the frictionless solvers (runtime.solve.lcp): with Coulomb friction the 2-D
contact problem (runtime.solve.friction_lcp) has the friction cone's two directions and a slack
per sticking contact, and sliding contacts fold -mu sign(v_t) of their tangential row into their
normal column, so M is not symmetric, nor positive semi-definite. Lemke's method solves every
feasible LCP whose M is copositive-plus, and is the method shown to process the friction cone's
LCP (Stewart and Trinkle 1996, Anitescu and Potra 1997); otherwise it solves it or ends on a
ray, which is what an inconsistent (Painleve) configuration gives -- and, rarely, a degenerate
one (see :func:`lemke_perturbed`). Written here (about 100 lines, compiled
with runtime.compiled.njit) rather than taken from a package: the friction forces call it from
compiled code at every integrator stage, which a Python package's solver could not serve, and
the project adds no dependency for it.

The method (Cottle, Pang and Stone, "The Linear Complementarity Problem", 1992, section 4.4):
the tableau [I  -M  -e | q] with w basic; the artificial z0 enters at the row of the most
negative q, then the complement of the variable that left enters, with the minimum-ratio
test choosing who leaves (z0 on a tie, so it ends as soon as it can; else lexicographically,
with the rows of the basis inverse, which prevents cycling on degenerate problems such as a
box whose two corners' tangential rows are equal), until z0 leaves (solved) or no row limits the
entering variable (a ray: no solution found). A few pivots for a contact island, each O(n^2).
In exact arithmetic the lexicographic rule meets no basis twice; in rounding a path can cycle
(4 of the first 25 covering vectors of a packed 60-disc pile's first frame, 660 unknowns,
returned to a basis 8-30 pivots after meeting it, and ran on to the pivot limit: 18.5 s
each), so the bases met are remembered by a hash and a second meeting ends the path.
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.compiled import njit

SOLVED, RAY, ITERATIONS, INACCURATE = 0, 1, 2, 3
_PIVOT, _TIE, _PIVOTS = settings.LEMKE_PIVOT, settings.LEMKE_TIE, settings.LEMKE_PIVOTS
_RETRIES, _PERTURB = settings.LEMKE_RETRIES, settings.LEMKE_PERTURB
_CHECK = settings.LEMKE_CHECK


@njit
def lemke(M, q, z, basic):
    """z (n,) written with the solution and ``basic`` (n,) with whether each z_i ended in the
    basis (the complementary basis, whose M_BB is not singular: the next solve's first try,
    runtime.solve.friction_lcp); returns SOLVED, RAY (no solution found) or ITERATIONS (a
    basis met again, or settings.LEMKE_PIVOTS x (n + 1) pivots without an end)."""
    return lemke_covering(M, q, np.ones(q.size), z, basic)


@njit
def lemke_covering(M, q, d, z, basic):
    """:func:`lemke` with the covering vector ``d`` (> 0) for the artificial variable's column
    (:func:`lemke`'s is all ones): z0 enters at the row of the least q_i / d_i."""
    n = q.size
    for i in range(n):
        z[i] = 0.0
        basic[i] = False
    if n == 0:
        return SOLVED
    worst = 0
    for i in range(n):
        if q[i] / d[i] < q[worst] / d[worst]:
            worst = i
    if q[worst] >= 0.0:
        return SOLVED
    # columns: w 0..n-1, z n..2n-1, z0 2n; rhs kept apart
    T = np.zeros((n, 2 * n + 1))
    rhs = q.copy()
    scale = 0.0
    for i in range(n):
        T[i, i] = 1.0
        for j in range(n):
            T[i, n + j] = -M[i, j]
            scale = max(scale, abs(M[i, j]))
        T[i, 2 * n] = -d[i]
    zero = _PIVOT * max(scale, 1.0)
    basis = np.arange(n)
    entering = 2 * n
    row = worst
    visited = set()  # the bases met (their hashes, _basis_key): a basis met again is a cycle
    key = np.uint64(0)
    for i in range(n):
        key ^= _basis_key(i)
    for _ in range(_PIVOTS * (n + 1)):
        _pivot(T, rhs, row, entering)
        leaving = basis[row]
        basis[row] = entering
        if leaving == 2 * n:
            break
        key ^= _basis_key(leaving) ^ _basis_key(entering)
        if key in visited:
            return ITERATIONS
        visited.add(key)
        entering = leaving + n if leaving < n else leaving - n
        row = _ratio_test(T, rhs, basis, entering, zero, n)
        if row < 0:
            return RAY
    else:
        return ITERATIONS
    for i in range(n):
        if n <= basis[i] < 2 * n:
            z[basis[i] - n] = max(rhs[i], 0.0)
            basic[basis[i] - n] = True
    return SOLVED


@njit
def lemke_perturbed(M, q, z, basic, covers):
    """:func:`lemke`, and on a ray, a path that cycles or runs past settings.LEMKE_PIVOTS or
    an end that does not solve the LCP (:func:`complementary`) up to settings.LEMKE_RETRIES
    times again with q moved by settings.LEMKE_PERTURB x max |q| in a fixed pattern:
    degenerate problems (rounding-level q entries beside exact zeros: a disc in a pile with
    d' = -5e-12 sliding at 0.14 m/s) can end on a ray that an exact lexicographic rule would not
    reach, and a perturbation of q is the lexicographic rule's own idea made numeric. Then up
    to ``covers`` other covering vectors (fixed quasi-random ones in [0.1, 1];
    settings.LEMKE_COVERS and LEMKE_COVERS_LAST say how many where): M is not copositive-plus
    here, so a ray does not prove that there is no solution, and the path depends on the
    covering vector. Rows of 20 discs dropped with mu = 1 stopped at an island of 35 sticking
    contacts (140 unknowns) whose path with all ones ends on a ray; 4 of the first 40 of these
    vectors solve it (the 5th first), 20 of 40 for a jammed 40-contact island of a falling
    30-disc pile. A heuristic, then, and a last one: a problem with no solution keeps the first
    path's status (INACCURATE where that path ended but did not solve it).

    Every end is checked against the LCP itself: in a 35-contact island of those rows the path
    with all ones ended "solved" at z with w_i = -18.9 beside z_i = 120 (its tableau's rounding
    had chosen a wrong basis; the pile sank 6.5e-8 m into a contact that force held)."""
    first = lemke(M, q, z, basic)
    if first == SOLVED:
        if complementary(M, q, z):
            return SOLVED
        first = INACCURATE
    size = 1.0
    for i in range(q.size):
        size = max(size, abs(q[i]))
    for attempt in range(1, _RETRIES + 1):
        moved = q.copy()
        for i in range(q.size):
            moved[i] += _PERTURB * size * attempt * (1.0 + ((i * 0.6180339887498949) % 1.0))
        if lemke(M, moved, z, basic) == SOLVED and complementary(M, q, z):
            return SOLVED
    for attempt in range(1, covers + 1):
        d = np.empty(q.size)
        for i in range(q.size):
            d[i] = 0.1 + 0.9 * ((i * 0.6180339887498949 + attempt * 0.7548776662466927) % 1.0)
        if lemke_covering(M, q, d, z, basic) == SOLVED and complementary(M, q, z):
            return SOLVED
    return first


@njit
def complementary(M, q, z):
    """Whether z >= 0 solves the LCP (M, q) to settings.LEMKE_CHECK: w = M z + q >= 0 and each
    pair has z_i or w_i at 0, relative to the largest z and |q| (a covering vector other than
    Lemke's own can end its path in a tableau whose rounding has grown). Not the row-by-row test
    of runtime.solve.friction_lcp's bases: the rows of small scale of a pile's island carry that
    rounding (~1e-13), and that test refused every covering vector's solution of the 35-contact
    island of rows of 20 dropped with mu = 1."""
    n = q.size
    w = M @ z + q
    z_scale, w_scale = 1e-300, 1.0
    for i in range(n):
        z_scale = max(z_scale, z[i])
        w_scale = max(w_scale, abs(q[i]))
    for i in range(n):
        if w[i] < -_CHECK * w_scale or min(z[i] / z_scale, w[i] / w_scale) > _CHECK:
            return False
    return True


@njit
def _basis_key(variable):
    """A 64-bit hash of one variable (splitmix64's finalizer); a basis's key is the XOR of its
    variables' keys, so a pivot updates it with two XORs."""
    x = np.uint64(variable) + np.uint64(0x9E3779B97F4A7C15)
    x = (x ^ (x >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    x = (x ^ (x >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return x ^ (x >> np.uint64(31))


@njit
def _pivot(T, rhs, row, col):
    """Gauss-Jordan pivot on T[row, col] (rhs too), element by element: row slices would
    allocate a temporary per row (0.57 against 0.31 ms a pivot of a 660-unknown tableau)."""
    p = T[row, col]
    width = T.shape[1]
    for j in range(width):
        T[row, j] /= p
    rhs[row] /= p
    for i in range(T.shape[0]):
        if i != row:
            f = T[i, col]
            if f != 0.0:
                for j in range(width):
                    T[i, j] -= f * T[row, j]
                rhs[i] -= f * rhs[row]
                T[i, col] = 0.0


@njit
def _ratio_test(T, rhs, basis, col, zero, n):
    """The leaving row for entering column ``col`` (-1: none, a ray): the minimum of
    rhs_i / T_ic over T_ic > zero; on a tie the artificial variable's row, else the
    lexicographically smallest row of the basis inverse (columns 0..n-1) over T_ic."""
    best = -1
    ratio = np.inf
    for i in range(T.shape[0]):
        if T[i, col] > zero:
            r = max(rhs[i], 0.0) / T[i, col]
            if r < ratio:
                ratio = r
    if ratio == np.inf:
        return -1
    tie = _TIE * max(ratio, 1e-300)
    for i in range(T.shape[0]):
        if T[i, col] > zero and max(rhs[i], 0.0) / T[i, col] <= ratio + tie:
            if basis[i] == 2 * n:
                return i
            if best < 0 or _lex_less(T, i, best, col, n):
                best = i
    return best


@njit
def _lex_less(T, a, b, col, n):
    """Whether row a of the basis inverse over T[a, col] is lexicographically below b's."""
    for j in range(n):
        x, y = T[a, j] / T[a, col], T[b, j] / T[b, col]
        if x < y - 1e-15 * (abs(x) + abs(y)):
            return True
        if x > y + 1e-15 * (abs(x) + abs(y)):
            return False
    return False


def solve(M: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, int]:
    """(z, status) of the LCP (M, q) by :func:`lemke_perturbed` (float64 copies), with
    settings.LEMKE_COVERS_LAST covering vectors: its caller has no other answer."""
    M = np.ascontiguousarray(M, dtype=float)
    q = np.ascontiguousarray(q, dtype=float)
    z = np.zeros(q.size)
    return z, int(lemke_perturbed(M, q, z, np.zeros(q.size, np.bool_), settings.LEMKE_COVERS_LAST))
