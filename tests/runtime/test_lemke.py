"""Lemke's method (runtime.solve.lemke) against independent references.

* symmetric positive definite M = J W J^T (the frictionless contact problem): the same z as the
  engine's frictionless solver (runtime.solve.lcp, Baraff's pivoting, written apart);
* non-symmetric P-matrices (positive definite plus skew, as friction's folded columns make):
  the unique solution, found by trying every complementary basis (2^n linear solves);
* the 2-D friction LCP of a box on a floor, whose two corners' tangential rows are equal (a
  degenerate problem, where pivoting without an anti-cycling rule can loop): solved, and its
  forces hold the box (a = 0) within the cone;
* no solution (M = -1, q = -1): a ray, not a wrong z.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

from runtime import settings
from runtime.solve import lcp, lemke


def _brute_force(M: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The solution of the LCP (M, q) over all complementary bases (small n only)."""
    n = q.size
    for basis in itertools.product((False, True), repeat=n):
        z = np.zeros(n)
        on = np.array(basis)
        if on.any():
            try:
                z[on] = np.linalg.solve(M[np.ix_(on, on)], -q[on])
            except np.linalg.LinAlgError:  # a singular basis: not this one
                continue
        w = M @ z + q
        scale = np.abs(M).sum() * (1 + np.abs(z).max()) + np.abs(q).max()
        if np.all(z >= -1e-12 * scale) and np.all(w >= -1e-12 * scale):
            return z
    raise AssertionError("no solution")


@pytest.mark.parametrize("seed", range(20))
def test_symmetric_positive_definite_problems_match_the_frictionless_solver(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 9))
    J = rng.normal(size=(n, n + 3))
    M = J @ np.diag(rng.uniform(0.1, 2.0, n + 3)) @ J.T
    q = rng.normal(size=n)
    z, status = lemke.solve(M, q)
    assert status == lemke.SOLVED
    reference = lcp.solve(M, q)
    assert np.allclose(z, reference, rtol=1e-9, atol=1e-12 * np.abs(reference).max(initial=1))


@pytest.mark.parametrize("seed", range(20))
def test_non_symmetric_p_matrix_problems_give_the_unique_solution(seed):
    rng = np.random.default_rng(100 + seed)
    n = int(rng.integers(1, 7))
    B = rng.normal(size=(n, n))
    S = rng.normal(size=(n, n))
    M = B @ B.T + 0.1 * np.eye(n) + (S - S.T)  # positive definite (not symmetric): a P-matrix
    q = rng.normal(size=n)
    z, status = lemke.solve(M, q)
    assert status == lemke.SOLVED
    assert np.allclose(z, _brute_force(M, q), rtol=1e-9, atol=1e-12)


def test_a_box_on_a_floor_with_equal_tangential_rows_is_solved_and_held():
    """Box of mass 2, inertia 0.1, corners at (+-0.2, -0.1) from its centre on a floor, gravity
    and a sideways pull of 3 N (mu 0.5: the hold needs 3 N of 0.5 x 19.62 N available)."""
    m, inertia, mu = 2.0, 0.1, 0.5
    W = np.diag([1 / m, 1 / m, 1 / inertia])
    levers = [np.array([-0.2, -0.1]), np.array([0.2, -0.1])]
    n, t = np.array([0.0, 1.0]), np.array([-1.0, 0.0])
    Jn = np.array([[*n, r[0] * n[1] - r[1] * n[0]] for r in levers])
    Jt = np.array([[*t, r[0] * t[1] - r[1] * t[0]] for r in levers])
    assert np.array_equal(Jt[0], Jt[1])
    a0 = np.array([3.0 / m, -9.81, 0.0])
    A = lambda P, Q: P @ W @ Q.T  # noqa: E731
    k = 2
    M = np.zeros((4 * k, 4 * k))
    blocks = [[A(Jn, Jn), A(Jn, Jt), -A(Jn, Jt)], [A(Jt, Jn), A(Jt, Jt), -A(Jt, Jt)]]
    M[:k, : 3 * k] = np.hstack(blocks[0])
    M[k : 2 * k, : 3 * k] = np.hstack(blocks[1])
    M[2 * k : 3 * k, : 3 * k] = -np.hstack(blocks[1])
    M[k : 3 * k, 3 * k :] = np.vstack([np.eye(k), np.eye(k)])
    M[3 * k :, :k] = mu * np.eye(k)
    M[3 * k :, k : 3 * k] = -np.hstack([np.eye(k), np.eye(k)])
    q = np.concatenate([Jn @ a0, Jt @ a0, -(Jt @ a0), np.zeros(k)])
    z, status = lemke.solve(M, q)
    assert status == lemke.SOLVED
    fn, ft, slack = z[:k], z[k : 2 * k] - z[2 * k : 3 * k], z[3 * k :]
    acc = a0 + W @ (Jn.T @ fn + Jt.T @ ft)
    assert np.allclose(acc, 0.0, atol=1e-12)
    assert np.all(np.abs(ft) <= mu * fn + 1e-12) and np.all(slack <= 1e-12)
    assert np.isclose(fn.sum(), m * 9.81, rtol=1e-12) and np.isclose(ft.sum(), 3.0, rtol=1e-12)


def test_a_problem_without_solution_ends_on_a_ray():
    z, status = lemke.solve(np.array([[-1.0]]), np.array([-1.0]))
    assert status == lemke.RAY


def test_a_degenerate_impact_problem_ends_on_a_ray_without_and_is_solved_with_perturbation():
    """The frictional impulse LCP of a disc pile (tests/runtime/data/lemke_degenerate_impact.npz:
    two contacts sliding at 0.14 and 0.2 m/s with approach rates of -5e-12 m/s beside exact
    zeros) sends plain Lemke onto a ray although it has a solution (found by trying bases);
    the perturbed retry solves it, exactly for a q moved by the perturbation (LEMKE_PERTURB x
    max(1, |q|), up to 2x in its pattern and 3 retries)."""
    data = np.load(Path(__file__).parent / "data" / "lemke_degenerate_impact.npz")
    M, q = data["M"], data["q"]
    assert lemke.lemke(M.copy(), q.copy(), np.zeros(q.size), np.zeros(q.size, bool)) == lemke.RAY
    _brute_force(M, q)  # a solution exists
    z, status = lemke.solve(M, q)
    w = M @ z + q
    moved = 6 * settings.LEMKE_PERTURB * max(1.0, np.abs(q).max())
    assert status == lemke.SOLVED
    assert z.min() >= 0 and w.min() >= -moved and abs(z @ w) <= moved * z.sum()
