"""Impulses of a time step (runtime.step.time_stepping): the velocity-level LCP of every island.

    p >= 0,  A p + b >= 0,  p . (A p + b) = 0,   A = J W J^T (+ a regularisation), per island

Why a module of its own: the same LCP as the contact forces' (note eq. 3, A from the generated
Jacobian rows), but posed on velocities once a step, with b mixing d' and gaps -- so b is not
in the range of A, and a pile's dependent rows (a disc in a packed row touches its neighbours
and the floor) meet an inconsistent b. The dense solver can then end "infeasible" on a problem
that has solutions (measured: the landing 50-disc pile of seed 7 at step 630, kept in
tests/runtime/data/impulse_lcp_dependent.npz; its 200-disc pile tunnelled). A relative
regularisation settings.IMPULSE_REGULARISATION of A's diagonal makes every island's A positive
definite, so each has one solution; what it adds is a compliance: a held
contact opens or closes by h x regularisation x A_ii x p per step (2e-13 m for a 1 kg disc
carrying ten others at 1 ms), far below the projection's tolerance.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp
from runtime.solve import lcp_envelope as env
from runtime.solve.assembly import (
    SOLVED,
    _diagonal,
    _solve_one,
    dense_lcp,
    island_csr,
    island_matrix,
    island_scratch,
    solve_with_guess,
)
from runtime.solve.islands import body_islands, contact_islands, grouped
from runtime.solve.lcp_primal import active_set
from runtime.solve.lcp_sparse import _held, _set_up, _tear_down


def solve_impulses(
    body1, body2, jacobian, b, guess, inverse_mass, fixed, start=None
) -> tuple[np.ndarray, np.ndarray]:
    """(p, clamped) for m contacts between body1 and body2 (Jacobian rows (m, 6), b (m,)),
    island by island, each warm-started from ``guess`` (the rows clamped at the last solve) and,
    from settings.SPARSE_WARM contacts on, from ``start`` (m,) (impulses >= 0 to start from, the
    last step's; none: 0); clamped: the rows held at A p + b = 0, the next guess.
    ``inverse_mass`` (n, 3) is 0 for fixed bodies. Raises ContactSolverError for an island
    without solution."""
    m = len(b)
    labels = contact_islands(body_islands(len(fixed), body1, body2, fixed), body1, body2, fixed)
    order, offsets = grouped(labels)
    jac = np.ascontiguousarray(jacobian[order])
    b1, b2, bo = body1[order], body2[order], np.ascontiguousarray(b[order])
    go = np.ascontiguousarray(guess[order])
    po = np.zeros(m) if start is None else np.ascontiguousarray(start[order])
    ok = np.zeros(len(offsets) - 1, np.bool_)
    _solve_islands(jac, b1, b2, inverse_mass, fixed, offsets, bo, go, po, ok,
                   settings.IMPULSE_REGULARISATION, settings.DENSE_ISLAND,
                   settings.SPARSE_WARM)  # fmt: skip
    for g in np.flatnonzero(~ok):  # large islands where the primal method ran out, or no solution
        start, stop = offsets[g], offsets[g + 1]
        dense_tried = stop - start <= settings.DENSE_ISLAND  # (and failed) in the call above
        data, indices, indptr, _ = _regularised_csr(
            jac, b1, b2, inverse_mass, fixed, start, stop, settings.IMPULSE_REGULARISATION
        )
        A = sp.csr_array((data, indices, indptr), shape=(stop - start, stop - start))
        b_g, p_g, guess_g = bo[start:stop], po[start:stop], go[start:stop]
        p_g[:] = 0.0  # (it held the start)
        if dense_tried or not dense_lcp(
            A.toarray(), b_g.copy(), np.zeros(stop - start, np.bool_), guess_g, p_g
        ):
            p_g[:], guess_g[:] = lcp.solve_warm(A, b_g, None, guess_g)  # or names the failure
    p, clamped = np.empty(m), np.empty(m, np.bool_)
    p[order], clamped[order] = po, go
    return p, clamped


@njit
def _regularised_csr(jac, body1, body2, inv_mass, fixed, start, stop, eps):
    """(data, indices, indptr, diagonal) of the island's A (runtime.solve.assembly.island_csr)
    with its diagonal scaled by 1 + eps."""
    data, indices, indptr = island_csr(jac, body1, body2, inv_mass, fixed, start, stop)
    diagonal = np.empty(stop - start)
    for r in range(stop - start):
        for q in range(indptr[r], indptr[r + 1]):
            if indices[q] == r:
                data[q] *= 1.0 + eps
                diagonal[r] = data[q]
    return data, indices, indptr, diagonal


@njit
def _solve_islands(
    jac, body1, body2, inv_mass, fixed, offsets, b, guess, p, ok, eps, limit, sparse
):
    """Every island in one compiled call: one row in closed form; from ``sparse`` contacts on,
    the primal active-set method from the guess on the envelope factor (:func:`_warm_envelope`);
    below it the guess by one dense Cholesky factorization; else, up to ``limit`` contacts, the
    dense solver.
    ``guess`` gets the clamped set, ``ok[g]`` whether island g was solved here (not: a miss
    above the limit, or no solution -- the caller then solves it or names the failure)."""
    A = island_scratch(offsets, limit)
    tol = settings.LCP_TOL
    for g in range(offsets.size - 1):
        start, stop = offsets[g], offsets[g + 1]
        K = stop - start
        if K == 1:
            p[start], solved = _solve_one(
                _diagonal(jac, body1, body2, inv_mass, fixed, start), b[start], True, tol
            )
            if not solved:  # pulling: the row is free
                p[start] = 0.0
            guess[start] = solved
            ok[g] = True
            continue
        bi, pi, gi = b[start:stop], p[start:stop], guess[start:stop]
        hit = False
        if K >= sparse:
            hit = _warm_envelope(jac, body1, body2, inv_mass, fixed, start, stop, bi, gi, pi, eps)
            if hit or K > limit:
                ok[g] = hit
                continue
        island_matrix(jac, body1, body2, inv_mass, fixed, start, stop, A)
        for k in range(K):
            A[k, k] *= 1.0 + eps
        if K < sparse:
            hit = solve_with_guess(A, bi, K, gi, tol, pi) == SOLVED
        ok[g] = hit or dense_lcp(
            np.ascontiguousarray(A[:K, :K]), bi.copy(), np.zeros(K, np.bool_), gi, pi
        )


@njit
def _warm_envelope(jac, body1, body2, inv_mass, fixed, start, stop, b, guess, p, eps):
    """Whether the island is solved here (p and guess then written): by the primal active-set
    method (runtime.solve.lcp_primal) from the guessed clamped set, A factored within its
    envelope in reverse Cuthill-McKee order. Why: a pile's A has a handful of entries a row; the
    dense factorization of a 120-row guess (~0.4 ms) and the dense solver (~0.7 ms) were most of
    its time step, an envelope factorization costs ~0.06 ms. Why not block pivoting (exchanging
    every violated row at once, the way this was solved up to session 28): it cycles on a packed
    pile's near-dependent rows (72 of 505 islands of a landing 50-disc pile, 406 of a 200-disc
    pile's 400-540-row islands), and even where it ended the primal method was faster (side by
    side, the falling 50-disc pile: the island solves 0.09 s against 0.25 s). If the method runs
    out, the dense solver, which has the fallbacks, takes an island up to
    settings.DENSE_ISLAND rows; the caller the larger ones."""
    data, indices, indptr, diag = _regularised_csr(
        jac, body1, body2, inv_mass, fixed, start, stop, eps
    )
    K = stop - start
    order = env.reverse_cuthill_mckee(indptr, indices)
    joint = np.zeros(K, np.bool_)
    tol = settings.LCP_TOL
    S, envelope, d, bs, js, live, member, dead = _set_up(
        indptr, indices, data, diag, b, joint, guess, order, tol
    )
    if dead.any():
        return False
    fs = np.empty(K)  # the start, scaled (p holds it on entry)
    for r in range(K):
        fs[r] = p[order[r]] / d[order[r]] if live[r] else 0.0
    if not active_set(S, envelope, bs, live, member, fs):
        return False
    held = _held(S, bs, js, fs, tol, live)
    f, clamped = _tear_down(order, d, fs, held, live, joint, b, tol)
    p[:] = f
    guess[:] = clamped
    return True
