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
from runtime.solve.lcp_primal import _projected_search, active_set
from runtime.solve.lcp_sparse import _set_up

CYCLING = Path(__file__).parent / "data" / "impulse_lcp_cycling.npz"
STALLED = Path(__file__).parent / "data" / "impulse_lcp_stalled.npz"


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


def _solve(
    A: sp.csr_array, b: np.ndarray, guess: np.ndarray, start: np.ndarray | None = None
) -> np.ndarray:
    """f in the original order and units from the guessed set and the start (forces >= 0, in
    the original order and units; none: 0), asserting that the method ends on a solution."""
    S, envelope, d, bs, _, live, member, order = _scaled(A, b, guess)
    fs = np.zeros(len(b)) if start is None else np.where(live, start[order] / d[order], 0.0)
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
    regularised as the engine does), on which block pivoting from the engine's guess (the
    method used up to session 28) exchanged rows for 25 factorizations without ending: the
    primal method ends on a solution, the oracle's to 1e-7 of |b| in A f."""
    data = np.load(CYCLING)
    m = len(data["b"])
    A = sp.csr_array((data["data"], data["indices"], data["indptr"]), shape=(m, m))
    b, guess = data["b"], data["guess"]
    _check(A.toarray(), b, _solve(A.copy(), b, guess))


def test_it_solves_the_island_where_it_once_stopped_descending():
    """501 rows of the falling 200-disc pile (step 710, its A regularised as the engine does),
    from the engine's start (the last step's impulses), on which the method with the factor
    redone every round stopped descending after five rounds (rounding on near-dependent rows)
    and gave the island up to the dense solver: it ends on the oracle's solution."""
    data = np.load(STALLED)
    m = len(data["b"])
    A = sp.csr_array((data["data"], data["indices"], data["indptr"]), shape=(m, m))
    b, guess, start = data["b"], data["guess"], data["start"]
    _check(A.toarray(), b, _solve(A.copy(), b, guess, start))


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_it_solves_regularised_packed_piles_from_any_start(seed):
    """A packed pile of 12 x 9 discs (293 rows, statically indeterminate), regularised as the
    engine does (settings.IMPULSE_REGULARISATION of A's diagonal), free velocities and open gaps
    at random; starting from no row, every row and a random half, each from f = 0 and from
    random forces (the engine starts from the last step's impulses): a solution every time."""
    _, _, J, inverse = packed_pile(12, 9)
    rng = np.random.default_rng(seed)
    A = (J * inverse) @ J.T
    A += settings.IMPULSE_REGULARISATION * np.diag(np.diag(A))
    gaps = np.where(rng.random(len(A)) < 0.2, rng.uniform(0, 1e-3, len(A)), 0.0)
    b = J @ rng.normal(scale=0.5, size=J.shape[1]) + gaps
    for guess in (np.zeros(len(b), bool), np.ones(len(b), bool), rng.random(len(b)) < 0.5):
        for start in (None, np.where(rng.random(len(b)) < 0.7, rng.uniform(0, 2, len(b)), 0.0)):
            _check(A, b, _solve(sp.csr_array(A), b, guess, start))


def _cycling_scaled():
    data = np.load(CYCLING)
    m = len(data["b"])
    A = sp.csr_array((data["data"], data["indices"], data["indptr"]), shape=(m, m))
    return _scaled(A, data["b"], data["guess"])


@pytest.mark.parametrize("seed", [4, 5, 6])
def test_the_packed_factor_refactored_from_a_row_on_is_the_whole_factorization(seed):
    """A set changed from row k on, its packed factor (member rows alone) redone from k over
    the last one, equals the packed factor of the new set made whole, and both equal to the bit
    the envelope factor of the new set at its kept members' rows and columns (a factor row
    depends only on the rows before it; the rows left out add zeros)."""
    S, envelope, _, _, _, live, _, _ = _cycling_scaled()
    first, offset, values = envelope
    m = len(first)
    rng = np.random.default_rng(seed)
    before = live & (rng.random(m) < 0.7)
    after = before.copy()
    k = int(rng.integers(1, m - 1))
    after[k:] = live[k:] & (rng.random(m - k) < 0.7)
    after[k] = not before[k] and live[k]  # row k itself changes

    def packed_factor(sets):
        packed = tuple(np.zeros(m + 1, np.int64) for _ in range(4))
        L, kept, scales = np.zeros(values.size), np.zeros(m, bool), np.empty((m, 2))
        for member, start in sets:
            n = env.refactor_members(
                *S, member, settings.LCP_DEPENDENT, start, packed, L, kept, scales
            )
        return n, packed, L, kept

    n, packed, L, kept = packed_factor([(before, 0), (after, k)])
    n_whole, packed_whole, L_whole, kept_whole = packed_factor([(after, 0)])
    pos, rows, pfirst, poffset = packed
    size = poffset[n]
    assert n == n_whole == after.sum()
    assert np.array_equal(L[:size], L_whole[:size]) and np.array_equal(kept[:n], kept_whole[:n])
    assert all(
        np.array_equal(a[:n], b[:n]) for a, b in zip(packed[1:], packed_whole[1:], strict=True)
    )
    dense = np.zeros((n, n))  # the packed factor, unpacked
    for w in range(n):
        dense[w, pfirst[w] : w + 1] = L[poffset[w] : poffset[w + 1]]
    L_env, kept_env = np.empty(values.size), np.empty(m, bool)
    env.factor(first, offset, values, after, settings.LCP_DEPENDENT, L_env, kept_env)
    full = np.zeros((m, m))
    for i in range(m):
        full[i, first[i] : i + 1] = L_env[offset[i] : offset[i + 1]]
    members = rows[:n]
    assert np.array_equal(kept[:n], kept_env[members])
    assert np.array_equal(dense, full[np.ix_(members, members)])
    assert np.all(full[np.ix_(members, np.flatnonzero(~after))] == 0.0)


@pytest.mark.parametrize("seed", [10, 11, 12])
def test_rows_taken_out_of_the_packed_factor_by_updates_leave_the_factor_of_the_rest(seed):
    """Rows leaving the member set one after another, each taken out of the packed factor by a
    rank-one update (remove_member): the factor then reproduces S over the remaining members to
    rounding (lower triangular with a positive diagonal: their Cholesky factor), and each row
    taken out is an identity row with a zero column."""
    S, envelope, _, _, _, live, _, _ = _cycling_scaled()
    m = len(live)
    rng = np.random.default_rng(seed)
    member = live & (rng.random(m) < 0.8)
    packed = tuple(np.zeros(m + 1, np.int64) for _ in range(4))
    L, kept, scales = np.zeros(envelope[2].size), np.zeros(m, bool), np.empty((m, 2))
    n = env.refactor_members(*S, member, settings.LCP_DEPENDENT, 0, packed, L, kept, scales)
    pos, rows, first, offset = packed
    assert kept[:n].all()  # (no row of this set is left out as dependent)
    out = np.sort(rng.choice(n, 6, replace=False))
    rotations = np.empty((n, 2))
    for k in out:
        env.remove_member(first, offset, L, kept, scales, n, k, rotations)
    factor = np.zeros((n, n))
    for w in range(n):
        factor[w, first[w] : w + 1] = L[offset[w] : offset[w + 1]]
    dense = sp.csr_array((S[2], S[1], S[0]), shape=(m, m)).toarray()[np.ix_(rows[:n], rows[:n])]
    rest = np.setdiff1d(np.arange(n), out)
    product = factor @ factor.T
    assert np.abs(product[np.ix_(rest, rest)] - dense[np.ix_(rest, rest)]).max() <= 1e-14
    assert np.all(np.diag(factor)[rest] > 0.0) and not kept[out].any()
    assert np.array_equal(factor[out], np.eye(n)[out]) and np.all(factor[:, out][rest] == 0.0)
    assert np.allclose(scales[rest, 0], 1.0 / np.diag(factor)[rest], rtol=1e-15, atol=0.0)


def _q(S, b, f):
    return 0.5 * f @ (S @ f) + b @ f


@pytest.mark.parametrize("seed", [7, 8, 9])
def test_the_projected_search_stops_at_the_first_minimiser_on_its_path(seed):
    """From a random feasible f towards the minimiser y of q over its free rows (with negative
    forces), the search ends where q along
    max(f + t (y - f), 0) stops falling: q there is the least on the path up to it and at most
    q(f), and a grid of 20,001 points on the path (evaluated apart, with S as a dense matrix)
    finds q's first rise within a grid step of it; the rows it freed are exactly 0."""
    (indptr, indices, data), _, _, b, _, live, _, _ = _cycling_scaled()
    m = len(b)
    S = sp.csr_array((data, indices, indptr), shape=(m, m)).toarray()
    rng = np.random.default_rng(seed)
    f = np.where(live & (rng.random(m) < 0.6), rng.uniform(0.0, 1.0, m), 0.0)
    free = f > 0.0
    y = np.zeros(m)
    y[free] = np.linalg.solve(S[np.ix_(free, free)], -b[free])  # as the method: q's minimiser
    p = y - f
    breaks, rows = np.empty(m), np.empty(m, np.int64)
    negative = np.flatnonzero(y < 0.0)
    breaks[: len(negative)], rows[: len(negative)] = (
        f[negative] / (f[negative] - y[negative]),
        negative,
    )
    moved = f.copy()
    t = _projected_search(
        (indptr, indices, data), b, moved, p.copy(), breaks, rows, len(negative), np.empty(m)
    )
    grid = np.linspace(0.0, 1.0, 20_001)
    path = [_q(S, b, np.maximum(f + s * p, 0.0)) for s in grid]
    rise = next((i for i in range(len(grid) - 1) if path[i + 1] > path[i]), len(grid) - 1)
    assert abs(t - grid[rise]) <= 1.0 / 20_000
    frozen = negative[f[negative] / (f[negative] - y[negative]) <= t]
    assert t > 0.0 and len(frozen) > 0  # (the case the test is about: rows freed on the way)
    assert np.allclose(moved, np.maximum(f + t * p, 0.0), rtol=0.0, atol=1e-14)
    q_end = _q(S, b, moved)
    assert q_end <= _q(S, b, f) and q_end <= min(path[: rise + 1]) + 1e-12 * abs(q_end)
    assert np.all(moved[frozen] == 0.0)
    assert np.array_equal(
        np.flatnonzero((moved == 0.0) & (f > 0.0)), np.sort(frozen[f[frozen] > 0])
    )
