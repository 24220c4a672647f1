"""The sparse path of the contact-force solve, for islands of hundreds to thousands of contacts.

Why: a pile's A = J M^-1 J^T has a handful of non-zeros per row (a contact couples only to the
contacts of its two bodies), so the dense solver's O(m^3) factorizations waste almost all of
their work. Here the rows are put in reverse Cuthill-McKee order (scipy.sparse.csgraph), and the
clamped block is factored within its envelope, leaving out dependent rows exactly as the dense
factor does (runtime.solve.lcp_envelope).

The clamped set is found by block principal pivoting (the primal-dual active-set method):
solve on the current set G; drop contacts with f < 0, add those outside with a < 0; repeat.
Warm-started from the previous set it usually ends after one factorization; cold, it starts
from every row clamped (a resting pile mostly is). A starting set with dependent rows whose
basic forces do not hold (a pile packed wall to wall: statically indeterminate) is first tried
with its least-norm forces, which hold where the set is right. A set that stops losing
violations for three rounds switches to one exchange per round (Murty's rule, the Judice-Pires
safeguard); if that fails too, the island goes to the dense compiled solver
(runtime.solve.lcp_dense), warm-started from the best set. Redundant rows get the dense path's
least-norm policy (runtime.solve.lcp_minnorm, the reduced QP of runtime.solve.lcp_reduced
first), with the basis the envelope factor finds in its order.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import reverse_cuthill_mckee

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp_dense
from runtime.solve import lcp_envelope as env
from runtime.solve.lcp_baraff import INFEASIBLE, MIN_NORM, OK, PIVOTS, STUCK
from runtime.solve.lcp_minnorm import DONE, FAILED, UNIQUE, least_distance

_ROUNDS = 50  # block pivoting rounds before the dense fallback (a warm start needs 1-3)
_PATIENCE = 3  # rounds without fewer violations before one exchange per round


@njit
def _violations(joint, member, kept, f, a, tol_a, out):
    """Mark the rows to exchange: held contacts with f < 0, others with a < 0, and dependent
    held rows whose a is not 0 (their set is inconsistent). Returns their number."""
    n = 0
    for i in range(f.size):
        if member[i] and not joint[i] and kept[i] and f[i] < 0.0:
            bad = True
        elif not member[i] and not joint[i] and a[i] < -tol_a[i]:
            bad = True
        else:
            bad = member[i] and not kept[i] and abs(a[i]) > tol_a[i] and (joint[i] or a[i] < 0)
        out[i] = bad
        n += bad
    return n


@njit
def pivot_blocks(S, envelope, b, joint, member, tol, counts, f, redundant_stop):
    """Block principal pivoting from ``member`` (updated in place), exchanging rows violated
    beyond settings.LCP_SHARP, accepting within ``tol``. ``S`` = (indptr, indices, data),
    ``envelope`` = (first, offset, values). Returns (status, smallest pivot ratio of the last
    factor, whether it kept every member); f on success. ``redundant_stop``: return STUCK at
    once, ``member`` unchanged, where the first set has dependent rows and its basic forces do
    not hold (the caller tries its least-norm forces first)."""
    indptr, indices, data = S
    first, offset, values = envelope
    m = b.size
    L = np.empty(values.size)
    kept, bad = np.zeros(m, np.bool_), np.zeros(m, np.bool_)
    a, tol_a, rhs, clipped = np.empty(m), np.empty(m), np.empty(m), np.empty(m)
    best, idle = m + 1, 0
    sharp = min(tol, settings.LCP_SHARP)
    for _ in range(_ROUNDS):
        counts[PIVOTS] += 1
        count, smallest = env.factor(first, offset, values, member, settings.LCP_DEPENDENT, L, kept)
        for i in range(m):
            rhs[i] = -b[i] if kept[i] else 0.0
        env.solve(first, offset, L, rhs, f)
        env.residual(indptr, indices, data, b, f, sharp, a, tol_a)
        n = _violations(joint, member, kept, f, a, tol_a, bad)
        for i in range(m):
            clipped[i] = f[i] if joint[i] else max(f[i], 0.0)
        whole = count == np.sum(member)
        if env.valid(indptr, indices, data, b, joint, clipped, sharp, a, tol_a):
            f[:] = clipped
            return OK, smallest, whole
        if n == 0:  # the set looks right: the forces are as good as this factor makes them
            f[:] = clipped
            good = env.valid(indptr, indices, data, b, joint, f, tol, a, tol_a)
            return (OK if good else STUCK), smallest, whole
        if redundant_stop and not whole:
            return STUCK, smallest, whole
        if n < best:
            best, idle = n, 0
        else:
            idle += 1
        last = -1
        for i in range(m):
            if bad[i]:
                last = i
        for i in range(m):
            if bad[i] and (idle < _PATIENCE or i == last):
                if member[i] and kept[i]:
                    member[i] = False
                elif not member[i]:
                    member[i] = True
    return STUCK, 0.0, False


def solve_sparse(A: sp.csr_array, b: np.ndarray, joint, guess, tol: float, counts):
    """(f, clamped, status, blame) of one island by the sparse path (see the module docstring).
    A: CSR with sorted indices (runtime.solve.lcp_problem.prepare)."""
    m = b.size
    order = reverse_cuthill_mckee(sp.csr_matrix(A), symmetric_mode=True).astype(np.int64)
    diag = A.diagonal()
    S, envelope, d, bs, js, live, member, dead = _set_up(
        A.indptr, A.indices, A.data, diag, b, joint, guess, order, tol
    )
    if dead.any():
        return np.zeros(m), dead, INFEASIBLE, dead
    fs = np.zeros(m)
    status, smallest, whole = pivot_blocks(S, envelope, bs, js, member, tol, counts, fs, True)
    settled = False  # the forces are the least-norm ones over ``member``
    if status != OK and not whole:  # a redundant set (a packed pile): its least norm may hold
        outcome, least = _least_norm_tries(S, envelope, bs, js, member & live, diag, order, tol)
        if outcome == DONE:
            status, fs, settled = OK, least, True
            counts[MIN_NORM] = DONE
        else:
            status, smallest, whole = pivot_blocks(
                S, envelope, bs, js, member, tol, counts, fs, False
            )
    if status != OK:  # the dense solver, warm-started from the best set
        dense = np.ascontiguousarray(A.toarray())
        f, clamped = np.empty(m), np.empty(m, np.bool_)
        start = np.zeros(m, np.bool_)
        start[order] = member
        status = lcp_dense.solve_dense_counted(dense, b, joint, start, tol, f, clamped, counts)
        return f, clamped, status, clamped if status != OK else None
    held = _held(S, bs, js, fs, tol, live)
    if settled:  # least norm over ``member`` already: again only if it holds other rows
        again = not np.array_equal(held, member & live)
    else:
        again = not (whole and smallest > settings.LCP_REDUNDANT and np.array_equal(held, member))
    if again:
        outcome, trial = _least_norm_tries(S, envelope, bs, js, held, diag, order, tol)
        counts[MIN_NORM] = outcome
        if outcome == DONE:
            fs = trial
            held = _held(S, bs, js, fs, tol, live)
    f, clamped = _tear_down(order, d, fs, held, live, joint, b, tol)
    return f, clamped, OK, None


def _least_norm_tries(S, envelope, b, joint, held, diag, order, tol):
    """(outcome, f) of :func:`_least_norm` over ``held``: rows within settings.LCP_REDUNDANT of
    the span of those before them counting as redundant, and where that fails only the truly
    dependent ones (settings.LCP_DEPENDENT). Also what a starting set with dependent rows is
    tried with before block pivoting goes on: there (a resting pile packed wall to wall, a
    third of its contacts depending on the others) the basic forces -- the dependent rows' left
    at 0 -- go negative and pivoting would drop contacts the pile needs, while the least-norm
    forces over the whole set hold; the dense solver finds them too, at O(m^3) (0.15 s for 571
    contacts)."""
    inv_w = (diag / np.max(diag))[order]
    for threshold in (settings.LCP_REDUNDANT, settings.LCP_DEPENDENT):
        outcome, trial = _least_norm(S, envelope, b, joint, held, inv_w, threshold, tol)
        if outcome != FAILED:
            break
    return outcome, trial


@njit
def _set_up(indptr, indices, data, diag, b, joint, guess, order, tol):
    """The scaled problem in the given order: S (CSR), its envelope, D's diagonal d, and b,
    joint, live (S_ii > 0) and the starting clamped set in that order; also the rows no force
    moves that need one (``dead``, in the original order)."""
    m = b.size
    top, b_max = 0.0, 0.0
    for i in range(m):
        top = max(top, diag[i])
        b_max = max(b_max, abs(b[i]))
    d = np.zeros(m)
    dead = np.zeros(m, np.bool_)
    for i in range(m):
        if diag[i] > settings.LCP_ZERO_ROW * top:
            d[i] = 1.0 / np.sqrt(diag[i])
        else:
            dead[i] = b[i] < -tol * b_max or (joint[i] and b[i] > tol * b_max)
    position = np.empty(m, np.int64)
    position[order] = np.arange(m)
    S = env.scaled(indptr, indices, data, d, position)
    envelope = env.envelope(S[0], S[1], S[2])
    cold = not np.any(guess)
    bs, js = np.empty(m), np.empty(m, np.bool_)
    live, member = np.empty(m, np.bool_), np.empty(m, np.bool_)
    for r in range(m):
        i = order[r]
        bs[r], js[r], live[r] = d[i] * b[i], joint[i], d[i] > 0.0
        member[r] = live[r] and (cold or joint[i] or guess[i] or bs[r] < 0.0)
    return S, envelope, d, bs, js, live, member, dead


@njit
def _held(S, b, joint, f, tol, live):
    """The held rows: joints, contacts with a force, and contacts within ``tol`` of a = 0."""
    m = b.size
    a, tol_a = np.empty(m), np.empty(m)
    env.residual(S[0], S[1], S[2], b, f, tol, a, tol_a)
    held = np.empty(m, np.bool_)
    for i in range(m):
        held[i] = live[i] and (joint[i] or f[i] > 0.0 or abs(a[i]) <= tol_a[i])
    return held


@njit
def _tear_down(order, d, fs, held, live, joint, b, tol):
    """Forces and the clamped set back in the original order and units; rows no force moves
    are clamped when they need no force (b ~ 0, or b >= 0 at a contact: they touch)."""
    m = b.size
    b_max = 0.0
    for i in range(m):
        b_max = max(b_max, abs(b[i]))
    f, clamped = np.zeros(m), np.zeros(m, np.bool_)
    for r in range(m):
        i = order[r]
        f[i] = d[i] * fs[r]
        clamped[i] = held[r] or (not live[r] and (joint[i] or b[i] <= tol * b_max))
    return f, clamped


def _least_norm(S, envelope, b, joint, held, inv_w, dependent, tol):
    """(outcome, f): the least-norm forces over the held rows, rows within ``dependent`` of the
    span of those before them counting as redundant (lcp_minnorm's UNIQUE, DONE or FAILED; f
    only with DONE)."""
    first, offset, values = envelope
    m = b.size
    L, kept = np.empty(values.size), np.zeros(m, np.bool_)
    count, _ = env.factor(first, offset, values, held, dependent, L, kept)
    if count == held.sum():
        return UNIQUE, None
    basis, others = np.flatnonzero(kept), np.flatnonzero(held & ~kept)
    T = np.empty((basis.size, others.size))
    rhs, x = np.zeros(m), np.empty(m)
    for c, r in enumerate(others):
        env.row_of(*S, r, kept, rhs)
        env.solve(first, offset, L, rhs, x)
        T[:, c] = x[basis]
    rhs[:] = np.where(kept, -b, 0.0)
    env.solve(first, offset, L, rhs, x)
    f_basis, f_others = np.empty(basis.size), np.empty(others.size)
    done = least_distance(
        T, x[basis].copy(), inv_w[basis], inv_w[others], joint[basis], joint[others], f_basis,
        f_others,
    )  # fmt: skip
    if not done:
        return FAILED, None
    f = np.zeros(m)
    f[basis], f[others] = f_basis, f_others
    f = np.where(joint, f, np.maximum(f, 0.0))
    f[np.abs(f) <= settings.LCP_NOISE * np.max(np.abs(f))] = 0.0  # rounding, as in lcp_minnorm
    a, tol_a = np.empty(m), np.empty(m)
    for _ in range(3):  # T may be ill-conditioned: refine a_B = 0 with the basis factor
        if env.valid(*S, b, joint, f, tol, a, tol_a):
            return DONE, f
        rhs[:] = np.where(kept, a, 0.0)
        env.solve(first, offset, L, rhs, x)
        f = f - x
        f = np.where(joint, f, np.maximum(f, 0.0))
    return FAILED, None
