"""The contact problem of one island with Coulomb friction, at the accelerations level.

Unknowns per contact: the normal force f_n >= 0 with d'' >= 0 and f_n d'' = 0 (as without
friction). Per frictional contact (mu > 0), by its mode ``slide``:

* sliding (slide = s = +-1, the sign of v_t): f_t = -s mu f_n, so its tangential row folds into
  its normal column (c = J_n - s mu J_t), which makes A = J_n W C^T non-symmetric (Baraff 1994,
  "Fast contact force computation for nonpenetrating rigid bodies", section 7);
* sticking (slide = 0, v_t = 0): the friction cone of 2-D is two directions, f_t = f+ - f-,
  with a slack lambda (the size of the tangential acceleration if it slips):

      a_t + lambda >= 0  _|_ f+ >= 0,   -a_t + lambda >= 0  _|_ f- >= 0,
      mu f_n - f+ - f- >= 0  _|_  lambda >= 0,

  so a_t = 0 while |f_t| < mu f_n, and a_t opposes f_t = +-mu f_n when it slips (lambda > 0).

Together an LCP in z = (f_n, f+, f-, lambda) (Stewart and Trinkle 1996 at the velocity level,
the same matrix here), solved by Lemke's method (runtime.solve.lemke). Its matrix:

    [ A_nn   A_nS  -A_nS  0 ]        A_nn = J_n W C^T,   A_nS = J_n W J_tS^T
    [ A_Sn   A_SS  -A_SS  I ]        A_Sn = J_tS W C^T,  A_SS = J_tS W J_tS^T
    [-A_Sn  -A_SS   A_SS  I ]        q = (b_n, b_S, -b_S, 0), b = J a0 + bias
    [ Mu    -I     -I     0 ]        Mu: mu of each sticking contact's normal

W the bodies' inverse masses, a0 their free accelerations; J rows from the generated kernels
(runtime.solve.friction_rows). An LCP with no solution (Lemke's ray) is a Painleve
configuration: :class:`FrictionInconsistent`.

Warm start: which unknowns are basic (positive, or held by an equation) hardly changes from one
integrator stage or step to the next, so each contact keeps the basis of its last solve (flags:
:data:`NORMAL`, :data:`PLUS`, :data:`MINUS`, :data:`SLACK`), and a solve first tries it: one LU
factorization of M_BB, M_BB z_B = -q_B, accepted if z_B >= 0 and w = M z + q >= 0 off the basis
(each to settings.LCP_SHARP of its row's scale, as a warm start must). It forms no M: M_BB entry
by entry, w from the accelerations the forces give (:func:`_warm`; M has n^2 entries, few of
them non-zero: forming it and M z cost a packed 100-disc pile 4.8 ms a solve, 0.4 ms without).
Lemke's method (O(n) pivots of O(n^2) each: 4 ms for a 20-disc pile's 208 unknowns) runs only
if that fails, and its final basis is the next guess (its forces solved again on it by one
factorization: the tableau carries its pivots' rounding). A pile's rows are dependent, but
Lemke's final basis never is: its M_BB is the basis matrix of the tableau.

When every frictional contact of an island sticks and Lemke's method still ends on a ray (a
packed pile of 12 discs at rest did, at its first step: its rows are dependent and the problem
degenerate, and the perturbed retries did not help), the island is tried as held, every
contact's d'' and a_t at 0: a linear program for forces in the cones (|f_t| <= mu f_n), which
dependent rows do not trouble (:func:`solve_held`). Its forces, checked on M and q, solve the
friction LCP with lambda = 0. (The least-norm forces of that held system are not enough: in the
12-disc pile a third of them left their cones.)

The held solution is also tried first when Lemke's method (or a warm start) solves an island
whose contacts all stick with forces that open or slip one of them (:func:`_moves`): with
friction the LCP can have more than one solution, and where the island can be held, it is held.
So a large island that sticks everywhere and has no basis that solves it is tried held before
Lemke's method (settings.HELD_FIRST: from a few hundred unknowns the linear program costs far
less than a path).
"""

from __future__ import annotations

import numpy as np
from scipy import optimize

from runtime import settings
from runtime.compiled import njit
from runtime.solve.lcp_problem import ContactSolverError
from runtime.solve.lemke import SOLVED, lemke_perturbed

MOVES = -1  # solve_island's status: a solution that opens or slips a contact of an island
# that sticks everywhere (solve_held is tried first)
HOLD_FIRST = -2  # solve_island's status: an island that sticks everywhere, has no basis that
# solves it and settings.HELD_FIRST unknowns or more: solve_held first, Lemke's method after
_HELD_FIRST = settings.HELD_FIRST
NORMAL, PLUS, MINUS, SLACK = 1, 2, 4, 8  # a contact's basis flags: f_n, f+, f-, lambda basic
_TOL = settings.LCP_SHARP
_SINGULAR = settings.LEMKE_BASIS_PIVOT
_ONSET = settings.SLIP_ONSET


class FrictionInconsistent(ContactSolverError):
    """No contact forces obey Coulomb's law here (a Painleve configuration: a sliding contact
    whose friction would have to pull it into the other body)."""


@njit
def _coupling(row, b_row, col, b_col, inv_mass, fixed, k, j):
    """sum over the bodies shared by row k and column j of row_k(body) W(body) col_j(body)."""
    s = 0.0
    for side_k in range(2):
        body = b_row[k, side_k]
        if fixed[body]:
            continue
        for side_l in range(2):
            if b_col[j, side_l] != body:
                continue
            for c in range(3):
                s += row[k, 3 * side_k + c] * inv_mass[body, c] * col[j, 3 * side_l + c]
    return s


@njit
def _add_forces(rows, ends, inv_mass, forces, acc):
    """acc += W J^T f over the rows' two bodies."""
    for k in range(forces.size):
        for side in range(2):
            body = ends[k, side]
            for c in range(3):
                acc[body, c] += inv_mass[body, c] * rows[k, 3 * side + c] * forces[k]


@njit
def _rates(rows, ends, bias, acc, out):
    """out = J acc + bias."""
    for k in range(bias.size):
        s = bias[k]
        for side in range(2):
            for c in range(3):
                s += rows[k, 3 * side + c] * acc[ends[k, side], c]
        out[k] = s


@njit
def _lu_solve(B, r):
    """x with B x = r by Gaussian elimination with partial pivoting (B and r overwritten);
    None if a pivot is below _SINGULAR of its column's largest entry (B singular)."""
    p = r.size
    for c in range(p):
        best, size = c, 0.0
        for i in range(c, p):
            size = max(size, abs(B[i, c]))
            if abs(B[i, c]) > abs(B[best, c]):
                best = i
        if not abs(B[best, c]) > _SINGULAR * size or size == 0.0:
            return None
        if best != c:
            for j in range(p):
                B[c, j], B[best, j] = B[best, j], B[c, j]
            r[c], r[best] = r[best], r[c]
        for i in range(c + 1, p):
            f = B[i, c] / B[c, c]
            if f != 0.0:
                for j in range(c + 1, p):
                    B[i, j] -= f * B[c, j]
                r[i] -= f * r[c]
    for c in range(p - 1, -1, -1):
        s = r[c]
        for j in range(c + 1, p):
            s -= B[c, j] * r[j]
        r[c] = s / B[c, c]
    return r


@njit
def from_basis(M, q, basic, z):
    """Whether the LCP (M, q) is solved with the unknowns ``basic`` basic (on a formed M: the
    reference of :func:`_warm`, solve_island's warm start, which forms none): z (written) from
    M_BB z_B = -q_B, accepted if z_B >= 0 and w = M z + q >= 0 elsewhere, each to LCP_SHARP of
    its row's scale (z_B entries of rounding size below 0, a basic unknown at 0, are set to 0).

    The elimination leaves each z_j an error of up to LCP_SHARP of the largest, so a row's
    scale counts each basic z_j at least that large: a contact that carries no force has rows
    whose own terms are rounding (~1e-16 N), and measured by them alone its cone row of a
    resting 20-disc pile with mu = 0.5 failed at w = -1e-16 -- the basis refused, Lemke's method
    (~2 ms) run at every solve, found the same basis, refused again at the next."""
    idx = np.flatnonzero(basic)
    p = idx.size
    B = np.empty((p, p))
    r = np.empty(p)
    for a in range(p):
        r[a] = -q[idx[a]]
        for c in range(p):
            B[a, c] = M[idx[a], idx[c]]
    largest = _basic_solution(B, r, idx, z)
    return largest >= 0.0 and _complementary(M, q, z, basic, _TOL, largest)


@njit
def _basic_solution(B, r, idx, z):
    """z with z_B from M_BB z_B = -q_B (``B``, ``r``: M_BB and -q_B, overwritten; ``idx``: B's
    unknowns) and 0 elsewhere: the largest |z_B|, or -1 where M_BB is singular or a z_B is below
    0 beyond LCP_SHARP of the largest (above that, rounding: set to 0)."""
    x = _lu_solve(B, r)
    if x is None:
        return -1.0
    largest = 0.0
    for a in range(x.size):
        largest = max(largest, abs(x[a]))
    z[:] = 0.0
    for a in range(x.size):
        if x[a] < -_TOL * largest:
            return -1.0
        z[idx[a]] = max(x[a], 0.0)
    return largest


@njit
def _complementary(M, q, z, held, tol, error=0.0):
    """Whether w = M z + q is 0 on the rows ``held`` and >= 0 elsewhere, each to tol of its row's
    scale |q_i| + sum_j |M_ij| (z_j + error), j over the unknowns held (z >= 0 given)."""
    for i in range(q.size):
        w, scale = q[i], abs(q[i])
        for j in range(q.size):
            if held[j]:
                w += M[i, j] * z[j]
                scale += abs(M[i, j]) * (z[j] + error)
        if (abs(w) if held[i] else -w) > tol * scale:
            return False
    return True


@njit
def island_lcp(
    jac, tangent_jac, ends, bias, tangent_bias, mu, slide, inv_mass, fixed, free_acc, rates
):  # fmt: skip
    """(M, q, stick) of one island's friction LCP (the module docstring; ``stick``: the sticking
    contacts, in the order of their unknowns); ``rates`` gets b_n, the free d''."""
    k = mu.size
    cols = _folded(jac, tangent_jac, mu, slide)
    stick = np.flatnonzero((mu > 0) & (slide == 0))
    s = stick.size
    jts = tangent_jac[stick]
    ends_s = ends[stick]
    _rates(jac, ends, bias, free_acc, rates)
    b_s = np.empty(s)
    _rates(jts, ends_s, tangent_bias[stick], free_acc, b_s)
    n = k + 3 * s
    M = np.zeros((n, n))
    q = np.zeros(n)
    for i in range(k):
        q[i] = rates[i]
        for j in range(k):
            M[i, j] = _coupling(jac, ends, cols, ends, inv_mass, fixed, i, j)
        for j in range(s):
            x = _coupling(jac, ends, jts, ends_s, inv_mass, fixed, i, j)
            M[i, k + j], M[i, k + s + j] = x, -x
    for i in range(s):
        q[k + i], q[k + s + i] = b_s[i], -b_s[i]
        for j in range(k):
            x = _coupling(jts, ends_s, cols, ends, inv_mass, fixed, i, j)
            M[k + i, j], M[k + s + i, j] = x, -x
        for j in range(s):
            x = _coupling(jts, ends_s, jts, ends_s, inv_mass, fixed, i, j)
            M[k + i, k + j], M[k + i, k + s + j] = x, -x
            M[k + s + i, k + j], M[k + s + i, k + s + j] = -x, x
        M[k + i, k + 2 * s + i] = M[k + s + i, k + 2 * s + i] = 1.0
        M[k + 2 * s + i, k + i] = M[k + 2 * s + i, k + s + i] = -1.0
        M[k + 2 * s + i, stick[i]] = mu[stick[i]]
    return M, q, stick


@njit
def _folded(jac, tangent_jac, mu, slide):
    """The normal columns C = J_n - s mu J_t, with sliding contacts' friction folded in."""
    cols = jac.copy()
    for i in range(mu.size):
        for c in range(6):
            cols[i, c] -= slide[i] * mu[i] * tangent_jac[i, c]
    return cols


@njit
def _block(i, k, s):
    """(block, index in it) of unknown or row i: 0 f_n (k of them), 1 f+, 2 f-, 3 lambda (s)."""
    if i < k:
        return 0, i
    return 1 + (i - k) // s, (i - k) % s


@njit
def _basis_matrix(island, idx):
    """M_BB of :func:`island_lcp`'s matrix for the unknowns ``idx``, entry by entry by
    :func:`_coupling`'s arithmetic (the same numbers to the bit), without forming M. Its loop is
    written out here: called per entry, _coupling made this 1.7x slower (inlined by numba, 6x)."""
    jac, tangent_jac, ends, cols, stick, mu, inv_mass, fixed = island
    k, s, p = mu.size, stick.size, idx.size
    block, sub, contact = np.empty(p, np.int64), np.empty(p, np.int64), np.empty(p, np.int64)
    for a in range(p):
        block[a], sub[a] = _block(idx[a], k, s)
        contact[a] = sub[a] if block[a] == 0 else stick[sub[a]]
    B = np.zeros((p, p))
    for a in range(p):
        ba, ca = block[a], contact[a]
        for c in range(p):
            bc, cc = block[c], contact[c]
            if ba == 3:  # the cone row: mu f_n - f+ - f-
                if bc == 0 and cc == ca:
                    B[a, c] = mu[ca]
                elif 0 < bc < 3 and sub[c] == sub[a]:
                    B[a, c] = -1.0
            elif bc == 3:  # lambda, in the plus and minus rows of its own contact
                if ba > 0 and sub[c] == sub[a]:
                    B[a, c] = 1.0
            else:  # J W C^T over the bodies the two contacts share
                x = 0.0
                for side_k in range(2):
                    body = ends[ca, side_k]
                    if fixed[body]:
                        continue
                    for side_l in range(2):
                        if ends[cc, side_l] != body:
                            continue
                        for d in range(3):
                            row = (
                                jac[ca, 3 * side_k + d]
                                if ba == 0
                                else tangent_jac[ca, 3 * side_k + d]
                            )
                            col = (
                                cols[cc, 3 * side_l + d]
                                if bc == 0
                                else tangent_jac[cc, 3 * side_l + d]
                            )
                            x += row * inv_mass[body, d] * col
                B[a, c] = -x if (ba == 2) != (bc == 2) else x
    return B


@njit
def _residuals(island, bias, tangent_bias, free_acc, z):
    """w = M z + q of :func:`island_lcp`'s LCP from the accelerations the forces z give: O(K)
    work, not the O(n^2) of M z."""
    jac, tangent_jac, ends, cols, stick, mu, inv_mass, fixed = island
    k, s = mu.size, stick.size
    f_t = np.zeros(k)
    for i in range(s):
        f_t[stick[i]] = z[k + i] - z[k + s + i]
    acc = free_acc.copy()
    _add_forces(cols, ends, inv_mass, z[:k], acc)
    _add_forces(tangent_jac, ends, inv_mass, f_t, acc)
    w = np.empty(z.size)
    a_t = np.empty(s)
    _rates(jac, ends, bias, acc, w[:k])
    _rates(tangent_jac[stick], ends[stick], tangent_bias[stick], acc, a_t)
    for i in range(s):
        lam = z[k + 2 * s + i]
        w[k + i], w[k + s + i] = a_t[i] + lam, -a_t[i] + lam
        w[k + 2 * s + i] = mu[stick[i]] * z[stick[i]] - z[k + i] - z[k + s + i]
    return w


@njit
def _scales(island, q_n, q_s, e):
    """Each row's scale for the checks of :func:`_complementary`: a bound on |q_i| + sum_j
    |M_ij| e_j (e >= 0) from the bodies' accelerations term by term (|J| W |C|^T e), O(K).
    ``q_n``, ``q_s``: q of the normal and of the plus rows."""
    jac, tangent_jac, ends, cols, stick, mu, inv_mass, fixed = island
    k, s = mu.size, stick.size
    e_t = np.zeros(k)
    for i in range(s):
        e_t[stick[i]] = e[k + i] + e[k + s + i]
    size = np.zeros((inv_mass.shape[0], 3))
    _add_forces(np.abs(cols), ends, inv_mass, e[:k], size)
    _add_forces(np.abs(tangent_jac), ends, inv_mass, e_t, size)
    scale = np.empty(e.size)
    terms = np.empty(s)
    _rates(np.abs(jac), ends, np.abs(q_n), size, scale[:k])
    _rates(np.abs(tangent_jac[stick]), ends[stick], np.abs(q_s), size, terms)
    for i in range(s):
        scale[k + i] = scale[k + s + i] = terms[i] + e[k + 2 * s + i]
        scale[k + 2 * s + i] = mu[stick[i]] * e[stick[i]] + e[k + i] + e[k + s + i]
    return scale


@njit
def _warm(island, bias, tangent_bias, free_acc, rates, basic, z):
    """:func:`from_basis` on :func:`island_lcp`'s LCP without forming M (n^2 entries, most of
    them 0: a packed 100-disc pile's island has 1,120 unknowns and M 1.9 % filled): M_BB entry
    by entry, w from the accelerations, the rows' scales bounded term by term (at most ~3x
    from_basis's). The same z, to the bit. ``rates``: q of the normal rows, b_n."""
    jac, tangent_jac, ends, cols, stick, mu, inv_mass, fixed = island
    k, s = mu.size, stick.size
    b_s = np.empty(s)
    _rates(tangent_jac[stick], ends[stick], tangent_bias[stick], free_acc, b_s)
    idx = np.flatnonzero(basic)
    r = np.zeros(idx.size)
    for a in range(idx.size):
        block, i = _block(idx[a], k, s)
        if block < 3:
            r[a] = -(rates[i] if block == 0 else (b_s[i] if block == 1 else -b_s[i]))
    largest = _basic_solution(_basis_matrix(island, idx), r, idx, z)
    if largest < 0.0:
        return False
    w = _residuals(island, bias, tangent_bias, free_acc, z)
    scale = _scales(island, rates, b_s, np.where(basic, z + largest, 0.0))
    for i in range(z.size):
        if (abs(w[i]) if basic[i] else -w[i]) > _TOL * scale[i]:
            return False
    return True


@njit
def solve_island(
    jac, tangent_jac, ends, bias, tangent_bias, mu, slide, inv_mass, fixed, free_acc,
    normal, tangent, slack, tangent_acc, rates, acc, flags, hold_first, covers,
):  # fmt: skip
    """The forces of one island's K contacts (``ends`` (K, 2): body 1 and 2; ``bias`` the normal
    bias, stabilised if so; ``slide`` each contact's mode, 0 for a sticking or a frictionless
    one), written to ``normal``, ``tangent``, ``slack``, ``tangent_acc`` (a_t), ``rates`` (the
    free d'', b_n); ``acc`` (n, 3) gets the forces' accelerations added. ``flags`` (K, int8):
    each contact's basis flags, tried first (all 0: none known) and replaced by the new basis.
    Returns SOLVED, or Lemke's status, or (``hold_first``) MOVES, nothing written, if every
    contact sticks and the solution found opens or slips one (:func:`_moves`), or HOLD_FIRST,
    nothing solved, if every contact sticks, no remembered basis solves the island and it has
    settings.HELD_FIRST unknowns or more: the caller tries the island held first
    (:func:`solve_held`). ``covers``: Lemke's other covering vectors
    (runtime.solve.lemke.lemke_perturbed).
    """
    k = mu.size
    stick = np.flatnonzero((mu > 0) & (slide == 0))
    s = stick.size
    z = np.zeros(k + 3 * s)
    basic = np.zeros(z.size, np.bool_)
    for i in range(k):
        basic[i] = (flags[i] & NORMAL) != 0
    for i in range(s):
        c = stick[i]
        basic[k + i], basic[k + s + i] = (flags[c] & PLUS) != 0, (flags[c] & MINUS) != 0
        basic[k + 2 * s + i] = (flags[c] & SLACK) != 0
    cols = _folded(jac, tangent_jac, mu, slide)
    island = (jac, tangent_jac, ends, cols, stick, mu, inv_mass, fixed)
    _rates(jac, ends, bias, free_acc, rates)
    if not (np.any(basic) and _warm(island, bias, tangent_bias, free_acc, rates, basic, z)):
        if hold_first and z.size >= _HELD_FIRST and _sticks(slide, k):
            return HOLD_FIRST
        M, q, _ = island_lcp(
            jac, tangent_jac, ends, bias, tangent_bias, mu, slide, inv_mass, fixed, free_acc,
            rates,
        )  # fmt: skip
        status = lemke_perturbed(M, q, z, basic, covers)
        if status != SOLVED:
            return status
        # the tableau carries its pivots' rounding (cone rows 4e-9 N off, 1e-10 of the forces,
        # in a 38-contact island of a falling pile); its basis solved again by one
        # factorization: 1e-14
        polished = np.empty(z.size)
        if _warm(island, bias, tangent_bias, free_acc, rates, basic, polished):
            z[:] = polished
    if hold_first and _moves(island, bias, tangent_bias, free_acc, rates, z, slide):
        return MOVES
    write_solution(z, basic, stick, jac, tangent_jac, ends, tangent_bias, mu, slide, inv_mass,
                   normal, tangent, slack, tangent_acc, acc, flags)  # fmt: skip
    return SOLVED


@njit
def _sticks(slide, k):
    """Whether an island of k contacts, two or more, sticks everywhere (``slide`` all 0)."""
    if k < 2:
        return False
    for i in range(slide.size):
        if slide[i] != 0.0:
            return False
    return True


@njit
def _moves(island, bias, tangent_bias, free_acc, q, z, slide):
    """Whether the LCP solution z of an island whose contacts all stick (no slide) opens a
    contact (its normal row's w = d'' > 0) or lets one slip (lambda > 0), each above
    settings.SLIP_ONSET of the island's scale (its largest |b_n| -- ``q``, at least 1, as
    :func:`island_slips`).

    Why: with friction an island's LCP can have more than one solution, and where the island
    can be held (the forces of a solution with every contact held lie in the cones), that
    solution is the one taken: a body at rest that its contacts can hold stays at rest. (The
    case that brought this in, a packed pile of 40 discs in which a disc spun up at 73 rad/s^2,
    was a wrong end of Lemke's path, since refused: runtime.solve.lemke.lemke_perturbed.)

    An island of one contact is left to Lemke's solution: the question arises only where
    contacts share bodies, and asking it there cost a falling 20-disc pile with mu = 0.5 ~400
    linear programs (0.4 s of its 2.5 s), none of which held."""
    k, s = slide.size, island[4].size
    if not _sticks(slide, k):
        return False
    w = _residuals(island, bias, tangent_bias, free_acc, z)  # only for an island that sticks
    tol = 1.0
    for i in range(k):
        tol = max(tol, abs(q[i]))
    tol *= _ONSET
    for i in range(s):
        if z[k + 2 * s + i] > tol:
            return True
    for i in range(k):
        if w[i] > tol:
            return True
    return False


@njit
def write_solution(z, basic, stick, jac, tangent_jac, ends, tangent_bias, mu, slide, inv_mass,
                   normal, tangent, slack, tangent_acc, acc, flags):  # fmt: skip
    """The island's forces, a_t, accelerations and basis flags from the LCP's solution z with
    the unknowns ``basic`` basic (:func:`solve_island`'s outputs)."""
    k, s = mu.size, stick.size
    for i in range(k):
        flags[i] = NORMAL if basic[i] else 0
    for i in range(s):
        c = stick[i]
        flags[c] += (PLUS if basic[k + i] else 0) + (MINUS if basic[k + s + i] else 0)
        flags[c] += SLACK if basic[k + 2 * s + i] else 0
    for i in range(k):
        normal[i] = z[i]
        tangent[i] = -slide[i] * mu[i] * z[i]
        slack[i] = 0.0
    for i in range(s):
        tangent[stick[i]] = z[k + i] - z[k + s + i]
        slack[stick[i]] = z[k + 2 * s + i]
    _add_forces(jac, ends, inv_mass, normal, acc)
    _add_forces(tangent_jac, ends, inv_mass, tangent, acc)
    _rates(tangent_jac, ends, tangent_bias, acc, tangent_acc)


@njit
def solve_islands(
    groups, offsets, jac, tangent_jac, ends, bias, tangent_bias, mu, slide, inv_mass, fixed,
    free_acc, normal, tangent, slack, tangent_acc, rates, acc, flags, slips, hold_first, covers,
):  # fmt: skip
    """:func:`solve_island` for each island ``groups[i]`` (contacts offsets[g]:offsets[g + 1] of
    the arrays, which it writes as it does), and each one's ``slips`` (:func:`island_slips`), in
    one compiled loop: a scene of many small frictional islands paid ~20 us of Python for each.
    Returns (the index into ``groups`` of the first island not solved -- or, ``hold_first``,
    whose solution moves it: :func:`_moves` -- and its status), (-1, SOLVED) if all were."""
    for i in range(groups.size):
        a, b = offsets[groups[i]], offsets[groups[i] + 1]
        status = solve_island(
            jac[a:b], tangent_jac[a:b], ends[a:b], bias[a:b], tangent_bias[a:b], mu[a:b],
            slide[a:b], inv_mass, fixed, free_acc, normal[a:b], tangent[a:b], slack[a:b],
            tangent_acc[a:b], rates[a:b], acc, flags[a:b], hold_first, covers,
        )  # fmt: skip
        if status != SOLVED:
            return i, status
        island_slips(normal[a:b], slack[a:b], rates[a:b], slips[a:b])
    return -1, SOLVED


@njit
def island_slips(normal, slack, rates, slips):
    """slips: the sticking contacts whose slack is above settings.SLIP_ONSET of the island's
    scale (its largest |b_n|, at least 1) and that are pressed (normal force above SLIP_ONSET of
    the island's largest): see runtime.solve.friction.FrictionSolution."""
    scale = 1.0
    for r in rates:
        scale = max(scale, abs(r))
    largest = np.max(normal)
    for i in range(slips.size):
        slips[i] = slack[i] > _ONSET * scale and normal[i] > _ONSET * largest


def solve_held(
    jac, tangent_jac, ends, bias, tangent_bias, mu, slide, inv_mass, fixed, free_acc,
    normal, tangent, slack, tangent_acc, rates, acc, flags,
) -> bool:  # fmt: skip
    """Whether the island (every frictional contact sticking; :func:`solve_island`'s arguments
    and outputs) is solved with every contact held, d'' = 0 and a_t = 0: forces in the cones
    (f_n >= 0, |f_t| <= mu f_n) by a linear program (scipy's HiGHS), checked as a solution of
    the friction LCP to settings.LCP_TOL. The fallback of the module docstring, for when
    Lemke's method finds no solution or one that moves the island, and the first try of a
    large island (settings.HELD_FIRST)."""
    if np.any(slide != 0):
        return False
    M, q, stick = island_lcp(
        jac, tangent_jac, ends, bias, tangent_bias, mu, slide, inv_mass, fixed, free_acc, rates
    )
    k, s = mu.size, stick.size
    held = np.r_[np.arange(k), k + np.arange(s)]  # d'' = 0, and a_t = 0 with lambda = 0
    cone = np.zeros((s, k + 3 * s))  # f+ + f- - mu f_n <= 0
    cone[np.arange(s), stick] = -mu[stick]
    cone[np.arange(s), k + np.arange(s)] = cone[np.arange(s), k + s + np.arange(s)] = 1.0
    cost = np.r_[np.zeros(k), np.ones(2 * s), np.zeros(s)]  # no needless f+ and f- together
    bounds = [(0.0, None)] * (k + 2 * s) + [(0.0, 0.0)] * s
    found = held_forces(cost, cone, M[held], -q[held], bounds)
    if found.status != 0:
        return False
    z = np.maximum(found.x, 0.0)
    # HiGHS without presolve leaves its tolerances' dust on the vertex (a contact without normal
    # force kept 5.9e-12 N of friction beside 30 N; the basis of the unknowns left is singular
    # in a pile, so not solved again): below LCP_TOL of the largest, 0 -- the check decides
    z[z < settings.LCP_TOL * z.max(initial=0.0)] = 0.0
    if not _complementary(M, q, z, z > 0.0, settings.LCP_TOL):
        return False
    write_solution(z, z > 0.0, stick, jac, tangent_jac, ends, tangent_bias, mu, slide,
                   inv_mass, normal, tangent, slack, tangent_acc, acc, flags)  # fmt: skip
    return True


def held_forces(cost, cone, equations, rhs, bounds):
    """scipy's linprog (HiGHS) of :func:`solve_held`: min cost.x with cone x <= 0, equations x =
    rhs, within bounds -- without HiGHS's presolve, which corrupted the heap and aborted the
    process on one such 20-variable LP (scipy 1.17.1; a half disc in a V of walls with end
    vertices and mu = 0.5; tests/runtime/data/held_lp_presolve_crash.json; upstream HiGHS
    presolve crashes: scipy issues 17521, 22188). These LPs are small and dense."""
    return optimize.linprog(
        cost, cone, np.zeros(len(cone)), equations, rhs, bounds, method="highs",
        options={"presolve": False},
    )  # fmt: skip


def painleve(mu: np.ndarray, slide: np.ndarray, first: int = 0) -> FrictionInconsistent:
    """The error of an island whose friction LCP has no solution found; its rows: the island's
    sliding contacts (all of them if none slides), numbered from ``first``."""
    sliding = np.flatnonzero(slide != 0)
    return FrictionInconsistent(
        f"no contact forces obey Coulomb friction for {mu.size} contact(s) ({sliding.size} "
        f"sliding, mu up to {float(np.max(mu, initial=0.0)):.3g}): a Painleve "
        "configuration (Lemke's method ended on a ray)",
        (sliding if sliding.size else np.arange(mu.size)) + first,
    )
