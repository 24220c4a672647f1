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
from runtime.solve import assembly, lcp_loaded

TOL = settings.LCP_TOL


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


def test_a_landing_pile_whose_loaded_set_leaves_bodies_free(pile) -> None:
    """The packed pile with three more discs, each on one top disc at 0.3 rad off the vertical:
    the loaded rows depend on each other (the pile) and leave each new disc free to slide along
    its contact, so K = B_P^T B_P is singular too (the module docstring's null space). The
    forces are still the oracle's least-norm ones to 1e-9 of the largest, every LCP condition
    to the solver's tolerance."""
    A, b, J, inverse, _, _ = pile
    mass = 1.0 / inverse[0]
    n = J.shape[1] // 3
    top = [n - 1, n - 3, n - 5]  # discs of the top row
    contacts = []
    for k, below in enumerate(top):
        normal = (np.sin(0.3) * (-1) ** k, np.cos(0.3))
        lever = (-0.5 * normal[0], -0.5 * normal[1])
        contacts.append(Contact(n + k, below, normal, lever, (-lever[0], -lever[1])))
    masses, inertias = np.full(n + 3, mass), np.full(n + 3, 0.125 * mass)
    _, J_new, inverse_new = contact_matrix(masses, inertias, contacts)
    J_all = np.zeros((len(b) + 3, 3 * (n + 3)))
    J_all[: len(b), : 3 * n] = J
    J_all[len(b) :] = J_new
    A_all = J_all @ (inverse_new[:, None] * J_all.T)
    b_all = gravity_b(J_all, inverse_new)
    want = least_norm_qp(
        A_all, b_all, np.zeros(len(b_all), bool), np.zeros(len(b_all)), 1e-9 * np.abs(b_all).max()
    )
    loaded = want > 1e-9 * want.max()
    B_P = (J_all * np.sqrt(inverse_new))[loaded]
    touched = np.count_nonzero(np.abs(B_P).sum(axis=0))
    rank = np.linalg.matrix_rank(B_P)
    assert rank < loaded.sum() and rank < touched  # dependent rows, and free directions
    B, columns, A_csr = _problem(J_all, inverse_new, b_all)
    found = lcp_loaded.solve_loaded(B, columns, A_csr, b_all, loaded)
    assert found is not None
    f, clamped = found
    np.testing.assert_allclose(f, want, rtol=0, atol=1e-9 * want.max())
    assert clamped.all()
    violation, scale, unit = row_violation(A_all, b_all, np.zeros(len(b_all), bool), f)
    assert np.all(violation <= settings.LCP_TOL * scale + settings.LCP_FLOOR * unit)


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
def test_a_loaded_set_that_leaves_a_body_free_gets_its_least_norm_forces(copies: int) -> None:
    """A disc on a slope, its contact (normal not along a body axis) loaded once or twice (a
    duplicated contact): K = B^T B has rank 1 on the two columns the rows touch, the disc is
    free to slide. The force is the closed form -b/A, shared equally by the two copies (the
    least-norm split), to 1e-12."""
    normal = (np.sin(0.3), np.cos(0.3))
    contacts = [Contact(0, -1, normal, (0.0, -0.5))] * copies
    A, J, inverse = contact_matrix([1.0], [0.1], contacts)
    b = gravity_b(J, inverse)
    B, columns, A_csr = _problem(J, inverse, b)
    found = lcp_loaded.solve_loaded(B, columns, A_csr, b, np.ones(copies, bool))
    assert found is not None
    np.testing.assert_allclose(found[0], -b[0] / A[0, 0] / copies, rtol=1e-12, atol=0)
    assert found[1].all()


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


def _engine_rows(J: np.ndarray, inverse: np.ndarray):
    """The engine's per-contact arrays of the oracle's J (bodies in 3-column blocks): jacobian
    rows (m, 6), body1, body2 (the ground: a fixed body after the others), inverse masses,
    fixed."""
    n = J.shape[1] // 3
    m = J.shape[0]
    jac, body1, body2 = np.zeros((m, 6)), np.full(m, n), np.full(m, n)
    for k in range(m):
        bodies = [i for i in range(n) if np.any(J[k, 3 * i : 3 * i + 3])]
        for side, i in enumerate(bodies):
            jac[k, 3 * side : 3 * side + 3] = J[k, 3 * i : 3 * i + 3]
            (body1 if side == 0 else body2)[k] = i
    inv_mass = np.vstack([inverse.reshape(n, 3), np.zeros((1, 3))])
    fixed = np.zeros(n + 1, bool)
    fixed[n] = True
    return jac, body1, body2, inv_mass, fixed


def test_a_small_packed_island_in_the_compiled_assembly() -> None:
    """A packed pile of 26 discs (72 contacts: above settings.LOADED_ISLAND, within
    settings.DENSE_ISLAND), solved as the compiled frame and stages solve an island
    (assembly.solve_small_islands) from a guess of every contact held. Its rows are dependent,
    so the warm start's Cholesky refuses them; the forces are the oracle's least-norm ones to
    1e-9 of the largest, and the guess becomes their loaded set. The next solve starts from
    that set in body space (its forces are lcp_loaded.solve_island's, to the bit) and gives
    the oracle's forces again."""
    A, b, J, inverse = packed_pile(7, 4)
    m = len(b)
    assert settings.LOADED_ISLAND <= m <= settings.DENSE_ISLAND
    want = least_norm_qp(A, b, np.zeros(m, bool), np.zeros(m), 1e-9 * np.abs(b).max())
    jac, body1, body2, inv_mass, fixed = _engine_rows(J, inverse)
    free_acc = np.zeros((len(fixed), 3))
    free_acc[:-1, 1] = -9.81
    offsets, guess = np.array([0, m]), np.ones(m, bool)
    tried = assembly.solve_with_guess(A.copy(), b.copy(), m, guess.copy(), TOL, np.zeros(m))
    assert tried == assembly.DEPENDENT
    solved = []
    for _ in range(2):
        start_guess = guess.copy()
        forces, rates, ok = np.zeros(m), np.zeros(m), np.zeros(1, bool)
        assembly.solve_small_islands(
            jac, body1, body2, np.zeros(m), inv_mass, fixed, free_acc, offsets, guess,
            settings.LCP_TOL, settings.DENSE_ISLAND, forces, rates, ok,
        )  # fmt: skip
        assert ok.all()
        np.testing.assert_allclose(rates, b, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(forces, want, rtol=0, atol=1e-9 * want.max())
        assert np.array_equal(guess, want > 1e-9 * want.max())
        solved.append((start_guess, forces))
    start_guess, forces = solved[1]
    data, indices, indptr, columns = assembly.island_scaled_jacobian(
        jac, body1, body2, inv_mass, fixed, 0, m
    )
    A_csr = assembly.island_csr(jac, body1, body2, inv_mass, fixed, 0, m)
    f, clamped = np.empty(m), np.empty(m, bool)
    assert lcp_loaded.solve_island((data, indices, indptr), columns, A_csr, b, start_guess, f,
                                   clamped)  # fmt: skip
    assert f.tobytes() == forces.tobytes()
