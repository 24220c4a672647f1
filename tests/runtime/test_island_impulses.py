"""The impulse LCP of a time step (runtime.solve.island_impulses) against a least-distance
oracle written here: the velocities after the impulses are the unique solution of

    min 1/2 |v - vf|_M^2   subject to   J v >= -c,

the projection of the free velocities onto the velocities that close no gap by more than it is
open (c = d+ / h). With u = M^1/2 (v - vf) that is min |u| s.t. B u >= -b (B = J M^-1/2,
b = J vf + c): a least-distance problem, solved by Lawson and Hanson's reduction to
non-negative least squares (scipy.optimize.nnls), which shares nothing with the pivoting under
test. The problems are packed piles of discs (tests/lcp_oracle.py): statically indeterminate,
so their rows are dependent, and with open gaps b leaves A's range -- what made the dense
solver end "infeasible" on a solvable problem before the regularisation.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import nnls

from runtime import settings
from runtime.solve.island_impulses import solve_impulses
from tests.lcp_oracle import packed_pile

CAPTURED = Path(__file__).parent / "data" / "impulse_lcp_dependent.npz"


def _least_distance(G: np.ndarray, h: np.ndarray) -> np.ndarray:
    """min |u| subject to G u >= h (Lawson and Hanson, "Solving Least Squares Problems", ch. 23)."""
    n = G.shape[1]
    E = np.vstack([G.T, h[None, :]])
    e = np.zeros(n + 1)
    e[n] = 1.0
    w, _ = nnls(E, e, maxiter=50 * E.shape[1])
    r = E @ w - e
    assert abs(r[n]) > 1e-12, "infeasible"
    return -r[:n] / r[n]


def _rows(J: np.ndarray, n: int):
    """(body1, body2, (m, 6) rows) of a dense J over n moving bodies; the ground is body n."""
    m = J.shape[0]
    body1, body2 = np.full(m, n), np.full(m, n)
    jac = np.zeros((m, 6))
    for k in range(m):
        blocks = [i for i in range(n) if np.any(J[k, 3 * i : 3 * i + 3])]
        body1[k] = blocks[0]
        jac[k, :3] = J[k, 3 * blocks[0] : 3 * blocks[0] + 3]
        if len(blocks) > 1:
            body2[k] = blocks[1]
            jac[k, 3:] = J[k, 3 * blocks[1] : 3 * blocks[1] + 3]
    return body1, body2, jac


def _problem(long_row: int, rows: int, seed: int, open_fraction: float):
    _, _, J, inverse = packed_pile(long_row, rows)
    n = J.shape[1] // 3
    rng = np.random.default_rng(seed)
    vf = rng.normal(scale=0.5, size=3 * n)
    gaps = np.where(rng.random(J.shape[0]) < open_fraction, rng.uniform(0, 1e-3, J.shape[0]), 0.0)
    b = J @ vf + gaps
    inverse_mass = np.vstack([inverse.reshape(n, 3), np.zeros((1, 3))])
    fixed = np.r_[np.zeros(n, bool), True]
    return J, inverse, vf, b, inverse_mass, fixed


@pytest.mark.parametrize(
    "long_row, rows, seed, open_fraction",
    [(4, 3, 1, 0.0), (4, 3, 2, 0.3), (6, 5, 3, 0.3), (12, 9, 4, 0.2)],
)
def test_the_velocities_after_the_impulses_are_the_least_distance_ones(
    long_row, rows, seed, open_fraction
):
    """Every guess (none, all, random) gives the oracle's velocities to 1e-7 of the velocity
    change's size (the regularisation's compliance is ~1e-9 of it); p >= 0 and the LCP's
    conditions hold. (12 x 9 has 293 rows: above settings.DENSE_ISLAND, the sparse paths.)"""
    J, inverse, vf, b, inverse_mass, fixed = _problem(long_row, rows, seed, open_fraction)
    n = J.shape[1] // 3
    body1, body2, jac = _rows(J, n)
    if long_row == 12:
        assert J.shape[0] > settings.DENSE_ISLAND
    half = 1.0 / np.sqrt(inverse)
    u = _least_distance(J / half[None, :], -b)
    expected = vf + u / half
    scale = np.max(np.abs(expected - vf))
    rng = np.random.default_rng(seed)
    for guess in (np.zeros(len(b), bool), np.ones(len(b), bool), rng.random(len(b)) < 0.5):
        p, clamped = solve_impulses(body1, body2, jac, b, guess, inverse_mass, fixed)
        v = vf + inverse * (J.T @ p)
        assert np.max(np.abs(v - expected)) <= 1e-7 * scale
        assert p.min() >= 0.0
        a = J @ v + (b - J @ vf)  # d' after, with the gap term: >= 0, 0 where p > 0
        assert a.min() >= -1e-7 * scale
        assert np.all(np.abs(a[p > 0]) <= 1e-7 * scale)
        assert np.all(clamped[p > 0])


def test_islands_are_solved_apart():
    """Two piles side by side share no body: solved together, each gets the impulses it gets
    alone."""
    J1, inv1, vf1, b1, _, _ = _problem(4, 3, 5, 0.3)
    J2, inv2, vf2, b2, _, _ = _problem(5, 3, 6, 0.3)
    n1, n2 = J1.shape[1] // 3, J2.shape[1] // 3
    J = np.zeros((J1.shape[0] + J2.shape[0], 3 * (n1 + n2)))
    J[: J1.shape[0], : 3 * n1], J[J1.shape[0] :, 3 * n1 :] = J1, J2
    body1, body2, jac = _rows(J, n1 + n2)
    inverse_mass = np.vstack([inv1.reshape(n1, 3), inv2.reshape(n2, 3), np.zeros((1, 3))])
    fixed = np.r_[np.zeros(n1 + n2, bool), True]
    b = np.r_[b1, b2]
    none = np.zeros(len(b), bool)
    p, _ = solve_impulses(body1, body2, jac, b, none, inverse_mass, fixed)
    for J_i, inv_i, b_i, part in (
        (J1, inv1, b1, slice(0, len(b1))),
        (J2, inv2, b2, slice(len(b1), None)),
    ):
        n_i = J_i.shape[1] // 3
        rows_i = _rows(J_i, n_i)
        alone, _ = solve_impulses(*rows_i[:2], rows_i[2], b_i, none[part],
                                  np.vstack([inv_i.reshape(n_i, 3), np.zeros((1, 3))]),
                                  np.r_[np.zeros(n_i, bool), True])  # fmt: skip
        assert np.array_equal(p[part], alone)


def test_the_captured_problem_without_regularisation_infeasible_is_solved():
    """The impulse LCP of step 630 of the landing 50-disc pile (bench.scenes.falling_pile(50,
    seed=7)), captured with the regularisation off, when the solve ended "infeasible" (115
    rows: a packed pile's dependent rows and open gaps). Its velocity change dv = W J^T p meets
    the QP's optimality conditions (J dv + b >= 0, = 0 where p > 0, p >= 0) to the
    regularisation's compliance (2.3e-10 m/s at most here) and rounding, and
    its kinetic-energy norm is no larger than the least-distance oracle's (which, on this
    degenerate problem, NNLS gets only to ~5e-4: the oracle is an upper bound here)."""
    data = np.load(CAPTURED)
    body1, body2, jac, b = data["body1"], data["body2"], data["jacobian"], data["b"]
    inverse_mass, fixed = data["inverse_mass"], data["fixed"]
    n = len(fixed)
    J = np.zeros((len(b), 3 * n))
    rows = np.arange(len(b))[:, None]
    J[rows, 3 * body1[:, None] + np.arange(3)] += jac[:, :3]
    J[rows, 3 * body2[:, None] + np.arange(3)] += jac[:, 3:]
    moving = np.repeat(~fixed, 3)
    inverse, Jm = inverse_mass.reshape(-1)[moving], J[:, moving]
    half = 1.0 / np.sqrt(inverse)
    oracle = _least_distance(Jm / half[None, :], -b) / half
    p, _ = solve_impulses(body1, body2, jac, b, data["guess"], inverse_mass, fixed)
    change = inverse * (Jm.T @ p)
    a = Jm @ change + b
    compliance = settings.IMPULSE_REGULARISATION * np.sum(Jm**2 * inverse, axis=1) * p
    slack = compliance + 1e-12 * np.max(np.abs(b))  # the regularisation's, and rounding
    assert p.min() >= 0.0
    assert np.all(a >= -slack)
    assert np.all(np.abs(a[p > 0]) <= slack[p > 0])
    assert np.sum(change**2 / inverse) <= np.sum(oracle**2 / inverse) * (1 + 1e-9)
