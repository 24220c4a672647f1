"""Every path of the contact-force solver, each checked against an exact answer.

The paths (runtime.solve.lcp_dense's counts[PATH], runtime.solve.lcp_sparse): a warm start
that hits, one that misses and hands over to pivoting, the single-row path, the fallback chain
(pivoting afresh, then projected Gauss-Seidel with its clamped set solved exactly -- forced with
pivot budgets), the sparse path (cold and warm), joints, islands, and the compiled core called
from compiled code. References: stacks of discs (each contact carries the weight above it,
exactly), duplicated contacts (the least norm halves each force), hanging discs (a joint pulls
m g), and the factorizations against NumPy.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from lcp_oracle import Contact, G, contact_matrix, gravity_b, packed_pile, row_violation
from scipy.optimize import lsq_linear

from runtime import settings
from runtime.compiled import njit
from runtime.solve import lcp, lcp_dense, lcp_envelope, lcp_factor, lcp_sparse
from runtime.solve.lcp_baraff import DRIVES, PIVOTS, is_solution
from runtime.solve.lcp_dense import PATH, PIVOTED, PIVOTED_FRESH, POLISHED, SINGLE, WARM_HIT

TOL = settings.LCP_TOL


def stack(masses, duplicated: bool = False):
    """A vertical stack of discs on the floor: (A, b, exact forces). Contact k (the floor's for
    k = 0) carries the weight of discs k.. above it; with ``duplicated`` every contact is
    reported twice (identical rows) and the least-norm forces are half of that on each."""
    n = len(masses)
    contacts = [Contact(0, -1, (0.0, 1.0), (0.0, -0.5))]
    contacts += [Contact(k, k - 1, (0.0, 1.0), (0.0, -0.5), (0.0, 0.5)) for k in range(1, n)]
    exact = G * np.cumsum(np.asarray(masses, float)[::-1])[::-1]
    if duplicated:
        contacts = [c for c in contacts for _ in range(2)]
        exact = np.repeat(exact / 2, 2)
    A, J, inverse = contact_matrix(masses, [0.1 * m for m in masses], contacts)
    return A, gravity_b(J, inverse), exact


def dense_call(A, b, guess=None, joint=None, budgets=None):
    """(status, f, clamped, counts) of the compiled core."""
    m = len(b)
    f, clamped, counts = np.empty(m), np.empty(m, bool), np.zeros(8, np.int64)
    joint = np.zeros(m, bool) if joint is None else np.asarray(joint, bool)
    guess = np.zeros(m, bool) if guess is None else np.asarray(guess, bool)
    A = np.ascontiguousarray(A, dtype=float)
    b = np.asarray(b, float)
    if budgets is None:
        status = lcp_dense.solve_dense_counted(A, b, joint, guess, TOL, f, clamped, counts)
    else:
        limits = np.asarray(budgets, float)
        status = lcp_dense.solve_dense_limited(A, b, joint, guess, TOL, f, clamped, counts, limits)
    return status, f, clamped, counts


MASSES = [2.0, 0.5, 3.0, 1.0, 0.7, 4.0]


# --- warm starts --------------------------------------------------------------------------


def test_warm_hit_returns_the_exact_forces() -> None:
    A, b, exact = stack(MASSES)
    status, f, clamped, counts = dense_call(A, b)
    assert status == 0 and counts[PATH] == PIVOTED and clamped.all()
    status, f, _, counts = dense_call(A, b, guess=clamped)
    assert status == 0 and counts[PATH] == WARM_HIT
    assert counts[DRIVES] == 0 and counts[PIVOTS] == 0
    np.testing.assert_allclose(f, exact, rtol=1e-13)


def test_warm_hit_with_redundant_rows_returns_the_least_norm_forces() -> None:
    A, b, exact = stack(MASSES, duplicated=True)
    status, f, clamped, counts = dense_call(A, b)
    np.testing.assert_allclose(f, exact, rtol=1e-12)
    status, f, _, counts = dense_call(A, b, guess=clamped)
    assert status == 0 and counts[PATH] == WARM_HIT
    np.testing.assert_allclose(f, exact, rtol=1e-12)


@pytest.mark.parametrize("wrong", ["too few", "too many"])
def test_warm_miss_hands_over_to_pivoting(wrong: str) -> None:
    """A guess missing contacts (they must join) or holding a lifting one (it must leave):
    pivoting from the guess's valid part finds the exact forces."""
    masses = MASSES + [1.5]
    A, b, exact = stack(masses)
    if wrong == "too few":
        guess = np.arange(len(masses)) % 3 == 0
    else:  # an extra contact pulled apart: the top disc is accelerated upwards by 20 m/s^2
        b = b.copy()
        b[-1] += 20.0 + G
        exact = exact - exact[-1]
        guess = np.ones(len(masses), bool)
    status, f, _, counts = dense_call(A, b, guess=guess)
    assert status == 0 and counts[PATH] == PIVOTED
    np.testing.assert_allclose(f, exact, rtol=1e-12, atol=1e-12 * np.max(exact))


def test_solve_warm_from_python() -> None:
    A, b, exact = stack(MASSES)
    f, clamped = lcp.solve_warm(A, b)
    again, held = lcp.solve_warm(A, b, guess=clamped)
    np.testing.assert_allclose(again, exact, rtol=1e-13)
    np.testing.assert_array_equal(held, clamped)


# --- one row ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("a_00", "b_0", "joint", "force", "held"),
    [
        (2.0, -4.0, False, 2.0, True),  # pressed: f = -b / A
        (2.0, 4.0, False, 0.0, False),  # separating: never the pulling -b / A = -2
        (2.0, 0.0, False, 0.0, True),  # touching, no force needed
        (2.0, 4.0, True, -2.0, True),  # a joint pulls
        (0.0, 1.0, False, 0.0, False),  # no force moves the row, and none is needed
    ],
)
def test_single_row(a_00, b_0, joint, force, held) -> None:
    status, f, clamped, counts = dense_call([[a_00]], [b_0], joint=[joint])
    assert status == 0 and counts[PATH] in (SINGLE, 0)
    assert f[0] == force and clamped[0] == held


def test_single_immovable_row_that_needs_a_force_is_infeasible() -> None:
    status, f, clamped, _ = dense_call([[0.0]], [-1.0])
    assert status == lcp_dense.INFEASIBLE and clamped[0]
    with pytest.raises(lcp.ContactSolverError, match=r"contact 0 .*infeasible.*residual 1"):
        lcp.solve_warm(np.zeros((1, 1)), np.array([-1.0]))


# --- the fallback chain -------------------------------------------------------------------


@pytest.mark.parametrize(
    ("forces", "valid"),
    [
        ((1.0, 1.0), True),  # the solution: a = A f + b = 0 on both pushed rows
        ((0.9, 1.0), False),  # pushed rows left approaching: a = (-0.2, -0.1)
        ((1.1, 1.0), False),  # pushed rows driven apart: a = (0.2, 0.1)
        ((0.0, 1.5), False),  # row 0 takes no force and penetrates: a_0 = -1.5
    ],
)
def test_every_path_s_acceptance_check_is_the_lcp_conditions(forces, valid) -> None:
    """lcp_baraff.is_solution, the check each path's forces must pass (warm hit, pivoting,
    polish, least norm), against the LCP's definition on A = [[2, 1], [1, 2]], b = (-3, -3),
    whose one solution is f = (1, 1): a pushed row (f > 0) needs a = 0 -- approaching (a < 0)
    as much as separating -- and an unpushed one a >= 0."""
    A, b = np.array([[2.0, 1.0], [1.0, 2.0]]), np.array([-3.0, -3.0])
    f = np.array(forces)
    a, tol_a = np.empty(2), np.empty(2)
    assert is_solution(A, b, np.zeros(2, bool), f, TOL, a, tol_a) == valid
    np.testing.assert_allclose(a, A @ np.array(forces) + b, atol=1e-15)


@pytest.mark.parametrize(
    ("budgets", "path"), [((1, 0), PIVOTED_FRESH), ((1, 1), POLISHED), ((3, 2), POLISHED)]
)
def test_fallback_chain_finds_the_exact_forces(budgets, path) -> None:
    """Pivoting cut short after a pivot or two (the budgets stand in for a cycle or lost
    accuracy): the fresh attempt, or projected Gauss-Seidel with its clamped set solved
    exactly, still returns the exact forces -- also with redundant (duplicated) rows."""
    for duplicated in (False, True):
        A, b, exact = stack(MASSES, duplicated)
        status, f, _, counts = dense_call(A, b, budgets=budgets)
        assert status == 0 and counts[PATH] == path
        np.testing.assert_allclose(f, exact, rtol=1e-11)


def test_fallback_chain_still_reports_an_infeasible_problem() -> None:
    """Opposed contacts pressing one body (a_0 + a_1 = -2 whatever f is): every fallback
    fails and the solve reports it (pivoting cut short: STUCK; in full: INFEASIBLE, with the
    certificate's rows), never a force."""
    A, b = [[1.0, -1.0], [-1.0, 1.0]], [-1.0, -1.0]
    status, f, _, _ = dense_call(A, b, budgets=(1, 1))
    assert status == lcp_dense.STUCK and np.all(np.isfinite(f))
    status, _, blame, counts = dense_call(A, b)
    assert status == lcp_dense.INFEASIBLE and blame.all() and counts[PATH] == POLISHED


# --- the sparse path ----------------------------------------------------------------------


def _sparse(A, b, guess=None, tol=TOL):
    counts = np.zeros(8, np.int64)
    m = len(b)
    guess = np.zeros(m, bool) if guess is None else guess
    f, clamped, status, _ = lcp_sparse.solve_sparse(
        sp.csr_array(A), b, np.zeros(m, bool), guess, tol, counts
    )
    return status, f, clamped, counts


@pytest.mark.parametrize("duplicated", [False, True])
def test_sparse_path_cold_and_warm(duplicated: bool) -> None:
    """A stack of 150 discs (masses 0.1-10 kg): cold, then warm from its own clamped set (one
    factorization), both exact; ``solve`` picks the sparse path for it."""
    rng = np.random.default_rng(3)
    A, b, exact = stack(rng.uniform(0.1, 10.0, 150), duplicated)
    status, f, clamped, counts = _sparse(A, b)
    assert status == 0 and counts[PATH] == 0  # the dense fallback sets a path
    np.testing.assert_allclose(f, exact, rtol=1e-10)
    status, f, _, counts = _sparse(A, b, guess=clamped)
    assert status == 0 and counts[1] == 1  # one round of block pivoting
    np.testing.assert_allclose(f, exact, rtol=1e-10)
    stats: dict = {}
    np.testing.assert_allclose(lcp.solve(sp.csr_array(A), b, stats=stats), exact, rtol=1e-10)
    assert stats["paths"] == {"sparse": 1}


@pytest.mark.parametrize("warm", [True, False])
def test_sparse_path_on_a_statically_indeterminate_pile(warm: bool) -> None:
    """A packed pile of 53 discs (157 contacts, rank 114), warm-started from every contact
    clamped (a resting pile's last set) or cold: block pivoting's basic forces go negative on
    such a set, and the sparse path finds the least-norm forces itself, without the dense
    solver's O(m^3) fallback. Reference, apart from the solver: min |f|^2 over f >= 0 with
    A f = -b, by scipy's bounded least squares on the equations weighted by 1e5 (off by
    ~|f| / 1e10)."""
    A, b, _, _ = packed_pile(10, 6)
    m = len(b)
    assert np.linalg.matrix_rank(A) < m  # redundant
    weighted = np.vstack([1e5 * A, np.eye(m)])
    want = lsq_linear(weighted, np.concatenate([-1e5 * b, np.zeros(m)]), bounds=(0, np.inf),
                      method="bvls", tol=1e-15).x  # fmt: skip
    status, f, clamped, counts = _sparse(A, b, guess=np.full(m, warm))
    assert status == 0 and counts[PATH] == 0  # no dense fallback (it sets a path)
    np.testing.assert_allclose(f, want, rtol=0, atol=1e-7 * want.max())
    violation, scale, unit = row_violation(A, b, np.zeros(m, bool), f)
    assert np.all(violation <= TOL * scale + settings.LCP_FLOOR * unit)


def test_sparse_path_agrees_with_the_dense_one_on_random_piles() -> None:
    """Random redundant contact sets of ~120 rows, each row valid and a = A f + b the same as
    the dense path's (unique for PSD A)."""
    rng = np.random.default_rng(11)
    for _ in range(3):
        bodies = 40
        contacts = []
        for k in range(120):
            body = k % bodies
            below = body - int(rng.integers(1, 4)) if body >= 3 else -1
            angle = rng.normal(np.pi / 2, 0.3)
            lever = (rng.uniform(-0.3, 0.3), -0.5)
            contacts.append(
                Contact(body, below, (np.cos(angle), np.sin(angle)), lever, (lever[0], 0.5))
            )
        A, J, inverse = contact_matrix(rng.uniform(0.5, 2, bodies), np.ones(bodies), contacts)
        b = gravity_b(J, inverse)
        status, f, _, _ = _sparse(A, b)
        assert status == 0
        violation, scale, unit = row_violation(A, b, np.zeros(len(b), bool), f)
        assert np.all(violation <= 4 * (TOL * scale + settings.LCP_FLOOR * unit))
        dense = lcp.solve(A, b)
        np.testing.assert_allclose(A @ f + b, A @ dense + b, atol=1e-7 * np.max(np.abs(b)))


def test_envelope_factor_matches_numpy() -> None:
    """The skyline Cholesky with dropped rows solves the kept block exactly (vs NumPy)."""
    rng = np.random.default_rng(5)
    m = 60
    J = np.zeros((m, 40))
    for i in range(m):
        J[i, rng.integers(max(0, i // 2 - 3), min(40, i // 2 + 3), 2)] = rng.normal(size=2)
    J[10] = J[11]  # an exactly dependent row
    S = J @ J.T + 1e-3 * np.eye(m) * (np.arange(m) % 7 != 0)
    d = 1 / np.sqrt(np.diagonal(S))
    S = d[:, None] * S * d[None, :]
    Sc = sp.csr_array(S)
    first, offset, values = lcp_envelope.envelope(Sc.indptr, Sc.indices, Sc.data)
    member = rng.random(m) < 0.8
    L, kept = np.empty(values.size), np.zeros(m, bool)
    lcp_envelope.factor(first, offset, values, member, settings.LCP_DEPENDENT, L, kept)
    assert np.all(kept <= member)
    rhs = np.where(kept, rng.normal(size=m), 0.0)
    x = np.empty(m)
    lcp_envelope.solve(first, offset, L, rhs, x)
    np.testing.assert_allclose(x[kept], np.linalg.solve(S[np.ix_(kept, kept)], rhs[kept]))
    assert np.all(x[~kept] == 0.0)
    assert np.linalg.matrix_rank(S[np.ix_(member, member)]) == kept.sum()


# --- joints, islands, compiled callers ------------------------------------------------------


def test_a_joint_pulls_and_a_contact_does_not() -> None:
    """A disc (m = 3) hanging from a ceiling: as a joint the row pulls with m g (f = -m g in
    the gap's direction), as a contact it lets go (f = 0)."""
    A, J, inverse = contact_matrix([3.0], [1.0], [Contact(0, -1, (0.0, -1.0), (0.0, 0.5))])
    b = gravity_b(J, inverse)
    np.testing.assert_allclose(lcp.solve(A, b, joint=[True]), [-3.0 * G], rtol=1e-15)
    np.testing.assert_array_equal(lcp.solve(A, b), [0.0])


def test_joint_and_redundant_contact_share_the_load() -> None:
    """A disc resting on the floor and also held by a joint along the same line: the least-norm
    forces split m g evenly; a second, independent joint sideways carries nothing."""
    contacts = [
        Contact(0, -1, (0.0, 1.0), (0.0, -0.5)),
        Contact(0, -1, (0.0, 1.0), (0.0, -0.5)),
        Contact(0, -1, (1.0, 0.0), (-0.5, 0.0)),
    ]
    A, J, inverse = contact_matrix([2.0], [1.0], contacts)
    f = lcp.solve(A, gravity_b(J, inverse), joint=[True, False, True])
    np.testing.assert_allclose(f, [G, G, 0.0], rtol=1e-12, atol=1e-12)


def test_islands_are_solved_apart() -> None:
    """Three stacks (75 rows, more than LCP_DENSE_MAX) in one problem, rows interleaved: one
    island each, the exact forces."""
    rng = np.random.default_rng(1)
    parts = [stack(rng.uniform(0.5, 2.0, n)) for n in (30, 25, 20)]
    sizes = [len(p[1]) for p in parts]
    order = np.random.default_rng(0).permutation(sum(sizes))
    A = np.zeros((sum(sizes), sum(sizes)))
    start = 0
    for (block, _, _), n in zip(parts, sizes, strict=True):
        A[start : start + n, start : start + n] = block
        start += n
    b = np.concatenate([p[1] for p in parts])
    exact = np.concatenate([p[2] for p in parts])
    stats: dict = {}
    f = lcp.solve(A[np.ix_(order, order)], b[order], stats=stats)
    assert stats["islands"] == 3
    np.testing.assert_allclose(f, exact[order], rtol=1e-13)


@njit
def _from_compiled_code(A, b):
    m = b.size
    f, clamped = np.empty(m), np.empty(m, np.bool_)
    none = np.zeros(m, np.bool_)
    status = lcp_dense.solve_dense(A, b, none, none, 0.0, f, clamped)
    return status, f


def test_compiled_core_is_callable_from_compiled_code() -> None:
    A, b, exact = stack(MASSES)
    status, f = _from_compiled_code(np.ascontiguousarray(A), b)
    assert status == 0
    np.testing.assert_allclose(f, exact, rtol=1e-13)


def test_compiled_core_reports_bad_input() -> None:
    status, *_ = dense_call([[1.0, 2.0], [0.0, 1.0]], [1.0, 1.0])
    assert status == lcp_dense.BAD_INPUT
    status, *_ = dense_call([[1.0, 0.0], [0.0, np.nan]], [1.0, 1.0])
    assert status == lcp_dense.BAD_INPUT


# --- the factor -----------------------------------------------------------------------------


def test_factor_updates_match_a_fresh_cholesky() -> None:
    """Rows entering (one substitution) and leaving (a rank-one update) keep L L^T = S_CC."""
    rng = np.random.default_rng(7)
    J = rng.normal(size=(30, 40))
    S = J @ J.T
    L, rows = lcp_factor.empty_factor(30)
    row, work = np.empty(30), np.empty(30)
    k = 0
    for _ in range(200):
        if k and (k == 30 or rng.random() < 0.4):
            k = lcp_factor.remove(L, rows, k, int(rng.integers(k)), work)
        else:
            j = int(rng.choice(sorted(set(range(30)) - set(rows[:k].tolist()))))
            pivot, _ = lcp_factor.trial(S, L, rows, k, j, row)
            k = lcp_factor.add(L, rows, k, j, row, pivot)
        sub = S[np.ix_(rows[:k], rows[:k])]
        Lk = np.tril(L[:k, :k])
        np.testing.assert_allclose(Lk @ Lk.T, sub, atol=1e-10 * np.max(np.abs(sub), initial=1))


def test_pivoted_basis_reveals_the_rank() -> None:
    """J J^T with duplicated, opposed and combined rows: the basis has NumPy's rank, and its
    block is factored exactly."""
    rng = np.random.default_rng(2)
    J = rng.normal(size=(12, 7))
    J = np.vstack([J, J[:3], -J[3:5], J[5] + 2 * J[6]])
    S = J @ J.T
    d = 1 / np.sqrt(np.diagonal(S))
    S = d[:, None] * S * d[None, :]
    m = len(S)
    L, rows = lcp_factor.empty_factor(m)
    k = lcp_factor.factor_basis(S, np.arange(m), m, L, rows, settings.LCP_DEPENDENT)
    assert k == np.linalg.matrix_rank(J) == 7
    Lk = np.tril(L[:k, :k])
    np.testing.assert_allclose(Lk @ Lk.T, S[np.ix_(rows[:k], rows[:k])], atol=1e-12)
