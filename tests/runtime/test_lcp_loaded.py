"""The contact forces of a large island from its loaded set (runtime.solve.lcp_loaded).

The reference is the oracle's least-norm QP (tests/lcp_oracle.py: SVD and Lawson and Hanson's
NNLS, none of the solver's algorithms) on a packed, statically indeterminate pile. The forces
must equal it, and a loaded set that is not the solution's must be refused, never answered.
In the engine, stepping a resting pile with and without this path must give the same motion.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from lcp_oracle import Contact, contact_matrix, gravity_b, least_norm_qp, packed_pile, row_violation

import runtime
from bench.steps import pile_scene
from runtime import settings
from runtime.solve import lcp_loaded


def _csr(matrix: np.ndarray) -> tuple:
    """(data, indices, indptr) of a dense matrix's non-zeros, sorted columns."""
    s = sp.csr_array(matrix)
    s.sort_indices()
    return s.data, s.indices.astype(np.int64), s.indptr.astype(np.int64)


def _problem(J, inverse, b):
    """solve_loaded's B and A arguments: B = J W^1/2 with its columns, A = B B^T with every
    diagonal entry stored (as the engine's assembly stores it)."""
    B = J * np.sqrt(inverse)
    A = B @ B.T
    return _csr(B), B.shape[1], _csr(A + np.diag(np.where(np.diag(A) == 0.0, 1e-300, 0.0)))


@pytest.fixture(scope="module", params=[1.0, 2e11])
def pile(request):
    """A packed pile of 53 discs (157 contacts, rank 114), of 1 kg or 2e11 kg discs, with its
    least-norm forces by the oracle and their loaded set."""
    A, b, J, inverse = packed_pile(10, 6)
    inverse = inverse / request.param
    A = A / request.param
    want = least_norm_qp(A, b, np.zeros(len(b), bool), np.zeros(len(b)), 1e-9 * np.abs(b).max())
    loaded = want > 1e-9 * want.max()
    return A, b, J, inverse, want, loaded


def test_the_least_norm_forces_of_a_packed_pile(pile) -> None:
    """From the oracle's loaded set: the oracle's forces to 1e-9 of the largest, every LCP
    condition to the solver's tolerance, every contact held (the pile is at rest)."""
    A, b, J, inverse, want, loaded = pile
    assert np.linalg.matrix_rank(A) < len(b)  # statically indeterminate
    assert 0 < np.count_nonzero(~loaded) < len(b) // 4  # some held contacts carry no force
    B, columns, A_csr = _problem(J, inverse, b)
    found = lcp_loaded.solve_loaded(B, columns, A_csr, b, loaded)
    assert found is not None
    f, clamped = found
    np.testing.assert_allclose(f, want, rtol=0, atol=1e-9 * want.max())
    assert np.array_equal(f > 0, loaded) and clamped.all()
    violation, scale, unit = row_violation(A, b, np.zeros(len(b), bool), f)
    assert np.all(violation <= settings.LCP_SHARP * scale + settings.LCP_FLOOR * unit)


def test_the_cached_ordering_gives_the_forces_of_a_fresh_one(pile) -> None:
    """The fill-reducing order of K is cached by K's pattern: a second solve (a cache hit) and
    a solve with the cache emptied give the same forces to the bit."""
    A, b, J, inverse, want, loaded = pile
    B, columns, A_csr = _problem(J, inverse, b)
    lcp_loaded._fill_reducing_order.cache_clear()
    fresh = lcp_loaded.solve_loaded(B, columns, A_csr, b, loaded)
    again = lcp_loaded.solve_loaded(B, columns, A_csr, b, loaded)
    assert lcp_loaded._fill_reducing_order.cache_info().hits == 1
    assert fresh is not None and again is not None
    assert fresh[0].tobytes() == again[0].tobytes() and np.array_equal(fresh[1], again[1])
    np.testing.assert_allclose(again[0], want, rtol=0, atol=1e-9 * want.max())  # the oracle's


def test_a_loaded_set_that_is_not_the_solutions_is_refused(pile) -> None:
    """A force-carrying contact left out of the set (the forces of the rest are then not the
    least-norm ones), the floor's contacts left out (the rest cannot hold the pile up: some
    row's a is not 0), a forceless one put in (its force comes out <= 0), every held contact
    taken as loaded: each gives None."""
    A, b, J, inverse, want, loaded = pile
    B, columns, A_csr = _problem(J, inverse, b)
    light = np.flatnonzero(loaded)[np.argmin(want[loaded])]
    floor = (J[:, 1::3] > 0).sum(axis=1) == 1  # the rows with one body pushed up, not across
    floor &= np.count_nonzero(J, axis=1) == 1
    assert floor.sum() == 10
    for wrong in (
        loaded & (np.arange(len(b)) != light),
        loaded & ~floor,
        loaded | (np.arange(len(b)) == np.flatnonzero(~loaded)[0]),
        np.ones(len(b), bool),
    ):
        assert lcp_loaded.solve_loaded(B, columns, A_csr, b, wrong) is None


def test_a_loaded_set_whose_rows_cannot_all_be_held_is_refused(pile) -> None:
    """One loaded contact's b lowered by 1 % of g: b is no longer in the range of the loaded
    rows (B_P v = -b_P has no exact solution), so the body-space forces, positive and with
    every multiplier of the right sign, leave some loaded row's a off 0 by ~1e-3 g: None (the
    problem's own solution lifts a contact)."""
    A, b, J, inverse, want, loaded = pile
    B, columns, A_csr = _problem(J, inverse, b)
    pushed = b.copy()
    pushed[np.flatnonzero(loaded)[len(b) // 2]] -= 0.01 * 9.81
    assert lcp_loaded.solve_loaded(B, columns, A_csr, pushed, loaded) is None


@pytest.mark.parametrize("copies", [1, 2])
def test_a_loaded_set_that_does_not_fix_the_bodies_is_refused(copies: int) -> None:
    """A disc on a slope, its contact (normal not along a body axis) loaded once or twice (a
    duplicated contact): K = B^T B has rank 1 on the two columns the rows touch, so the
    body-space solve has no unique v. One row is fewer than the columns (refused before K is
    built); two equal rows are as many, and the factorization finds K singular. The solution
    is left to the pivoting solver."""
    normal = (np.sin(0.3), np.cos(0.3))
    contacts = [Contact(0, -1, normal, (0.0, -0.5))] * copies
    A, J, inverse = contact_matrix([1.0], [0.1], contacts)
    b = gravity_b(J, inverse)
    B, columns, A_csr = _problem(J, inverse, b)
    assert lcp_loaded.solve_loaded(B, columns, A_csr, b, np.ones(copies, bool)) is None


def test_stepping_a_packed_pile_with_and_without_the_loaded_set() -> None:
    """The bench's packed pile of 60 discs (one island of 168 contacts, beyond the dense
    limit): 20 steps with the loaded-set path (which must answer every solve after the first)
    and with it switched off end in the same state to 1e-15 m and 1e-12 m/s, at rest."""
    counted = {"answered": 0, "asked": 0}
    original = lcp_loaded.solve_loaded

    def counting(*args):
        counted["asked"] += 1
        found = original(*args)
        counted["answered"] += found is not None
        return found

    states = []
    for loaded_path in (True, False):
        world = runtime.World(pile_scene(60, gap=0.0))
        if not loaded_path:
            world.stepper.forces.memory.loaded = None
        lcp_loaded.solve_loaded = counting
        try:
            for _ in range(20):
                report = world.step(1e-3)
        finally:
            lcp_loaded.solve_loaded = original
        assert len(report.recorded) > settings.DENSE_ISLAND
        states.append((world.poses.copy(), world.velocities.copy()))
    assert counted["asked"] > 20 and counted["answered"] == counted["asked"]
    (q1, v1), (q2, v2) = states
    np.testing.assert_allclose(q1, q2, rtol=0, atol=1e-15)
    np.testing.assert_allclose(v1, v2, rtol=0, atol=1e-12)
    assert np.abs(v1).max() < 1e-10
