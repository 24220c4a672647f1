"""Independent references for the contact-force solver's tests (tests/runtime/test_lcp*.py).

Nothing here imports runtime.solve: the problems are built from bodies and contacts
(A = J M^-1 J^T), and the answers come from brute force over clamped sets, NumPy's SVD and
scipy.optimize (nnls), so a test that compares with them checks the solver against code that
shares none of its algorithms.

* ``contact_matrix``: J, M^-1 and A for contacts between planar rigid bodies and the ground;
* ``packed_pile``: a statically indeterminate pile of discs, at rest;
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


def packed_pile(long_row: int, rows: int):
    """Discs (radius 1/2, 1 kg) packed hexagonally wall to wall in a box: long rows of
    ``long_row`` discs touching each other and both walls, short rows of one fewer in the
    notches. Every contact is central (no torque) and the set is statically indeterminate:
    its forces are not unique, a = A f + b = 0 for all of them. Returns (A, b, J, M^-1)."""
    index, contacts, s = {}, [], np.sqrt(3.0) / 2
    for r in range(rows):
        for i in range(long_row - r % 2):
            index[r, i] = len(index)
    for (r, i), k in index.items():
        if r == 0:
            contacts.append(Contact(k, -1, (0.0, 1.0), (0.0, -0.5)))  # the floor
        if i == 0 and r % 2 == 0:
            contacts.append(Contact(k, -1, (1.0, 0.0), (-0.5, 0.0)))  # the left wall
        if i == long_row - 1 and r % 2 == 0:
            contacts.append(Contact(k, -1, (-1.0, 0.0), (0.5, 0.0)))  # the right wall
        if (r, i - 1) in index:
            contacts.append(Contact(k, index[r, i - 1], (1.0, 0.0), (-0.5, 0.0), (0.5, 0.0)))
        for j, side in ((i - 1 + r % 2, 1.0), (i + r % 2, -1.0)):  # the two below
            if r > 0 and (r - 1, j) in index:
                normal = (side * 0.5, s)  # from the disc below, up and across
                contacts.append(Contact(k, index[r - 1, j], normal,
                                        (-side * 0.25, -s / 2), (side * 0.25, s / 2)))  # fmt: skip
    n = len(index)
    A, J, inverse = contact_matrix(np.ones(n), np.full(n, 0.125), contacts)
    return A, gravity_b(J, inverse), J, inverse


def feasible_b(A, f0, a0) -> np.ndarray:
    """b with (f0, a0) a solution: a0 = A f0 + b."""
    return a0 - A @ f0


def row_violation(A, b, joint, f) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(violation, scale, unit) per row: contacts: max(-f, -a, |a| if f > 0); joints: |a|;
    scale: sum_j |A_ij f_j| + |b_i| (the solver's componentwise measure); unit: sqrt(A_ii)
    max_j(|b_j| / sqrt(A_jj), |f_j| sqrt(A_jj)), the largest term in the units of row i (the
    solver adds a tiny multiple of it to every row's tolerance)."""
    a = A @ f + b
    scale = np.abs(A) @ np.abs(f) + np.abs(b)
    root = np.sqrt(np.diagonal(A))
    live = root > 0
    unit = root * max(np.max(np.abs(b[live]) / root[live], initial=0), np.max(np.abs(f) * root))
    held = joint | (f > 0)
    violation = np.where(held, np.abs(a), np.maximum(-a, 0.0))
    violation = np.where(~joint & (f < 0), np.maximum(violation, -f * np.diagonal(A)), violation)
    return violation, scale, unit


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


class OracleUndecided(ArithmeticError):
    """The oracle's own rounding decides the answer (b at rounding level of A f, say): no
    reference for this problem."""


def least_norm_qp(A, b, joint, a, held_tol: float) -> np.ndarray:
    """min |f|^2 over the solutions with acceleration a: f = 0 where a_i > held_tol, A_PP f_P =
    -b_P on the held rows P, f >= 0 at contacts. By SVD, f = p + N z with p the pseudo-inverse
    solution and N an orthonormal basis of A_PP's null space (p is orthogonal to it), so the
    problem is min |z| s.t. N z >= -p at contacts: a least-distance problem, solved exactly by
    Lawson and Hanson's reduction to non-negative least squares ("Solving Least Squares
    Problems", ch. 23): u >= 0 minimising |[G^T; h^T] u - e| gives z = -r_(1..k) / r_(k+1).
    Rows with A_ii = 0 must not be held (the tests' problems have none)."""
    P = joint | (np.abs(a) <= held_tol)
    idx = np.flatnonzero(P)
    f = np.zeros(len(b))
    if idx.size == 0:
        return f
    APP, bP = A[np.ix_(idx, idx)], b[idx]
    D = 1.0 / np.sqrt(np.diagonal(APP))  # rank decided on D A D (unit diagonal): any units
    U, s, Vt = np.linalg.svd(D[:, None] * APP * D[None, :])
    r = int(np.sum(s > 1e-10 * s[0]))
    solution = D * (Vt[:r].T @ ((U[:, :r].T @ (-D * bP)) / s[:r]))
    N, _ = np.linalg.qr(D[:, None] * Vt[r:].T)  # null(A_PP) = D null(D A D), orthonormalized
    particular = solution - N @ (N.T @ solution)  # orthogonal to the null space
    k = N.shape[1]
    contact = ~joint[idx]
    if k == 0 or not contact.any():
        f[idx] = particular
        return f
    top = max(float(np.max(np.abs(particular))), 1e-300)  # the problem is homogeneous in p
    slack = 64 * np.finfo(float).eps * s[0] / s[r - 1]  # p's rounding may cut off the bounds
    G, h = N[contact], -particular[contact] / top - slack
    M = np.vstack([G.T, h[None, :]])
    e = np.zeros(k + 1)
    e[k] = 1.0
    u, _ = nnls(M, e, maxiter=100 * M.shape[1])
    residual = M @ u - e
    if not abs(residual[k]) > 1e-12:  # feasible (a solution is known): p's rounding cut it off
        raise OracleUndecided("the least-distance problem is infeasible after rounding")
    f[idx] = particular + top * (N @ (-residual[:k] / residual[k]))
    return f
