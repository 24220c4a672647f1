"""The contact-force solver before issue 11 (runtime/solve/lcp.py at 3a5203e) and the warm start the
engine then used (runtime/solve/warm_start.py: solve_with_guess), verbatim but for this docstring
and imports: for bench/lcp.py's before/after comparison only. Nothing imports it otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.linalg import LinAlgError, cholesky, solve_triangular

__all__ = ["ContactSolverError", "solve", "solve_pgs"]

DEFAULT_TOL = 1e-9  # accelerations: |a| <= DEFAULT_TOL * max|b| counts as zero
_PIVOT_EPS = 1e-12  # Schur complement / A_jj below this: row j depends on the clamped rows
_NOISE_EPS = 1e-12  # Delta a, Delta f entries this small (relative) are rounding noise
_TINY = 1e-300
Array = NDArray[np.float64]
Mask = NDArray[np.bool_]


class ContactSolverError(RuntimeError):
    """No valid force was found; ``rows`` holds the offending contact indices."""

    def __init__(self, message: str, rows: Sequence[int] = ()) -> None:
        super().__init__(message)
        self.rows: tuple[int, ...] = tuple(int(r) for r in rows)


def _prepare(A: ArrayLike, b: ArrayLike, joint: ArrayLike | None) -> tuple[Array, Array, Mask]:
    """Validate shapes and finiteness; symmetrize A (its data is symmetric only to rounding)."""
    A = np.array(A, dtype=float, ndmin=2)
    b = np.array(b, dtype=float).reshape(-1)
    n = b.size
    if n == 0:
        A = A.reshape(0, 0)
    if A.shape != (n, n):
        raise ValueError(f"A has shape {A.shape}, expected ({n}, {n}) to match b")
    if not (np.all(np.isfinite(A)) and np.all(np.isfinite(b))):
        raise ValueError("A and b must be finite")
    scale = max(float(np.max(np.abs(A), initial=0.0)), _TINY)
    if np.max(np.abs(A - A.T), initial=0.0) > 1e-8 * scale or np.any(np.diagonal(A) < 0):
        raise ValueError("A must be symmetric positive semi-definite")
    mask = np.zeros(n, bool) if joint is None else np.asarray(joint, dtype=bool).reshape(-1)
    if mask.shape != (n,):
        raise ValueError(f"joint has {mask.size} entries, expected {n}")
    return 0.5 * (A + A.T), b, mask


def _kind(joint: Mask, i: int) -> str:
    return "joint" if joint[i] else "contact"


class _Factor:
    """Lower Cholesky factor of A[C, C], updated in O(k^2) as rows enter and leave C."""

    def __init__(self, A: Array) -> None:
        self.A = A
        self.L = np.zeros_like(A)
        self.rows: list[int] = []
        self.refactorizations = 0

    def solve(self, rhs: Array) -> Array:
        """Return A_CC^-1 rhs by two triangular solves."""
        L = self.L[: len(self.rows), : len(self.rows)]
        y = solve_triangular(L, rhs, lower=True, check_finite=False)
        return solve_triangular(L, y, lower=True, trans="T", check_finite=False)

    def trial(self, j: int) -> tuple[Array, float]:
        """New bottom row of L if j were added, and its squared pivot (the Schur complement)."""
        k = len(self.rows)
        if k == 0:
            return np.empty(0), float(self.A[j, j])
        row = solve_triangular(self.L[:k, :k], self.A[j, self.rows], lower=True, check_finite=False)
        return row, float(self.A[j, j] - row @ row)

    def add(self, j: int, row: Array, pivot: float) -> None:
        k = len(self.rows)
        self.L[k, :k] = row
        self.L[k, k] = math.sqrt(pivot)
        self.rows.append(j)

    def remove(self, j: int) -> None:
        """Delete row/column j: drop it from L and fold its column into the trailing block."""
        p, k = self.rows.index(j), len(self.rows)
        L = self.L
        trailing = L[p + 1 : k, p + 1 : k].copy()
        _cholesky_update(trailing, L[p + 1 : k, p].copy())
        L[p : k - 1, :p] = L[p + 1 : k, :p]
        L[p : k - 1, p : k - 1] = trailing
        L[k - 1, :k] = 0.0
        del self.rows[p]

    def refactor(self) -> None:
        """Fresh factorization of A_CC, to shed rounding accumulated by updates."""
        k = len(self.rows)
        if k == 0:
            return
        try:
            fresh = cholesky(self.A[np.ix_(self.rows, self.rows)], lower=True, check_finite=False)
        except LinAlgError:
            return  # numerically singular: the updated factor is the better one
        self.L[:k, :k] = fresh
        self.refactorizations += 1


def _cholesky_update(L: Array, x: Array) -> None:
    """In place: L L^T + x x^T = L' L'^T for lower-triangular L (Givens-style, stable)."""
    for i in range(len(x)):
        r = math.hypot(L[i, i], x[i])
        c, s = r / L[i, i], x[i] / L[i, i]
        L[i, i] = r
        L[i + 1 :, i] = (L[i + 1 :, i] + s * x[i + 1 :]) / c
        x[i + 1 :] = c * x[i + 1 :] - s * L[i + 1 :, i]


def solve(
    A: ArrayLike,
    b: ArrayLike,
    joint: ArrayLike | None = None,
    *,
    tol: float | None = None,
    stats: dict[str, int] | None = None,
) -> Array:
    """Return contact forces f solving the (mixed) LCP by Baraff's pivoting method.

    Raises ContactSolverError naming the contacts if no valid f exists or accuracy is lost.
    ``stats``, if given, receives counts of drives, pivots and fresh factorizations.
    """
    A, b, joint = _prepare(A, b, joint)
    tol = DEFAULT_TOL if tol is None else float(tol)
    if b.size == 1 and not joint[0] and stats is None:
        return _solve_single(float(A[0, 0]), float(b[0]), tol)
    solver = _Baraff(A, b, joint, tol)
    f = solver.run()
    if stats is not None:
        stats.update(solver.count, refactorizations=solver.factor.refactorizations)
    return f


def _solve_single(a_00: float, b_0: float, tol: float) -> Array:
    """One contact (the common resting case): f = max(0, -b/A), without the pivoting machinery."""
    if b_0 >= -tol * abs(b_0):
        return np.zeros(1)
    if a_00 <= _PIVOT_EPS * abs(b_0):
        raise ContactSolverError(
            f"contact 0 cannot be driven to zero: infeasible (a = {b_0:.3g}, A = {a_00:.3g})", [0]
        )
    return np.array([-b_0 / a_00])


class _Baraff:
    """State of one solve: f, a, the sets C (``clamped``) and NC, and the factor of A_CC."""

    def __init__(self, A: Array, b: Array, joint: Mask, tol: float) -> None:
        n = b.size
        self.A, self.b, self.joint, self.n = A, b, joint, n
        self.tol_a = tol * float(np.max(np.abs(b), initial=0.0))
        self.diag = np.diagonal(A).copy()
        self.diag_max = max(float(np.max(self.diag, initial=0.0)), _TINY)
        self.f = np.zeros(n)
        self.a = b.copy()
        self.clamped = np.zeros(n, bool)
        self.not_clamped = np.zeros(n, bool)
        self.factor = _Factor(A)
        self.count = {"drives": 0, "pivots": 0}

    def run(self) -> Array:
        """compute-forces: drive violated joints, then violated contacts, one at a time."""
        joint, tol_a = self.joint, self.tol_a
        for j in np.flatnonzero(joint & (np.abs(self.a) <= tol_a)):
            self.try_clamp(int(j))  # satisfied joints are clamped at once: they stay satisfied
        for _ in range(4 * self.n + 4):
            a, free = self.a, ~self.clamped
            bad_joint = joint & free & (np.abs(a) > tol_a)
            if bad_joint.any():
                d = int(np.flatnonzero(bad_joint)[np.argmax(np.abs(a[bad_joint]))])
            else:
                bad = ~joint & free & (a < -tol_a)
                if not bad.any():
                    break
                scaled = a / np.sqrt(np.maximum(self.diag, _TINY))  # most violated first
                d = int(np.argmin(np.where(bad, scaled, np.inf)))
            self.count["drives"] += 1
            self.not_clamped[d] = False
            self.drive_to_zero(d)
            self.a = self.A @ self.f + self.b  # fresh each drive: no drift of a
        else:
            raise ContactSolverError("iteration limit: too many drives", [])
        return _polish(self.A, self.b, self.f, self.factor, joint, self.tol_a, self.diag_max)

    def try_clamp(self, j: int) -> bool:
        """Add j to C unless its Schur complement says it depends on the clamped rows."""
        factor, limit = self.factor, _PIVOT_EPS * self.diag[j]
        row, pivot = factor.trial(j)
        if not pivot > limit:
            factor.refactor()  # the factor may have drifted; judge again with a fresh one
            row, pivot = factor.trial(j)
            if not pivot > limit:
                return False
        factor.add(j, row, pivot)
        self.clamped[j], self.not_clamped[j] = True, False
        return True

    def direction(self, d: int, sigma: float) -> tuple[Array, Array]:
        """fdirection: Delta f (Delta f_d = sigma, A_CC Delta f_C = -sigma A_Cd) and A Delta f."""
        A, C = self.A, self.factor.rows
        df = np.zeros(self.n)
        df[d] = sigma
        if C:
            df[C] = self.factor.solve(-sigma * A[d, C])
            da = A @ df
            if np.max(np.abs(da[C])) > _NOISE_EPS * self.diag_max * np.max(np.abs(df)):
                self.factor.refactor()  # inaccurate direction: the factor drifted
                df[C] = self.factor.solve(-sigma * A[d, C])
                da = A @ df
            da[C] = 0.0  # exact in exact arithmetic; keep rounding out of a_C
        else:
            da = A @ df
        if not (np.all(np.isfinite(df)) and np.all(np.isfinite(da))):
            raise ContactSolverError(f"{_kind(self.joint, d)} {d}: direction not finite", [d])
        return df, da

    def drive_to_zero(self, d: int) -> None:
        """Move f along fdirection, swapping C/NC at each maxstep, until a_d = 0."""
        f, a, clamped = self.f, self.a, self.clamped
        sigma = 1.0 if a[d] < 0 else -1.0
        for _ in range(10 * self.n + 10):
            self.count["pivots"] += 1
            df, da = self.direction(d, sigma)
            noise_f = _NOISE_EPS * np.max(np.abs(df))
            noise_a = self.diag_max * noise_f
            while True:  # maxstep; a refused entrant is treated as dependent (Delta a = 0)
                contacts = clamped & ~self.joint
                s, j = _max_step(f, a, df, da, d, contacts, self.not_clamped, noise_a, noise_f)
                if j < 0:
                    rows = [d] + [i for i in self.factor.rows if abs(df[i]) > noise_f]
                    raise ContactSolverError(
                        f"{_kind(self.joint, d)} {d} cannot be driven to zero: infeasible "
                        f"(a = {a[d]:.3g}, tolerance {self.tol_a:.3g}; forces on rows {rows} "
                        "cannot change it)",
                        rows,
                    )
                leaving = bool(clamped[j])
                if leaving or self.try_clamp(j):
                    break
                da[j] = 0.0
            f += s * df
            a += s * da
            if leaving:  # f_j fell to zero: C -> NC
                f[j] = 0.0
                self.factor.remove(j)
                clamped[j], self.not_clamped[j] = False, True
            else:  # a_j reached zero: NC -> C, or j = d and the drive is done
                a[j] = 0.0
                if j == d:
                    return
        raise ContactSolverError(f"{_kind(self.joint, d)} {d}: iteration limit", [d])


def _max_step(
    f: Array,
    a: Array,
    df: Array,
    da: Array,
    d: int,
    clamped_contacts: Mask,
    not_clamped: Mask,
    noise_a: float,
    noise_f: float,
) -> tuple[float, int]:
    """Baraff's maxstep: the largest step keeping the invariants, and the limiting index."""
    best_s, best_j = math.inf, -1
    if da[d] * df[d] > noise_a:  # a_d moves toward 0 (df[d] = +-1 sets the direction)
        best_s, best_j = max(-a[d] / da[d], 0.0), d
    leaving = np.flatnonzero(clamped_contacts & (df < -noise_f))
    if leaving.size:
        steps = np.maximum(f[leaving], 0.0) / -df[leaving]
        i = int(np.argmin(steps))
        if steps[i] < best_s:
            best_s, best_j = float(steps[i]), int(leaving[i])
    entering = np.flatnonzero(not_clamped & (da < -noise_a))
    if entering.size:
        steps = np.maximum(a[entering], 0.0) / -da[entering]
        i = int(np.argmin(steps))
        if steps[i] < best_s:
            best_s, best_j = float(steps[i]), int(entering[i])
    return best_s, best_j


def _polish(
    A: Array,
    b: Array,
    f: Array,
    factor: _Factor,
    joint: Mask,
    tol_a: float,
    diag_max: float,
) -> Array:
    """Refine f on C (iterative refinement with the factor), then verify every condition."""
    C = factor.rows
    for _ in range(2):
        if not C:
            break
        residual = A[C] @ f + b[C]
        trial = f.copy()
        trial[C] -= factor.solve(residual)
        if not np.all(np.isfinite(trial)):
            break
        if np.max(np.abs(A[C] @ trial + b[C])) >= np.max(np.abs(residual)):
            break
        f = trial
    contacts = ~joint
    if not np.all(np.isfinite(f)):
        rows = np.flatnonzero(~np.isfinite(f)).tolist()
        raise ContactSolverError(f"forces at rows {rows} are not finite", rows)
    f_scale = max(
        float(np.max(np.abs(f), initial=0.0)), float(np.max(np.abs(b), initial=0.0)) / diag_max
    )
    rows = np.flatnonzero(contacts & (f < -1e-9 * f_scale)).tolist()
    if rows:
        raise ContactSolverError(f"accuracy lost: negative force at contacts {rows}", rows)
    f[contacts] = np.maximum(f[contacts], 0.0)
    a = A @ f + b
    bad = (contacts & (a < -tol_a)) | ((joint | (f > 0)) & (np.abs(a) > tol_a))
    if bad.any():
        rows = np.flatnonzero(bad).tolist()
        worst = float(np.max(np.abs(a[bad])))
        raise ContactSolverError(
            f"accuracy lost at rows {rows}: |a| = {worst:.3g} > tolerance {tol_a:.3g}", rows
        )
    return f


def solve_pgs(
    A: ArrayLike,
    b: ArrayLike,
    joint: ArrayLike | None = None,
    *,
    iterations: int = 20_000,
    tol: float = 1e-8,
    stats: dict[str, float] | None = None,
) -> Array:
    """Projected Gauss-Seidel: slow, simple, independent of the pivoting code (for checks).

    Stops when the natural residual min(A_ii f_i, a_i) (a_i at joints) is below tol * max|b|
    everywhere; raises ContactSolverError naming the worst rows after ``iterations`` sweeps.
    """
    A, b, joint = _prepare(A, b, joint)
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


def solve_with_guess(
    a_matrix: np.ndarray, b: np.ndarray, clamped: np.ndarray, tol: float = DEFAULT_TOL
) -> np.ndarray | None:
    """f >= 0 with A f + b = 0 on ``clamped`` (a bool mask, the guessed active set) and >= 0
    elsewhere, to ``tol`` relative to max |b|; None if the guess does not give a solution."""
    scale = tol * float(np.max(np.abs(b), initial=0.0))
    if b.size == 1:  # the common single contact: no LinAlg overhead
        if clamped[0]:
            f = -b / a_matrix[0]
            return f if f[0] >= 0.0 else None
        return np.zeros(1) if b[0] >= -scale else None
    f = np.zeros_like(b)
    if clamped.any():
        every = bool(clamped.all())
        sub = a_matrix if every else a_matrix[np.ix_(clamped, clamped)]
        try:
            f_c = np.linalg.solve(sub, -b if every else -b[clamped])
        except np.linalg.LinAlgError:
            return None
        if not np.all(f_c >= 0.0):
            return None
        f[clamped] = f_c
    a = a_matrix @ f + b
    if np.all(np.abs(a[clamped]) <= scale) and np.all(a[~clamped] >= -scale):
        return f
    return None
