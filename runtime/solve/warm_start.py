"""Contact forces warm-started from the previous solve's clamped set.

Why this module exists: the engine solves the contact LCP at every integrator stage (four times
per RK4 step), and from one stage to the next the set of contacts that carry a force almost never
changes. The pivoting solver (runtime.solve.lcp) rebuilds that set from scratch each time, one pivot per
contact, which makes it the dominant cost of resting piles and stacks. Here the last clamped set C
is tried first: solve A_CC f_C = -b_C directly and accept f if it satisfies the LCP conditions
(f >= 0; a = A f + b = 0 on C and >= 0 elsewhere, to the solver's relative tolerance) -- then it
*is* a solution, so the accelerations are those the pivoting solver would give. Otherwise the
pivoting solver runs and its clamped set is remembered.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from runtime.solve import lcp


def solve_with_guess(
    a_matrix: np.ndarray, b: np.ndarray, clamped: np.ndarray, tol: float = lcp.DEFAULT_TOL
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


class WarmStartSolver:
    """A drop-in ``solver(A, b) -> f`` for runtime.solve.dynamics.ContactDynamics.

    Set ``keys`` (one hashable identity per row, e.g. runtime.step.collisions.contact_key) before a
    solve and the guess follows the contacts when the set changes (after an impact); without
    keys the last clamped mask is reused if the size matches.
    """

    def __init__(self, solve: Callable[..., np.ndarray] = lcp.solve, tol: float = lcp.DEFAULT_TOL):
        self.solve = solve
        self.tol = tol
        self.keys: list | None = None
        self.memory: dict = {}  # key -> clamped at the last solve that had it
        self.clamped: np.ndarray | None = None
        self.hits = 0
        self.misses = 0

    def _guess(self, m: int) -> np.ndarray | None:
        if self.keys is not None and len(self.keys) == m:
            return np.array([self.memory.get(k, False) for k in self.keys], dtype=bool)
        if self.clamped is not None and self.clamped.shape == (m,):
            return self.clamped
        return None

    def __call__(self, a_matrix: np.ndarray, b: np.ndarray) -> np.ndarray:
        guess = self._guess(len(b))
        f = None if guess is None else solve_with_guess(a_matrix, b, guess, self.tol)
        if f is not None:
            self.hits += 1
            return f
        self.misses += 1
        f = self.solve(a_matrix, b)
        self.clamped = f > 0.0
        if self.keys is not None and len(self.keys) == len(b):
            self.memory.update(zip(self.keys, self.clamped.tolist(), strict=True))
        return f
