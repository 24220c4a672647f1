"""The least-norm stage's least-distance problem, solved in the redundant rows' forces.

    solved = reduced_least_distance(T, g, wB, wR, jB, jR, fB, fR)

The problem of runtime.solve.lcp_minnorm: min sum f_i^2 / w_i subject to f_B + T f_R = g and
f >= 0 at contacts, over a basis B of the held rows and the rest R (the rows that depend on B).
Its equations give f_B = g - T f_R, so with z = f_R it is

    min 1/2 z^T H z + c^T z,   H = T^T W_B^-1 T + W_R^-1,   c = -T^T W_B^-1 g,
    subject to z_c >= 0 (contacts of R) and g_i - (T z)_i >= 0 (contacts of B),

a strictly convex QP in q = |R| unknowns. Why: in a pile q is a few (a landing pile of 50 discs:
~90 held rows, 1-9 redundant), while the dual Newton method of runtime.solve.lcp_minnorm works
in the k = |B| unknowns of the equations, a k x k Cholesky per Newton step (~0.5 ms of every
warm-started solve of such a pile, measured). Here a step costs O(k q + q^3).

Method: Goldfarb and Idnani's dual active-set method (Math. Programming 27, 1983), which needs
no feasible start: from the unconstrained minimum, add the most violated constraint, moving
along the direction that keeps the active ones active and dropping an active one whose
multiplier would turn negative, until none is violated. Each step is solved afresh from H^-1
and the active normals (q is small), not by the method's updated factorizations. A constraint
missed by less than settings.LCP_LEAST_NORM_DONE of the largest row's terms is met, as the
dual Newton method's equations are: g of a row that carries nothing is rounding of 0, and
when it is just below 0 (a random problem: -2.7e-12 beside 133) enforcing f >= 0 there drove
the others to forces 100x the least-norm ones. It reports False -- the caller then uses the
dual Newton method -- when a row has no weight, the QP is infeasible, the active normals are
dependent, or the iterations run out. :func:`reduced_outcome` tells infeasibility apart: a
violated constraint that no step can meet while the active ones stay met (the dual step is
unbounded), which is a proof that no forces >= 0 solve the equations; the dual Newton method
is then not tried (its dual is unbounded too: it ran its 100 steps of a k x k Cholesky, 4-12 ms
on a landing pile's 90-row islands, and failed).
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_factor as fac

_MET = settings.LCP_LEAST_NORM_DONE


FAILED, SOLVED, INFEASIBLE = 0, 1, 2  # reduced_outcome's


@njit
def reduced_least_distance(T, g, wB, wR, jB, jR, fB, fR):
    """See the module docstring: fB (k,), fR (q,) written; True when solved."""
    return reduced_outcome(T, g, wB, wR, jB, jR, fB, fR) == SOLVED


@njit
def reduced_outcome(T, g, wB, wR, jB, jR, fB, fR):
    """reduced_least_distance, telling SOLVED, INFEASIBLE (a constraint missed beyond
    settings.LCP_LEAST_NORM_DONE that no step can meet with the active ones kept: no forces
    >= 0 solve the equations) and FAILED (any other reason)."""
    k, q = T.shape
    for i in range(k):
        if not wB[i] > 0.0:
            return FAILED
    for c in range(q):
        if not wR[c] > 0.0:
            return FAILED
    H, scratch = np.empty((q, q)), np.empty((q, q))
    c_lin = np.zeros(q)
    for a in range(q):
        for b in range(a + 1):
            s = 0.0
            for i in range(k):
                s += T[i, a] * T[i, b] / wB[i]
            H[a, b] = s
            H[b, a] = s
        H[a, a] += 1.0 / wR[a]
        for i in range(k):
            c_lin[a] -= T[i, a] * g[i] / wB[i]
    H_inv, unit, column = np.empty((q, q)), np.zeros(q), np.empty(q)
    if not fac.cholesky(H, q, scratch):
        return FAILED
    for a in range(q):  # H^-1 column by column from the one factor
        unit[:] = 0.0
        unit[a] = 1.0
        fac.solve(scratch, q, unit, column)
        H_inv[:, a] = column
    z = np.zeros(q)
    for a in range(q):
        for b in range(q):
            z[a] -= H_inv[a, b] * c_lin[b]
    # constraints j < k: row j of B (normal -T_j, value g_j - T_j z); j >= k: z_(j-k) >= 0
    count = k + q
    skip = np.zeros(count, np.bool_)  # joints (no sign) and the active set
    for i in range(k):
        skip[i] = jB[i]
    for c in range(q):
        skip[k + c] = jR[c]
    active = np.empty(q, np.int64)
    lam = np.zeros(q)
    n_active = 0
    normal, h_n, dz, values = np.empty(q), np.empty(q), np.empty(q), np.empty(count)
    for _ in range(4 * (count + q) + 8):
        # a miss below _MET of the largest row's terms is met, as the dual Newton method's
        # equations are (a row whose g is rounding of 0 may need a force < 0 by ~1e-12 of the
        # largest: made active, it drives the others to large opposed forces)
        floor = 0.0
        for j in range(count):
            values[j], size = _constraint(T, g, z, j, k)
            floor = max(floor, _MET * size)
        p, worst = -1, 0.0
        for j in range(count):
            if not skip[j] and values[j] < -floor and values[j] < worst:
                p, worst = j, values[j]
        if p < 0:
            _forces(T, g, z, jB, jR, fB, fR)
            return SOLVED
        _normal(T, p, k, normal)
        lam_p = 0.0
        while True:  # raise p's multiplier until p is active (or a drop is needed first)
            dl = _direction(H_inv, T, active, n_active, k, normal, h_n, dz)
            if dl.size != n_active:  # the active normals are (nearly) dependent
                return FAILED
            block, t_drop = -1, np.inf
            for a in range(n_active):
                if dl[a] < 0.0 and -lam[a] / dl[a] < t_drop:
                    block, t_drop = a, -lam[a] / dl[a]
            rate = 0.0
            curvature = 0.0
            for a in range(q):
                rate += normal[a] * dz[a]
                curvature += normal[a] * h_n[a]
            value, _ = _constraint(T, g, z, p, k)
            if rate <= 1e-12 * curvature:  # p depends on the active set: a dual step only
                if block < 0:
                    return INFEASIBLE
                t = t_drop
            else:
                t = min(-value / rate, t_drop)
                for a in range(q):
                    z[a] += t * dz[a]
            for a in range(n_active):
                lam[a] += t * dl[a]
            lam_p += t
            if block >= 0 and t == t_drop:  # the blocking constraint leaves the active set
                skip[active[block]] = False
                for a in range(block, n_active - 1):
                    active[a], lam[a] = active[a + 1], lam[a + 1]
                n_active -= 1
                continue
            if n_active == q:
                return FAILED
            active[n_active], lam[n_active] = p, lam_p
            n_active += 1
            skip[p] = True
            break
    return FAILED


@njit
def _constraint(T, g, z, j, k):
    """(value, size) of constraint j: g_j - T_j z for a row of B, z_c for one of R; size is
    the sum of its terms' magnitudes (what rounding is relative to)."""
    if j >= k:
        return z[j - k], abs(z[j - k])
    value, size = g[j], abs(g[j])
    for a in range(z.size):
        term = T[j, a] * z[a]
        value -= term
        size += abs(term)
    return value, size


@njit
def _normal(T, j, k, out):
    """The gradient of constraint j in z."""
    if j >= k:
        out[:] = 0.0
        out[j - k] = 1.0
    else:
        for a in range(out.size):
            out[a] = -T[j, a]


@njit
def _direction(H_inv, T, active, n_active, k, normal, h_n, dz):
    """The step per unit of the new multiplier: dz = H^-1 (n_p + N^T dl) with N dz = 0 (the
    active constraints stay active), dl = -(N H^-1 N^T)^-1 N H^-1 n_p; h_n = H^-1 n_p.
    Returns dl (an empty array if N H^-1 N^T is not positive definite)."""
    q, r = normal.size, n_active
    for a in range(q):
        total = 0.0
        for b in range(q):
            total += H_inv[a, b] * normal[b]
        h_n[a] = total
    dz[:] = h_n
    if r == 0:
        return np.empty(0)
    N, NH = np.empty((r, q)), np.zeros((r, q))
    for a in range(r):
        _normal(T, active[a], k, N[a])
        for b in range(q):
            for c in range(q):
                NH[a, b] += N[a, c] * H_inv[c, b]
    M, rhs = np.zeros((r, r)), np.zeros(r)
    for a in range(r):
        for b in range(r):
            for c in range(q):
                M[a, b] += NH[a, c] * N[b, c]
        for c in range(q):
            rhs[a] -= N[a, c] * h_n[c]
    dl, scratch = np.empty(r), np.empty((r, r))
    if not fac.cholesky_solve(M, rhs, dl, scratch):
        return np.empty(0)
    for b in range(q):
        for a in range(r):
            dz[b] += NH[a, b] * dl[a]
    return dl


@njit
def _forces(T, g, z, jB, jR, fB, fR):
    """f_R = z and f_B = g - T z, contacts' rounding below 0 set to 0."""
    k = g.size
    for i in range(k):
        value, _ = _constraint(T, g, z, i, k)
        fB[i] = value if jB[i] or value > 0.0 else 0.0
    for c in range(z.size):
        fR[c] = z[c] if jR[c] or z[c] > 0.0 else 0.0
