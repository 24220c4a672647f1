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
"""

from __future__ import annotations

import numpy as np

from runtime.compiled import njit
from runtime.solve.lcp_problem import ContactSolverError
from runtime.solve.lemke import SOLVED, lemke_perturbed


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
def solve_island(
    jac, tangent_jac, ends, bias, tangent_bias, mu, slide, inv_mass, fixed, free_acc,
    normal, tangent, slack, tangent_acc, rates, acc,
):  # fmt: skip
    """The forces of one island's K contacts (``ends`` (K, 2): body 1 and 2; ``bias`` the normal
    bias, stabilised if so; ``slide`` each contact's mode, 0 for a sticking or a frictionless
    one), written to ``normal``, ``tangent``, ``slack``, ``tangent_acc`` (a_t), ``rates`` (the
    free d'', b_n); ``acc`` (n, 3) gets the forces' accelerations added. Returns Lemke's status.
    """
    k = mu.size
    cols = jac.copy()  # the normal columns, with sliding contacts' friction folded in
    for i in range(k):
        for c in range(6):
            cols[i, c] -= slide[i] * mu[i] * tangent_jac[i, c]
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
    z = np.zeros(n)
    status = lemke_perturbed(M, q, z)
    if status != SOLVED:
        return status
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
    return status


def painleve(mu: np.ndarray, slide: np.ndarray) -> FrictionInconsistent:
    """The error of an island whose friction LCP has no solution found."""
    sliding = np.flatnonzero(slide != 0)
    return FrictionInconsistent(
        f"no contact forces obey Coulomb friction for {mu.size} contact(s) ({sliding.size} "
        f"sliding, mu up to {float(np.max(mu, initial=0.0)):.3g}): a Painleve "
        "configuration (Lemke's method ended on a ray)",
        sliding.tolist() or list(range(mu.size)),
    )
