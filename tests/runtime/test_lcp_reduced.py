"""The least-norm stage's reduced QP (runtime.solve.lcp_reduced) against exhaustive search.

The reference enumerates every set of at most q constraints held as equalities, solves each
equality-constrained QP with NumPy's lstsq on its KKT system, and keeps the feasible point of
least objective: a strictly convex QP's minimum is one of them, so this shares nothing with the
Goldfarb-Idnani method under test. Also: the dual Newton method of runtime.solve.lcp_minnorm
reaches the same forces, and a row whose g is rounding of 0 does not drive the others to large
opposed forces.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy.optimize import linprog

from runtime.solve.lcp_minnorm import dual_newton, least_distance
from runtime.solve.lcp_reduced import INFEASIBLE, SOLVED, reduced_least_distance, reduced_outcome


def _objective(fB, fR, wB, wR) -> float:
    return float(np.sum(fB**2 / wB) + np.sum(fR**2 / wR))


def _exhaustive(T, g, wB, wR, jB, jR):
    """(fB, fR) of least objective over the feasible KKT points of every active set."""
    k, q = T.shape
    H = T.T @ (T / wB[:, None]) + np.diag(1.0 / wR)
    c = -T.T @ (g / wB)
    normals = [(-T[i], g[i]) for i in range(k) if not jB[i]]  # n.z + d >= 0
    normals += [(np.eye(q)[j], 0.0) for j in range(q) if not jR[j]]
    best, best_value = None, np.inf
    for size in range(min(q, len(normals)) + 1):
        for chosen in itertools.combinations(range(len(normals)), size):
            N = np.array([normals[i][0] for i in chosen]).reshape(size, q)
            d = np.array([normals[i][1] for i in chosen])
            kkt = np.block([[H, -N.T], [N, np.zeros((size, size))]])
            if np.linalg.matrix_rank(kkt) < q + size:
                continue
            z = np.linalg.solve(kkt, np.concatenate([-c, -d]))[:q]
            if all(n @ z + dd >= -1e-9 * (1 + abs(dd)) for n, dd in normals):
                value = 0.5 * z @ H @ z + c @ z
                if value < best_value:
                    best, best_value = z, value
    return g - T @ best, best


def _problem(rng):
    k, q = int(rng.integers(1, 7)), int(rng.integers(1, 4))
    T = rng.normal(size=(k, q)) * (rng.random((k, q)) < 0.7)
    fB0 = rng.random(k) * (rng.random(k) < 0.6)
    fR0 = rng.random(q) * (rng.random(q) < 0.6)
    g = fB0 + T @ fR0  # feasible: (fB0, fR0) is a point of it
    wB, wR = rng.uniform(0.05, 1.0, k), rng.uniform(0.05, 1.0, q)
    jB, jR = rng.random(k) < 0.15, rng.random(q) < 0.15
    return T, g, wB, wR, jB, jR


@pytest.mark.parametrize("seed", range(6))
def test_reduced_qp_matches_exhaustive_search(seed: int) -> None:
    rng = np.random.default_rng(seed)
    for _ in range(60):
        T, g, wB, wR, jB, jR = _problem(rng)
        fB, fR = np.empty(g.size), np.empty(wR.size)
        assert reduced_least_distance(T, g, wB, wR, jB, jR, fB, fR)
        eB, eR = _exhaustive(T, g, wB, wR, jB, jR)
        scale = 1.0 + np.abs(g).max() + np.abs(eR).max()
        assert np.abs(fB - eB).max() <= 1e-9 * scale
        assert np.abs(fR - eR).max() <= 1e-9 * scale
        assert np.all(fB[~jB] >= 0.0) and np.all(fR[~jR] >= 0.0)
        assert np.abs(fB + T @ fR - g).max() <= 1e-12 * scale


@pytest.mark.parametrize("seed", range(3))
def test_reduced_qp_agrees_with_the_dual_newton_method(seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    for _ in range(60):
        T, g, wB, wR, jB, jR = _problem(rng)
        fB, fR, dB, dR = (np.empty(g.size), np.empty(wR.size), np.empty(g.size), np.empty(wR.size))
        assert reduced_least_distance(T, g, wB, wR, jB, jR, fB, fR)
        assert dual_newton(T, g, wB, wR, jB, jR, dB, dR)
        scale = 1.0 + np.abs(g).max() + np.abs(dR).max()
        assert np.abs(fB - dB).max() <= 1e-8 * scale
        assert np.abs(fR - dR).max() <= 1e-8 * scale
        assert _objective(fB, fR, wB, wR) <= _objective(dB, dR, wB, wR) * (1 + 1e-8) + 1e-12


def test_a_row_whose_g_is_rounding_of_zero_is_met() -> None:
    """Row 1 carries nothing: its g is -2e-13 beside forces of ~1 and its T row 1e-14.
    Enforcing f_1 >= 0 there would need f_R >= 20; it is met as it stands (f_1 = 0, the
    equations missed by 2e-13), and the others take the least-norm forces of g_1 = 0."""
    T = np.array([[1.0], [1e-14], [0.5]])
    g = np.array([1.0, -2e-13, 2.0])
    ones = np.ones(3)
    no = np.zeros(3, np.bool_)
    fB, fR = np.empty(3), np.empty(1)
    assert reduced_least_distance(T, g, ones, ones[:1], no, no[:1], fB, fR)
    eB, eR = _exhaustive(T, np.array([1.0, 0.0, 2.0]), ones, ones[:1], no, no[:1])
    assert fB[1] == 0.0
    assert np.allclose(fR, eR, rtol=0, atol=1e-9) and eR[0] < 2.0
    assert np.allclose(fB[[0, 2]], eB[[0, 2]], rtol=0, atol=1e-9)


def test_weightless_row_is_left_to_the_dual_newton_method() -> None:
    T, g = np.array([[1.0]]), np.array([1.0])
    no = np.zeros(1, np.bool_)
    assert not reduced_least_distance(
        T, g, np.ones(1), np.zeros(1), no, no, np.empty(1), np.empty(1)
    )


def _feasible(T, g, jB, jR) -> bool:
    """Whether some forces >= 0 (contacts) meet f_B + T f_R = g: scipy's LP (HiGHS), a method
    the code under test does not use."""
    k, q = T.shape
    bounds = [(None, None) if j else (0, None) for j in np.concatenate([jB, jR])]
    lp = linprog(np.zeros(k + q), A_eq=np.hstack([np.eye(k), T]), b_eq=g, bounds=bounds)
    return lp.status == 0


@pytest.mark.parametrize("seed", range(4))
def test_infeasibility_is_reported_only_where_the_lp_finds_no_forces(seed: int) -> None:
    """INFEASIBLE lets the least-norm stage skip the dual Newton method (whose dual is then
    unbounded: 100 Newton steps of a k x k Cholesky, 4-12 ms on a landing pile's 90-row
    islands, to no avail). So it must never be said of a problem that has forces >= 0: random
    problems with g pushed below a feasible one's by up to 1 on random rows, against the LP."""
    rng = np.random.default_rng(300 + seed)
    said = {True: 0, False: 0, INFEASIBLE: 0}
    for _ in range(80):
        T, g, wB, wR, jB, jR = _problem(rng)
        g = g - rng.random(g.size) * (rng.random(g.size) < 0.5)
        fB, fR = np.empty(g.size), np.empty(wR.size)
        outcome = reduced_outcome(T, g, wB, wR, jB, jR, fB, fR)
        feasible = _feasible(T, g, jB, jR)
        assert outcome != INFEASIBLE or not feasible
        assert outcome == SOLVED or not feasible  # (a feasible problem is always solved)
        if not feasible:
            assert not least_distance(T, g, wB, wR, jB, jR, np.empty(g.size), np.empty(wR.size))
        said[feasible] += 1
        said[INFEASIBLE] += outcome == INFEASIBLE
    assert said[True] > 10 and said[False] > 10  # both kinds were drawn
    assert said[INFEASIBLE] >= said[False] // 2  # and most infeasible ones were told as such


def test_a_row_that_needs_a_negative_force_is_infeasible() -> None:
    """f_1 + f_R = -1 with both >= 0: no forces (a g at rounding of the row's other terms is
    met instead: test_a_row_whose_g_is_rounding_of_zero_is_met)."""
    T, no = np.array([[1.0]]), np.zeros(1, np.bool_)
    out = np.empty(1), np.empty(1)
    assert reduced_outcome(T, np.array([-1.0]), np.ones(1), np.ones(1), no, no, *out) == INFEASIBLE
    assert reduced_outcome(T, np.array([1.0]), np.ones(1), np.ones(1), no, no, *out) == SOLVED
