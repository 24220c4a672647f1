"""Redundant contacts: the least-norm forces among all solutions, compiled.

Why: with redundant contacts (A singular: a box flat on three floor contacts, a disc wedged in a
slot) the LCP has a whole polyhedron of solutions. All of them give the same accelerations
(for positive semi-definite A, a = A f + b is the same for every solution), so every one moves
the bodies alike, but their forces differ and may be huge and opposed (39 N against 45 N where
3 N suffice). The policy: return the one of least Euclidean norm (sum of f_i^2, in N^2), which
is unique (a strictly convex objective over a convex set) and bounded by the data.

Every solution is zero off the held set P (rows with a = 0: joints and touching contacts) and
solves A_PP f_P = -b_P with f >= 0 at contacts, so the least-norm one solves the least-distance
problem  min sum w_i f_i^2  s.t.  E f = g,  f_contacts >= 0,  where, for a basis B of P's rows
(a pivoted rank-revealing factorization, runtime.solve.lcp_factor) and R = P \\ B, E = [I, T] with
T = S_BB^-1 S_BR and g = -S_BB^-1 b_B (the rows of R are combinations of B's). It is solved
first in R's forces alone (runtime.solve.lcp_reduced: f_B = g - T f_R, a QP in |R| unknowns,
a few where B has ~90 rows); where that reports failure (rounding makes it infeasible), by its
dual. The dual is
unconstrained and concave, max_l g.l - 1/2 sum_i w_i^-1 [(E^T l)_i]_+^2 (joints not clipped), with
f_i = [(E^T l)_i]_+ / w_i: a piecewise quadratic that a Newton method with a line search solves
exactly once it has found the right pieces (usually in 1-3 steps, the first being the
unconstrained least-norm solution over P). Rounding can make the problem infeasible by an ulp
(g_i = -1e-15 for two exactly opposed rows that carry nothing), which makes the dual unbounded
and would drive such a pair to huge opposed forces; so the dual carries a tiny proximal term
-mu/2 |l|^2 (mu = settings.LCP_LEAST_NORM_REGULAR of each row's curvature), which lets E f = g
be missed by mu l -- rounding -- and keeps the dual strongly concave. Scaled forces
f~ = sqrt(A_ii) f carry weights w_i = 1 / A_ii, so the norm is that of f in N, whatever the
scaling.
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_factor as fac
from runtime.solve.lcp_baraff import is_solution, refine
from runtime.solve.lcp_reduced import INFEASIBLE, SOLVED, reduced_outcome

_STEP_SLOPE = 1e-4  # Armijo: a step must gain this fraction of its first-order promise
_CONVERGED = settings.LCP_LEAST_NORM_DONE
_LOOSE = settings.LCP_LEAST_NORM_ENOUGH
_GROWTH = settings.LCP_LEAST_NORM_GROWTH
_REGULAR = settings.LCP_LEAST_NORM_REGULAR


UNIQUE, DONE, FAILED = 0, 1, 2  # least_norm's outcomes


@njit
def least_norm(S, b, joint, inv_w, held, count, dependent, tol, f_out):
    """Write the least-norm solution over ``held[:count]`` into ``f_out`` (0 elsewhere).
    Returns DONE if it solves the LCP to ``tol``; UNIQUE if the held rows are independent (the
    solution is unique, ``f_out`` untouched); FAILED if the Newton method did not converge or
    its forces fail the check (an ill-conditioned basis: ``f_out`` unspecified)."""
    L = np.empty((count, count))
    rows = np.empty(count, np.int64)
    k = fac.factor_basis(S, held, count, L, rows, dependent)
    return least_norm_factored(S, b, joint, inv_w, held, count, L, rows, k, tol, f_out)


@njit
def least_norm_factored(S, b, joint, inv_w, held, count, L, rows, k, tol, f_out):
    """least_norm with the basis of the held rows already found: ``rows[:k]`` and its factor
    ``L`` (lcp_factor.factor_basis of ``held[:count]``; neither is changed), for a caller that
    factored them for its own use."""
    m = b.size
    q = count - k
    if q == 0:
        return UNIQUE
    basis = np.zeros(m, np.bool_)
    for c in range(k):
        basis[rows[c]] = True
    others = np.empty(q, np.int64)
    n = 0
    for c in range(count):
        if not basis[held[c]]:
            others[n] = held[c]
            n += 1
    T = np.empty((k, q))
    rhs, x = np.empty(k), np.empty(k)
    for c in range(q):
        for i in range(k):
            rhs[i] = S[rows[i], others[c]]
        fac.solve(L, k, rhs, x)
        T[:, c] = x
    for i in range(k):
        rhs[i] = -b[rows[i]]
    g = np.empty(k)
    fac.solve(L, k, rhs, g)
    if _attempt(S, b, joint, inv_w, tol, T, g, L, rows, k, others, f_out) == DONE:
        return DONE
    # g's rounding of 0 (the large entries', carried into a row by the solve with S_BB and
    # grown by its conditioning) can make E f = g need a negative force or a spurious one:
    # infeasible by rounding, which the proximal dual spreads onto other rows, beyond a light
    # row's tolerance (seen: forces 1e6 apart, g_i = -1e-14 of the largest; and g_i = 1e-4
    # beside 3e6 with cond(S_BB) ~ 1e5). Entries within their rounding bound are 0 on a second
    # attempt; the check decides.
    bound = _rounding(S, b, rows, k, L, g)
    rounding = False
    for i in range(k):
        if g[i] != 0.0 and abs(g[i]) <= bound[i]:
            g[i] = 0.0
            rounding = True
    if not rounding:
        return FAILED
    return _attempt(S, b, joint, inv_w, tol, T, g, L, rows, k, others, f_out)


@njit
def _rounding(S, b, rows, k, L, g):
    """A bound on the rounding in g = -S_BB^-1 b_B (Skeel's, componentwise): 4 eps
    |S_BB^-1| (|S_BB| |g| + |b_B|), with S_BB^-1 column by column from the factor."""
    residual_size = np.empty(k)
    for i in range(k):
        total = abs(b[rows[i]])
        for j in range(k):
            total += abs(S[rows[i], rows[j]] * g[j])
        residual_size[i] = total
    bound, unit, column = np.zeros(k), np.zeros(k), np.empty(k)
    for j in range(k):
        unit[:] = 0.0
        unit[j] = 1.0
        fac.solve(L, k, unit, column)
        for i in range(k):
            bound[i] += abs(column[i]) * residual_size[j]
    return 4.0 * np.finfo(np.float64).eps * bound


@njit
def least_distance(T, g, wB, wR, jB, jR, fB, fR):
    """The least-distance problem (see dual_newton) in the redundant rows' forces
    (runtime.solve.lcp_reduced), or by the dual Newton method where that fails for another
    reason than a proof that the problem is infeasible (False then)."""
    outcome = reduced_outcome(T, g, wB, wR, jB, jR, fB, fR)
    if outcome == SOLVED:
        return True
    if outcome == INFEASIBLE:
        return False
    return dual_newton(T, g, wB, wR, jB, jR, fB, fR)


@njit
def _attempt(S, b, joint, inv_w, tol, T, g, L, rows, k, others, f_out):
    """The least-distance problem's forces into f_out, checked (again after refining a_B = 0
    with the basis, should T's conditioning have cost accuracy): DONE or FAILED."""
    m, q = b.size, others.size
    f_basis, f_others = np.empty(k), np.empty(q)
    done = least_distance(
        T, g, inv_w[rows[:k]], inv_w[others], joint[rows[:k]], joint[others], f_basis, f_others
    )
    f_out[:] = 0.0
    for c in range(k):
        f_out[rows[c]] = f_basis[c]
    for c in range(q):
        f_out[others[c]] = f_others[c]
    if not done:
        return FAILED
    _drop_noise(f_out)
    a, tol_a = np.empty(m), np.empty(m)
    if is_solution(S, b, joint, f_out, tol, a, tol_a):
        return DONE
    refine(S, b, f_out, L, rows, k)
    return DONE if is_solution(S, b, joint, f_out, tol, a, tol_a) else FAILED


@njit
def _drop_noise(f):
    """Set forces at rounding level of the largest (settings.LCP_NOISE) to 0: they are what is
    left of cancelling terms, and a row they touch may have nothing else to be measured by."""
    top = 0.0
    for i in range(f.size):
        top = max(top, abs(f[i]))
    for i in range(f.size):
        if abs(f[i]) <= settings.LCP_NOISE * top:
            f[i] = 0.0


@njit
def _forces(T, g, lam, centre, mu, wB, wR, jB, jR, fB, fR, uR, grad):
    """f(l) = [E^T l]_+ / w and the dual's gradient g - E f - mu (l - centre); returns the dual
    objective g.l - 1/2 sum w u_+^2 - 1/2 mu |l - centre|^2."""
    r, q = T.shape
    phi = 0.0
    for i in range(r):
        u = lam[i]
        phi += g[i] * u - 0.5 * mu[i] * (u - centre[i]) ** 2
        if jB[i] or u > 0.0:
            fB[i] = wB[i] * u
            phi -= 0.5 * wB[i] * u * u
        else:
            fB[i] = 0.0
    for c in range(q):
        u = 0.0
        for i in range(r):
            u += T[i, c] * lam[i]
        uR[c] = u
        if jR[c] or u > 0.0:
            fR[c] = wR[c] * u
            phi -= 0.5 * wR[c] * u * u
        else:
            fR[c] = 0.0
    for i in range(r):
        s = g[i] - fB[i] - mu[i] * (lam[i] - centre[i])
        for c in range(q):
            s -= T[i, c] * fR[c]
        grad[i] = s
    return phi


@njit
def dual_newton(T, g, wB, wR, jB, jR, fB, fR):
    """The least-distance problem min sum f_i^2 / w_i s.t. f_B + T f_R = g, contacts >= 0, by
    Newton's method on its (proximally regularized) dual (``w`` here are the inverse weights
    A_ii / max A_jj). Fills fB, fR; True when the dual's gradient is at rounding level.

    The proximal term lets E f = g be missed by mu l: rounding beside the largest row, but not
    always for a light row coupled to heavy ones, whose multiplier the heavy rows make huge
    (forces 1e6 apart: a light row missed its LCP tolerance twice over). So while a row misses
    its own terms' rounding, proximal-point passes re-centre the term at the last l and solve
    again, each shrinking the miss by mu / (mu + curvature); a pass that would enlarge the
    forces (a miss the equations cannot meet with f >= 0, rounding of 0 needing f < 0) is not
    taken."""
    r, q = T.shape
    mu = wB.copy()
    for i in range(r):
        for c in range(q):
            mu[i] += wR[c] * T[i, c] * T[i, c]
        mu[i] *= _REGULAR
    lam, centre = np.zeros(r), np.zeros(r)
    done = _newton(T, g, lam, centre, mu, wB, wR, jB, jR, fB, fR, True)
    trial, fB_t, fR_t = np.empty(r), np.empty(r), np.empty(q)
    for _ in range(3):
        if _rows_met(T, g, fB, fR):
            break
        centre[:] = lam
        trial[:] = lam
        if not _newton(T, g, trial, centre, mu, wB, wR, jB, jR, fB_t, fR_t, False):
            break
        if _objective(fB_t, fR_t, wB, wR) > _objective(fB, fR, wB, wR) * (1.0 + _GROWTH):
            break
        lam[:] = trial
        fB[:] = fB_t
        fR[:] = fR_t
        done = True
    return done


@njit
def _newton(T, g, lam, centre, mu, wB, wR, jB, jR, fB, fR, everything):
    """Newton's method with a line search on the dual, proximal about ``centre``, from ``lam``
    (updated). A full step that keeps every row on its piece solves the dual's quadratic there
    exactly, so it is taken even when rounding hides its gain in the objective; after it only
    rounding is left. ``everything``: the first step takes every row as active (the
    unconstrained least norm)."""
    r, q = T.shape
    trial, step = np.empty(r), np.empty(r)
    grad, grad_t = np.empty(r), np.empty(r)
    uR, uR_t = np.empty(q), np.empty(q)
    fB_t, fR_t = np.empty(r), np.empty(q)
    H, scratch = np.empty((r, r)), np.empty((r, r))
    phi = _forces(T, g, lam, centre, mu, wB, wR, jB, jR, fB, fR, uR, grad)
    for _ in range(100):
        H[:, :] = 0.0
        for i in range(r):
            H[i, i] = mu[i]
            if everything or jB[i] or lam[i] > 0.0:
                H[i, i] += wB[i]
        for c in range(q):
            if everything or jR[c] or uR[c] > 0.0:
                for i in range(r):
                    t = wR[c] * T[i, c]
                    if t != 0.0:
                        for p in range(r):
                            H[i, p] += t * T[p, c]
        if not fac.cholesky_solve(H, grad, step, scratch):
            return False
        slope = 0.0
        for i in range(r):
            slope += grad[i] * step[i]
        t = 1.0
        accepted = same = False
        for _ in range(60):
            for i in range(r):
                trial[i] = lam[i] + t * step[i]
            phi_t = _forces(T, g, trial, centre, mu, wB, wR, jB, jR, fB_t, fR_t, uR_t, grad_t)
            same = t == 1.0 and _same_pieces(lam, uR, trial, uR_t, jB, jR, everything)
            if same or phi_t >= phi + _STEP_SLOPE * t * slope:
                accepted = True
                break
            t *= 0.5
        if not accepted:
            return _converged(T, g, fB, fR, _LOOSE)
        lam[:] = trial
        fB[:] = fB_t
        fR[:] = fR_t
        uR[:] = uR_t
        grad[:] = grad_t
        phi = phi_t
        everything = False
        if _converged(T, g, fB, fR, _CONVERGED):
            return True
        if same:
            return _converged(T, g, fB, fR, _LOOSE)
    return False


@njit
def _rows_met(T, g, fB, fR):
    """Whether every row of E f = g holds to _CONVERGED of its own terms, or to rounding of
    the largest row's (which the solve with S_BB carries into every row)."""
    sizes, misses = _residual(T, g, fB, fR)
    if sizes.size == 0:
        return True
    floor = 16.0 * np.finfo(np.float64).eps * np.max(sizes)
    for i in range(sizes.size):
        if abs(misses[i]) > max(_CONVERGED * sizes[i], floor):
            return False
    return True


@njit
def _objective(fB, fR, wB, wR):
    """sum f_i^2 / w_i, the least-distance objective (rows of weight 0 carry no force)."""
    total = 0.0
    for i in range(fB.size):
        if wB[i] > 0.0:
            total += fB[i] * fB[i] / wB[i]
    for c in range(fR.size):
        if wR[c] > 0.0:
            total += fR[c] * fR[c] / wR[c]
    return total


@njit
def _same_pieces(lam, uR, trial, uR_t, jB, jR, everything):
    """Whether every row is active at ``trial`` exactly where it was for the last Newton
    matrix (every row, on the first step)."""
    for i in range(lam.size):
        if not jB[i] and (trial[i] > 0.0) != (everything or lam[i] > 0.0):
            return False
    for c in range(uR.size):
        if not jR[c] and (uR_t[c] > 0.0) != (everything or uR[c] > 0.0):
            return False
    return True


@njit
def _converged(T, g, fB, fR, bound):
    """Whether E f = g holds to ``bound`` times the size of its terms (the largest row's: a
    row whose g is rounding of 0 and cannot be met with f >= 0 is met). The proximal term may
    only absorb rounding: a miss beyond it means the equations were not solved."""
    sizes, misses = _residual(T, g, fB, fR)
    return sizes.size == 0 or np.max(np.abs(misses)) <= bound * np.max(sizes)


@njit
def _residual(T, g, fB, fR):
    """Row by row, the size of E f = g's terms and its miss g - E f."""
    r, q = T.shape
    sizes, misses = np.empty(r), np.empty(r)
    for i in range(r):
        sizes[i], misses[i] = abs(g[i]) + abs(fB[i]), g[i] - fB[i]
        for c in range(q):
            sizes[i] += abs(T[i, c] * fR[c])
            misses[i] -= T[i, c] * fR[c]
    return sizes, misses
