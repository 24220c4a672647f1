"""Baraff's pivoting (runtime.solve.lcp_baraff, the dense solver's main path) solves every
strictly convex contact problem on its own: with A positive definite the LCP has one solution
and the method reaches it (Baraff 1994, "Fast contact force computation for nonpenetrating
rigid bodies"), so the solve must end on the pivoting path, not on a fallback, with
the forces of the brute-force oracle (tests/lcp_oracle.py).

Why: the fallbacks (a fresh start, projected Gauss-Seidel) repair what the pivoting gets wrong,
so a broken pivoting rule -- maxstep letting a free contact's acceleration go negative (the
mutant lcp:max-step-sign of bench/mutants.py) -- still returned exact forces, after about 8
times the pivots, and every solver test passed.
"""

from __future__ import annotations

import numpy as np
from lcp_oracle import brute_force

from runtime import settings
from runtime.solve import lcp_dense
from runtime.solve.lcp_dense import PATH, PIVOTED


def test_pivoting_alone_solves_strictly_convex_problems():
    rng = np.random.default_rng(0)
    for trial in range(300):
        n = int(rng.integers(2, 7))
        M = rng.normal(size=(n, n + 2))
        A, b = np.ascontiguousarray(M @ M.T), rng.normal(size=n) * 3.0
        (exact, _), *others = brute_force(A, b, np.zeros(n, bool))
        assert not others  # positive definite: one solution
        f, clamped, counts = np.empty(n), np.empty(n, bool), np.zeros(8, np.int64)
        none = np.zeros(n, bool)
        status = lcp_dense.solve_dense_counted(
            A, b, none, none, settings.LCP_TOL, f, clamped, counts
        )
        assert status == lcp_dense.OK and counts[PATH] == PIVOTED, (trial, counts)
        np.testing.assert_allclose(f, exact, rtol=1e-9, atol=1e-12 * np.max(np.abs(b)))
