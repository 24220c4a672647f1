"""Independent references for the contact-force solver's tests (tests/runtime/test_lcp*.py).

Nothing here imports runtime.solve: the problems are built from bodies and contacts
(A = J M^-1 J^T), and the answers come from brute force over clamped sets, NumPy's SVD and
scipy.optimize (nnls), so a test that compares with them checks the solver against code that
shares none of its algorithms.

* ``contact_matrix``: J, M^-1 and A for contacts between planar rigid bodies and the ground;
* ``feasible_b``: b = a0 - A f0 for a chosen solution (f0, a0), so the problem is solvable and
  its acceleration a0 is known (the same for every solution when A is PSD);
* ``brute_force``: every solution with a nonsingular clamped block, by enumeration (n <= 10);
* ``least_norm_qp``: the least-norm solution over the held rows of a known acceleration, a
  least-distance QP solved through scipy.optimize.nnls (Lawson and Hanson's reduction), the
  held rows' equations first reduced to an independent set by SVD;
* ``row_violation``: each row's violation of the LCP conditions and its componentwise scale.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
from scipy.optimize import nnls

G = 9.81


@dataclass
class Contact:
    """A contact row: body1 pressed by body2 (-1: the fixed ground) along ``normal`` (from body 2
    toward body 1) at the given levers from the bodies' centres of mass."""

    body1: int
    body2: int
    normal: tuple[float, float]
    lever1: tuple[float, float]
    lever2: tuple[float, float] = (0.0, 0.0)


def contact_matrix(
    masses, inertias, contacts: list[Contact]
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A, J, M^-1 diagonal) with J the gap Jacobian rows d(gap)/d(x, y, theta) of each body."""
    n = len(masses)
    J = np.zeros((len(contacts), 3 * n))
    for k, c in enumerate(contacts):
        nx, ny = c.normal
        J[k, 3 * c.body1 : 3 * c.body1 + 3] += [nx, ny, c.lever1[0] * ny - c.lever1[1] * nx]
        if c.body2 >= 0:
            J[k, 3 * c.body2 : 3 * c.body2 + 3] -= [nx, ny, c.lever2[0] * ny - c.lever2[1] * nx]
    inverse = np.repeat(1.0 / np.asarray(masses, float), 3)
    inverse[2::3] = 1.0 / np.asarray(inertias, float)
    return (J * inverse) @ J.T, J, inverse


def gravity_b(J: np.ndarray, inverse: np.ndarray, gravity=(0.0, -G)) -> np.ndarray:
    """b = J M^-1 F for gravity on every body (F = m g, so M^-1 F = g)."""
    acc = np.zeros(J.shape[1])
    acc[0::3], acc[1::3] = gravity
    return J @ acc


def feasible_b(A, f0, a0) -> np.ndarray:
    """b with (f0, a0) a solution: a0 = A f0 + b."""
    return a0 - A @ f0


def row_violation(A, b, joint, f) -> tuple[np.ndarray, np.ndarray]:
    """(violation, scale) per row: contacts: max(-f, -a, |a| if f > 0); joints: |a|; scale:
    sum_j |A_ij f_j| + |b_i| (the solver's componentwise measure)."""
    a = A @ f + b
    scale = np.abs(A) @ np.abs(f) + np.abs(b)
    held = joint | (f > 0)
    violation = np.where(held, np.abs(a), np.maximum(-a, 0.0))
    violation = np.where(~joint & (f < 0), np.maximum(violation, -f * np.diagonal(A)), violation)
    return violation, scale


def brute_force(A, b, joint, tol: float = 1e-9) -> list[tuple[np.ndarray, np.ndarray]]:
    """All (f, a) with f solving A_SS f_S = -b_S for a nonsingular A_SS, valid everywhere.

    Any solution reduces to one with a nonsingular A_SS (move along a null vector of A_SS,
    which is also one of A, until a force reaches 0), so this finds one if one exists.
    """
    n = len(b)
    found = []
    for bits in itertools.product((False, True), repeat=n):
        S = np.array(bits, bool)
        f = np.zeros(n)
        if S.any():
            ASS = A[np.ix_(S, S)]
            if np.linalg.cond(ASS) > 1e10:
                continue
            f[S] = np.linalg.solve(ASS, -b[S])
        a = A @ f + b
        if (
            np.all(f[S & ~joint] >= -tol)
            and np.all(a[~S & ~joint] >= -tol)
            and np.all(np.abs(a[~S & joint]) <= tol)
        ):
            found.append((f, a))
    return found


def least_norm_qp(A, b, joint, a, held_tol: float) -> np.ndarray:
    """min |f|^2 over the solutions with acceleration a: f = 0 where a_i > held_tol, A_PP f_P =
    -b_P on the held rows P (reduced by SVD to independent equations E f = c), f >= 0 at
    contacts. A least-distance problem (min |x| s.t. G x >= h), solved exactly by Lawson and
    Hanson's reduction to non-negative least squares ("Solving Least Squares Problems", ch. 23):
    u >= 0 minimising |[G^T; h^T] u - e_(n+1)| gives x = -r_(1..n) / r_(n+1), r the residual."""
    P = joint | (np.abs(a) <= held_tol)
    idx = np.flatnonzero(P)
    f = np.zeros(len(b))
    if idx.size == 0:
        return f
    APP, bP = A[np.ix_(idx, idx)], b[idx]
    U, s, _ = np.linalg.svd(APP)
    r = int(np.sum(s > 1e-10 * s[0])) if s[0] > 0 else 0
    E, c = U[:, :r].T @ APP, -U[:, :r].T @ bP
    n = idx.size
    bounds = np.eye(n)[~joint[idx]]
    G = np.vstack([bounds, E, -E])
    h = np.concatenate([np.zeros(len(bounds)), c, -c])
    M = np.vstack([G.T, h[None, :]])
    e = np.zeros(n + 1)
    e[n] = 1.0
    u, _ = nnls(M, e, maxiter=50 * M.shape[1])
    residual = M @ u - e
    assert abs(residual[n]) > 1e-12, "the least-distance problem is infeasible"
    f[idx] = -residual[:n] / residual[n]
    return f
