"""The primal active-set method of a large island's impulse LCP (runtime.solve.lcp_primal)
against answers computed apart.

A definite LCP is the QP min q(f) = 1/2 f.A f + b.f over f >= 0; with A = R^T R (Cholesky) that
is the bounded least-squares problem min |R f + R^-T b| over f >= 0, solved here by scipy's BVLS
(scipy.optimize.lsq_linear), which shares nothing with the method. The problems: packed piles
of discs (tests/lcp_oracle.py: statically indeterminate, so nearly dependent once regularised)
and an island of the landing 200-disc pile on which block pivoting cycles.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp
from lcp_oracle import packed_pile, row_violation
from scipy.linalg import solve_triangular
from scipy.optimize import lsq_linear

from runtime import settings
from runtime.solve import lcp_envelope as env
from runtime.solve.island_impulses import _pivot
from runtime.solve.lcp_primal import active_set
from runtime.solve.lcp_sparse import _set_up

CYCLING = Path(__file__).parent / "data" / "impulse_lcp_cycling.npz"


def _scaled(A: sp.csr_array, b: np.ndarray, guess: np.ndarray):
    """The island as runtime.solve.island_impulses poses it: S = D A D in reverse Cuthill-McKee
    order, its envelope, D, the scaled b, live rows and the starting set, and the order."""
    A.sort_indices()
    indptr, indices = A.indptr.astype(np.int64), A.indices.astype(np.int64)
    order = env.reverse_cuthill_mckee(indptr, indices)
    joint = np.zeros(len(b), bool)
    S, envelope, d, bs, js, live, member, _ = _set_up(
        indptr, indices, A.data, A.diagonal(), b, joint, guess, order, settings.LCP_TOL
    )
    return S, envelope, d, bs, js, live, member, order


def _solve(A: sp.csr_array, b: np.ndarray, guess: np.ndarray) -> np.ndarray:
    """f in the original order and units, asserting that the method ends on a solution."""
    S, envelope, d, bs, _, live, member, order = _scaled(A, b, guess)
    fs = np.empty(len(b))
    assert active_set(S, envelope, bs, live, member, fs)
    f = np.empty(len(b))
    f[order] = d[order] * fs
    return f


def _oracle(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """argmin 1/2 f.A f + b.f over f >= 0 by BVLS on the Cholesky factor."""
    R = np.linalg.cholesky(A).T
    target = -solve_triangular(R.T, b, lower=True)
    return lsq_linear(R, target, bounds=(0.0, np.inf), method="bvls", tol=1e-15).x


def _check(A: np.ndarray, b: np.ndarray, f: np.ndarray) -> None:
    """The LCP's conditions row by row within the solver's tolerance, and the velocity change
    A f and the minimum q against the oracle's."""
    violation, scale, unit = row_violation(A, b, np.zeros(len(b), bool), f)
    assert f.min() >= 0.0
    assert np.all(violation <= settings.LCP_TOL * scale + 1e-11 * unit)
    expected = _oracle(A, b)
    size = np.max(np.abs(b))
    assert np.max(np.abs(A @ f - A @ expected)) <= 1e-7 * size
    q, q_expected = 0.5 * f @ A @ f + b @ f, 0.5 * expected @ A @ expected + b @ expected
    assert q <= q_expected + 1e-9 * abs(q_expected)  # (q sums terms that cancel)


def test_it_solves_the_island_on_which_block_pivoting_cycles():
    """274 rows of the landing 200-disc pile (bench.scenes.falling_pile(200), t ~ 0.7 s, its A
    regularised as the engine does): block pivoting from the engine's guess exchanges rows for
    settings.SPARSE_ROUNDS factorizations without ending; the primal method ends on a solution,
    the oracle's to 1e-7 of |b| in A f."""
    data = np.load(CYCLING)
    m = len(data["b"])
    A = sp.csr_array((data["data"], data["indices"], data["indptr"]), shape=(m, m))
    b, guess = data["b"], data["guess"]
    S, envelope, _, bs, js, live, member, _ = _scaled(A.copy(), b, guess)
    assert not _pivot(S, envelope, bs, js, live, member, np.empty(m))  # the premise
    _check(A.toarray(), b, _solve(A.copy(), b, guess))


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_it_solves_regularised_packed_piles_from_any_start(seed):
    """A packed pile of 12 x 9 discs (293 rows, statically indeterminate), regularised as the
    engine does (settings.IMPULSE_REGULARISATION of A's diagonal), free velocities and open gaps
    at random; starting from no row, every row and a random half: a solution every time."""
    _, _, J, inverse = packed_pile(12, 9)
    rng = np.random.default_rng(seed)
    A = (J * inverse) @ J.T
    A += settings.IMPULSE_REGULARISATION * np.diag(np.diag(A))
    gaps = np.where(rng.random(len(A)) < 0.2, rng.uniform(0, 1e-3, len(A)), 0.0)
    b = J @ rng.normal(scale=0.5, size=J.shape[1]) + gaps
    for guess in (np.zeros(len(b), bool), np.ones(len(b), bool), rng.random(len(b)) < 0.5):
        _check(A, b, _solve(sp.csr_array(A), b, guess))
