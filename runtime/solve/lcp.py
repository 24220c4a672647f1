"""Contact forces: the frictionless contact LCP, solved whenever it has a solution.

Problem: A (m, m) symmetric positive semi-definite (1/kg; singular when contacts are
redundant), b (m,) (m/s^2); find f (N) with a = A f + b and, for contact rows, a >= 0, f >= 0,
f.a = 0; for rows flagged ``joint`` (bilateral), a = 0 with f free in sign.

Entry points (signatures are the contract with the engine):

    f = solve(A, b, joint=None, *, tol=None, stats=None)
        A: array-like or scipy.sparse (m, m); b: (m,); joint: (m,) bool or None; tol: relative
        row tolerance (None: settings.LCP_TOL); stats: a dict that receives counts (islands,
        paths taken, drives, pivots, least_norm). Splits a problem of more than
        settings.LCP_DENSE_MAX rows into contact islands (connected components of A's
        pattern) and solves each cold; a smaller one is solved whole (the dense solver costs
        less than finding them). Returns f (m,) float64; raises ValueError for bad input and
        ContactSolverError(message, rows) when no valid force exists (naming the rows and
        the residual).
    f, clamped = solve_warm(A, b, joint=None, guess=None, tol=None)
        One island, warm-started: ``guess`` is the ``clamped`` of the previous solve of the same
        rows (None or all False: cold). The compiled dense solver up to settings.LCP_DENSE_MAX
        rows (and for a larger A fuller than settings.LCP_SPARSE_DENSITY), the sparse path
        otherwise. Returns f and clamped (m,) bool, the held rows (a = 0 within tol: joints
        and touching contacts); raises as ``solve``.
    status = solve_dense(A, b, joint, guess, tol, f_out, clamped_out)
        The compiled core (runtime.solve.lcp_dense; callable from numba code): A (m, m) float64
        C-contiguous, b (m,) float64, joint and guess (m,) bool, tol float (<= 0: the default),
        f_out (m,) float64 and clamped_out (m,) bool written; returns OK = 0, INFEASIBLE = 1,
        STUCK = 2, NOT_FINITE = 3, BAD_INPUT = 4; never raises.
    solve_pgs(A, b, joint=None, *, iterations, tol, stats)
        Projected Gauss-Seidel, the independent slow reference (runtime.solve.lcp_pgs).

What is returned (docs/numerics.md, "The contact solver"):
* validity: every row within tol * (sum_j |A_ij f_j| + |b_i|) of its conditions -- a
  componentwise backward error, the same in any units (a 2e11 kg disc has A = 5e-12);
* redundant contacts: of all solutions (they share a, hence the accelerations) the one of least
  Euclidean norm, sum f_i^2 (runtime.solve.lcp_minnorm);
* failure only when Baraff's pivoting finds a certificate of infeasibility (forces on the rows
  named that cannot change their a) and the fallbacks agree, or when every fallback failed.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike
from scipy.sparse.csgraph import connected_components

from runtime import settings
from runtime.solve import lcp_dense, lcp_sparse
from runtime.solve.lcp_dense import N_COUNTS, OK, solve_dense
from runtime.solve.lcp_pgs import solve_pgs
from runtime.solve.lcp_problem import Array, ContactSolverError, Mask, failure, prepare

__all__ = ["ContactSolverError", "DEFAULT_TOL", "solve", "solve_dense", "solve_pgs", "solve_warm"]

DEFAULT_TOL = settings.LCP_TOL  # the name runtime.step.resting and solve.warm_start use
PATHS = ("none", "warm hit", "pivoting", "pivoting afresh", "polished", "single row", "sparse")


def solve(
    A: ArrayLike | sp.spmatrix | sp.sparray,
    b: ArrayLike,
    joint: ArrayLike | None = None,
    *,
    tol: float | None = None,
    stats: dict | None = None,
) -> Array:
    """Contact forces f of every island of the problem (see the module docstring)."""
    A, b, joint = prepare(A, b, joint)
    tol = _tolerance(tol)
    m = b.size
    f = np.zeros(m)
    counts = np.zeros(N_COUNTS, np.int64)
    paths: dict[str, int] = {}
    islands = _islands(A) if m > settings.LCP_DENSE_MAX else [np.arange(m)]
    for rows in islands:
        if len(islands) == 1:
            sub = A
        else:
            sub = A[np.ix_(rows, rows)] if not sp.issparse(A) else A[rows][:, rows]
        island_counts = np.zeros(N_COUNTS, np.int64)
        f_rows, _, status, blame = _solve_island(
            sub, b[rows], joint[rows], None, tol, island_counts
        )
        counts += island_counts
        name = PATHS[int(island_counts[lcp_dense.PATH])]
        paths[name] = paths.get(name, 0) + 1
        if status != OK:
            infeasible = status == lcp_dense.INFEASIBLE
            raise failure(infeasible, sub, b[rows], joint[rows], f_rows, blame, tol, rows)
        f[rows] = f_rows
    if stats is not None:
        stats.update(
            islands=len(islands),
            paths=paths,
            drives=int(counts[0]),
            pivots=int(counts[1]),
            refactorizations=int(counts[2]),
            least_norm=int(counts[lcp_dense.MIN_NORM]),
        )
    return f


def solve_warm(
    A: ArrayLike | sp.spmatrix | sp.sparray,
    b: ArrayLike,
    joint: ArrayLike | None = None,
    guess: ArrayLike | None = None,
    tol: float | None = None,
) -> tuple[Array, Mask]:
    """(f, clamped) of one island, starting from the clamped set ``guess`` (see the module
    docstring). Cheap when the guess is right: one factorization of the guessed block."""
    b = np.ascontiguousarray(b, dtype=np.float64).reshape(-1)
    m = b.size
    joint = np.zeros(m, np.bool_) if joint is None else np.ascontiguousarray(joint, np.bool_)
    guess = np.zeros(m, np.bool_) if guess is None else np.ascontiguousarray(guess, np.bool_)
    tol = _tolerance(tol)
    if not sp.issparse(A):
        A = np.ascontiguousarray(A, dtype=np.float64)
        if A.ndim == 2 and m <= settings.LCP_DENSE_MAX:
            f, clamped = np.empty(m), np.empty(m, np.bool_)
            if solve_dense(A, b, joint.reshape(-1), guess.reshape(-1), tol, f, clamped) == OK:
                return f, clamped
    A, b, joint = prepare(A, b, joint)  # a failure, or a large problem: check it, then solve
    if guess.shape != (m,):
        raise ValueError(f"guess has {guess.size} entries, expected {m}")
    f, clamped, status, blame = _solve_island(A, b, joint, guess, tol, np.zeros(N_COUNTS, int))
    if status != OK:
        raise failure(status == lcp_dense.INFEASIBLE, A, b, joint, f, blame, tol)
    return f, clamped


def _tolerance(tol: float | None) -> float:
    if tol is None:
        return settings.LCP_TOL
    if not (np.isfinite(tol) and tol > 0):
        raise ValueError(f"tol must be a positive number, got {tol!r}")
    return float(tol)


def _islands(A) -> list[np.ndarray]:
    """Row indices of each contact island: the connected components of A's pattern."""
    pattern = sp.csr_array(A) if not sp.issparse(A) else A
    count, labels = connected_components(pattern, directed=False)
    if count == 1:
        return [np.arange(A.shape[0])]
    order = np.argsort(labels, kind="stable")
    return np.split(order, np.flatnonzero(np.diff(labels[order])) + 1)


def _solve_island(A, b: Array, joint: Mask, guess: Mask | None, tol: float, counts: np.ndarray):
    """(f, clamped, status, blame) of one island, by the dense or the sparse path."""
    m = b.size
    guess = np.zeros(m, np.bool_) if guess is None else guess
    if m > settings.LCP_DENSE_MAX:
        nonzeros = A.nnz if sp.issparse(A) else np.count_nonzero(A)
        if nonzeros < settings.LCP_SPARSE_DENSITY * m * m:
            counts[lcp_dense.PATH] = PATHS.index("sparse")
            A = A if isinstance(A, sp.csr_array) else sp.csr_array(A)
            return lcp_sparse.solve_sparse(A, b, joint, guess, tol, counts)
    dense = np.ascontiguousarray(A.toarray() if sp.issparse(A) else A, dtype=np.float64)
    f, clamped = np.empty(m), np.empty(m, np.bool_)
    status = lcp_dense.solve_dense_counted(dense, b, joint, guess, tol, f, clamped, counts)
    if status == lcp_dense.BAD_INPUT:  # prepare() passed: only a badly scaled row can do this
        raise ValueError("A must be symmetric positive semi-definite")
    return f, clamped, status, clamped if status != OK else None
