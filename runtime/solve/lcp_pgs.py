"""Projected Gauss-Seidel: a slow, simple contact-force solver, independent of the pivoting code.

Why it is kept: it shares nothing with runtime.solve.lcp's solver (no factorization, no clamped
set), so tests and benchmarks use it as a second opinion on the accelerations a = A f + b (the
same for every solution of a positive semi-definite LCP), and bench/lcp.py times it as the
iterative method engines often use instead (10 and 100 sweeps).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from runtime.solve.lcp_problem import ContactSolverError, prepare

_TINY = 1e-300


def solve_pgs(
    A: ArrayLike,
    b: ArrayLike,
    joint: ArrayLike | None = None,
    *,
    iterations: int = 20_000,
    tol: float = 1e-8,
    stats: dict[str, float] | None = None,
) -> NDArray[np.float64]:
    """Projected Gauss-Seidel: slow, simple, independent of the pivoting code (for checks).

    Stops when the natural residual min(A_ii f_i, a_i) (a_i at joints) is below tol * max|b|
    everywhere; raises ContactSolverError naming the worst rows after ``iterations`` sweeps.
    """
    A, b, joint = prepare(A, b, joint)
    n = b.size
    diag = np.diagonal(A).copy()
    active = diag > 1e-14 * max(float(np.max(diag, initial=0.0)), _TINY)
    tol_a = tol * float(np.max(np.abs(b), initial=0.0))
    f = np.zeros(n)
    a = b.copy()
    residual = np.zeros(n)
    for sweep in range(1, iterations + 1):
        for i in np.flatnonzero(active):
            fi = f[i] - a[i] / diag[i]
            if not joint[i] and fi < 0.0:
                fi = 0.0
            if fi != f[i]:
                a += (fi - f[i]) * A[i]  # A is symmetric: row i is column i
                f[i] = fi
        a = A @ f + b
        residual = np.where(joint, a, np.minimum(diag * f, a))
        if not np.all(np.isfinite(residual)):
            raise ContactSolverError("projected Gauss-Seidel diverged", [])
        if np.max(np.abs(residual), initial=0.0) <= tol_a:
            if stats is not None:
                stats.update(iterations=sweep, residual=float(np.max(np.abs(residual))))
            return f
    worst = np.argsort(-np.abs(residual))[:5]
    rows = worst[np.abs(residual[worst]) > tol_a].tolist()
    raise ContactSolverError(
        f"projected Gauss-Seidel: iteration limit ({iterations} sweeps), worst rows {rows}, "
        f"residual {np.max(np.abs(residual)):.3g}",
        rows,
    )
