"""The contact-force problem as the user gives it: validation, and the error when it has no answer.

Why apart from the solver: every entry point (runtime.solve.lcp's solve and solve_warm, the PGS
reference) must turn bad input into one clear ValueError, and a failure into one
ContactSolverError that names the rows and the residual, in the user's units -- the compiled
solver itself only returns status codes.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from runtime import settings
from runtime.solve.lcp_envelope import (
    FINE,
    NEGATIVE_DIAGONAL,
    NOT_FINITE,
    NOT_PSD,
    NOT_SYMMETRIC,
    check_csr,
)

Array = NDArray[np.float64]
Mask = NDArray[np.bool_]
_SYMMETRIC = settings.LCP_SYMMETRY


class ContactSolverError(RuntimeError):
    """No valid force was found; ``rows`` holds the offending row indices."""

    def __init__(self, message: str, rows: Sequence[int] = ()) -> None:
        super().__init__(message)
        self.rows: tuple[int, ...] = tuple(int(r) for r in rows)


def prepare(
    A: ArrayLike | sp.spmatrix | sp.sparray, b: ArrayLike, joint: ArrayLike | None
) -> tuple[Array | sp.csr_array, Array, Mask]:
    """(A, b, joint) checked: shapes, finiteness, symmetry, a non-negative diagonal and
    |A_ij| <= sqrt(A_ii A_jj) (necessary for positive semi-definite A). A stays sparse (CSR)
    if it was given sparse; a dense A is returned as a C-contiguous float64 copy."""
    b = np.array(b, dtype=float).reshape(-1)
    n = b.size
    if sp.issparse(A):
        if not (isinstance(A, sp.csr_array) and A.dtype == float and A.has_canonical_format):
            A = sp.csr_array(A, dtype=float, copy=True)  # (the caller's matrix stays as it is)
            A.sum_duplicates()  # and sorts the indices
        if A.shape != (n, n):
            raise ValueError(f"A has shape {A.shape}, expected ({n}, {n}) to match b")
        problem = check_csr(A.indptr, A.indices, A.data, A.diagonal())
        if not np.all(np.isfinite(b)):
            problem = NOT_FINITE
    else:
        A = np.array(A, dtype=float, ndmin=2)
        if n == 0:
            A = A.reshape(0, 0)
        if A.shape != (n, n):
            raise ValueError(f"A has shape {A.shape}, expected ({n}, {n}) to match b")
        problem = _check_dense(A, b)
    if problem != FINE:
        raise ValueError(_PROBLEMS[problem])
    mask = np.zeros(n, bool) if joint is None else np.asarray(joint, dtype=bool).reshape(-1)
    if mask.shape != (n,):
        raise ValueError(f"joint has {mask.size} entries, expected {n}")
    return A, b, mask


_PROBLEMS = {
    NOT_FINITE: "A and b must be finite",
    NEGATIVE_DIAGONAL: "A must be positive semi-definite: a negative diagonal entry",
    NOT_SYMMETRIC: "A must be symmetric (A_ij = A_ji to 1e-8 of sqrt(A_ii A_jj))",
    NOT_PSD: "A must be positive semi-definite (|A_ij| <= sqrt(A_ii A_jj))",
}


def _check_dense(A: Array, b: Array) -> int:
    """check_csr's verdict for a dense A (and a finite b)."""
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(b))):
        return NOT_FINITE
    diag = np.diagonal(A)
    if np.any(diag < 0):
        return NEGATIVE_DIAGONAL
    bound = np.sqrt(np.outer(diag, diag))
    if np.any(np.abs(A - A.T) > _SYMMETRIC * bound):
        return NOT_SYMMETRIC
    if np.any(np.abs(A) > (1 + _SYMMETRIC) * bound):
        return NOT_PSD
    return FINE


def row_names(rows: Sequence[int], joint: Mask, index: Sequence[int] | None = None) -> str:
    """'contact 3', 'joint 0, contact 2', ... (at most 8 named; ``index`` numbers the rows)."""
    number = index if index is not None else range(len(joint))
    names = [f"{'joint' if joint[r] else 'contact'} {number[r]}" for r in rows[:8]]
    return ", ".join(names) + (f" and {len(rows) - 8} more" if len(rows) > 8 else "")


def violations(A, b: Array, joint: Mask, f: Array, tol: float) -> tuple[Array, Array]:
    """(violation, tolerance) of every row at f: -a at contacts with f = 0, |a| at joints and
    at contacts with f > 0, against tol * (sum_j |A_ij f_j| + |b_i|) plus the floor
    settings.LCP_FLOOR * sqrt(A_ii) max_j(|b_j| / sqrt(A_jj), |f_j| sqrt(A_jj))."""
    a = A @ f + b
    size = abs(A) @ np.abs(f) + np.abs(b)
    root = np.sqrt(A.diagonal())
    live = root > 0
    top = max(np.max(np.abs(b[live]) / root[live], initial=0.0), np.max(np.abs(f) * root))
    held = joint | (f > 0)
    return np.where(held, np.abs(a), -a), tol * size + settings.LCP_FLOOR * root * top


def failure(
    infeasible: bool,
    A,
    b: Array,
    joint: Mask,
    f: Array,
    blame: Mask,
    tol: float,
    index: Sequence[int] | None = None,
) -> ContactSolverError:
    """The ContactSolverError of a failed solve: the rows to blame and the worst residual at the
    best point found (rows numbered by ``index``, e.g. an island's rows in the whole problem)."""
    number = np.arange(b.size) if index is None else np.asarray(index)
    excess, limit = violations(A, b, joint, f, tol)
    worst = int(np.argmax(excess - limit)) if b.size else 0
    rows = np.flatnonzero(blame).tolist() or np.flatnonzero(excess > limit).tolist() or [worst]
    where = f"{'joint' if joint[worst] else 'contact'} {number[worst]}"
    residual = (
        f"residual {excess[worst]:.3g} m/s^2 at {where}, tolerance {limit[worst]:.3g}"
        if b.size
        else "no rows"
    )
    if infeasible:
        return ContactSolverError(
            f"{row_names(rows, joint, number)} cannot be held: infeasible, no forces give a >= 0 "
            f"at contacts and a = 0 at joints ({residual}, at the best forces found)",
            number[rows].tolist(),
        )
    return ContactSolverError(
        f"no valid contact forces found for {row_names(rows, joint, number)}: pivoting and its "
        f"fallbacks failed ({residual})",
        number[rows].tolist(),
    )
