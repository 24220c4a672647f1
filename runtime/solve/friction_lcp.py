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

from dataclasses import dataclass

import numpy as np

from runtime.solve import lemke
from runtime.solve.lcp_problem import ContactSolverError


class FrictionInconsistent(ContactSolverError):
    """No contact forces obey Coulomb's law here (a Painleve configuration: a sliding contact
    whose friction would have to pull it into the other body)."""


@dataclass(frozen=True)
class IslandForces:
    """The solved island: normal and tangential forces, the slack lambda (0 unless a sticking
    contact slips), the tangential accelerations a_t, the free rates b_n, and the accelerations
    ``acc`` (nb, 3) of the island's moving bodies ``bodies``."""

    normal: np.ndarray
    tangent: np.ndarray
    slack: np.ndarray
    tangent_acceleration: np.ndarray
    free_rates: np.ndarray
    bodies: np.ndarray
    acc: np.ndarray


def dense_rows(rows6, body1, body2, local, fixed, width) -> np.ndarray:
    """(K, 6) rows over the pair's bodies as (K, 3 nb) over the island's moving bodies."""
    out = np.zeros((len(rows6), width))
    for side, bodies in ((0, body1), (3, body2)):
        keep = np.flatnonzero(~fixed[bodies])
        cols = 3 * local[bodies[keep]][:, None] + np.arange(3)
        out[keep[:, None], cols] += rows6[keep, side : side + 3]
    return out


def solve_island(rows, bias, slide, inverse_mass, fixed, free_acc) -> IslandForces:
    """The forces of one island's contacts (``rows``: FrictionRows of the island, ``bias``
    its normal bias (stabilised if so), ``slide`` each contact's mode, 0 for a sticking or a
    frictionless one)."""
    b1, b2, mu = rows.body1, rows.body2, rows.mu
    ends = np.concatenate([b1, b2])
    bodies = np.unique(ends[~fixed[ends]])
    local = np.zeros(len(fixed), dtype=np.int64)
    local[bodies] = np.arange(bodies.size)
    width = 3 * bodies.size
    jn = dense_rows(rows.jacobian, b1, b2, local, fixed, width)
    jt = dense_rows(rows.tangent_jacobian, b1, b2, local, fixed, width)
    w = inverse_mass[bodies].ravel()
    a0 = free_acc[bodies].ravel()
    k = len(mu)
    columns = jn - (slide * mu)[:, None] * jt
    stick = np.flatnonzero((mu > 0) & (slide == 0))
    s = stick.size
    jts = jt[stick]
    b_n = jn @ a0 + bias
    b_s = jts @ a0 + rows.tangent_bias[stick]
    M = np.zeros((k + 3 * s, k + 3 * s))
    q = np.concatenate([b_n, b_s, -b_s, np.zeros(s)])
    A_nn, A_ns = (jn * w) @ columns.T, (jn * w) @ jts.T
    A_sn, A_ss = (jts * w) @ columns.T, (jts * w) @ jts.T
    plus, minus, slack = slice(k, k + s), slice(k + s, k + 2 * s), slice(k + 2 * s, k + 3 * s)
    M[:k, :k], M[:k, plus], M[:k, minus] = A_nn, A_ns, -A_ns
    M[plus, :k], M[plus, plus], M[plus, minus] = A_sn, A_ss, -A_ss
    M[minus, :k], M[minus, plus], M[minus, minus] = -A_sn, -A_ss, A_ss
    eye = np.eye(s)
    M[plus, slack], M[minus, slack] = eye, eye
    M[slack, plus], M[slack, minus] = -eye, -eye
    M[k + 2 * s + np.arange(s), stick] = mu[stick]
    z, status = lemke.solve(M, q)
    if status != lemke.SOLVED:
        sliding = np.flatnonzero(slide != 0)
        raise FrictionInconsistent(
            f"no contact forces obey Coulomb friction for {k} contact(s) ({sliding.size} "
            f"sliding, mu up to {float(np.max(mu, initial=0.0)):.3g}): a Painleve "
            "configuration (Lemke's method ended on a ray)",
            sliding.tolist() or list(range(k)),
        )
    normal = z[:k]
    tangent = -slide * mu * normal
    tangent[stick] = z[plus] - z[minus]
    lam = np.zeros(k)
    lam[stick] = z[slack]
    acc = a0 + w * (jn.T @ normal + jt.T @ tangent)
    a_t = jt @ acc + rows.tangent_bias
    return IslandForces(normal, tangent, lam, a_t, b_n, bodies, acc.reshape(-1, 3))
