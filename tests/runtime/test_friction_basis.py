"""The friction LCP's warm start (runtime.solve.friction_lcp.from_basis) against references.

* Lemke's final basis (runtime.solve.lemke) solves its own problem again by one LU solve: the
  same z; and, for q moved a little, the unique solution of a P-matrix problem, found by trying
  every complementary basis (written apart, NumPy's solver);
* a basis that is not the solution's is refused (z_B < 0 or w < 0 off the basis), and so is a
  singular one -- refused, not a NaN or an exception;
* in a sticking pile of discs the remembered bases give the forces that Lemke's method gives from
  a cold start, and the pile keeps Coulomb's law at every step.
"""

from __future__ import annotations

import itertools
from pathlib import Path

import numpy as np
import pytest

import runtime
from bench.steps import pile_scene
from runtime import settings
from runtime.solve import friction, friction_lcp, lemke


def _brute_force(M: np.ndarray, q: np.ndarray) -> np.ndarray:
    """The solution of the LCP (M, q) over all complementary bases (small n only)."""
    for basis in itertools.product((False, True), repeat=q.size):
        on = np.array(basis)
        z = np.zeros(q.size)
        if on.any():
            try:
                z[on] = np.linalg.solve(M[np.ix_(on, on)], -q[on])
            except np.linalg.LinAlgError:
                continue
        w = M @ z + q
        if np.all(z >= -1e-12) and np.all(w >= -1e-12):
            return z
    raise AssertionError("no solution")


def _p_matrix_problem(seed: int):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 8))
    B, S = rng.normal(size=(n, n)), rng.normal(size=(n, n))
    return B @ B.T + 0.1 * np.eye(n) + (S - S.T), rng.normal(size=n), rng  # a P-matrix


def _lemke(M, q):
    z, basic = np.zeros(q.size), np.zeros(q.size, bool)
    assert lemke.lemke_perturbed(M, q, z, basic, settings.LEMKE_COVERS) == lemke.SOLVED
    return z, basic


@pytest.mark.parametrize("seed", range(12))
def test_lemkes_basis_solves_its_problem_and_a_nearby_one(seed):
    M, q, rng = _p_matrix_problem(seed)
    z, basic = _lemke(M, q)
    again = np.full(q.size, np.nan)
    assert friction_lcp.from_basis(M, q, basic, again)
    np.testing.assert_allclose(again, z, rtol=1e-12, atol=1e-12)
    moved = q + 1e-7 * rng.normal(size=q.size)
    reference = _brute_force(M, moved)
    if np.min(np.maximum(reference, M @ reference + moved)) < 1e-6:
        pytest.skip("the moved problem is nearly degenerate: its basis may change")
    assert friction_lcp.from_basis(M, moved, basic, again)
    np.testing.assert_allclose(again, reference, rtol=1e-10, atol=1e-12)


def test_lemkes_basis_is_taken_again_beside_a_contact_without_force():
    """The friction LCP of a 37-contact island of the falling 20-disc pile with mu = 0.5 at
    rest (t = 0.611 s): a contact carries no force, so the rows of its cone and slack have
    terms of rounding size only (< 1e-12 of the largest). Measured by those terms alone, Lemke's
    own final basis was refused as a warm start (w = -1e-16 N against a row scale of 1e-16),
    and Lemke's method ran again at every solve: a resting pile cost 16 ms a step instead of 1.
    solve_island's warm start takes the basis, its z Lemke's, and z solves the LCP (numpy)."""
    island = _island("friction_unloaded_basis.npz")
    args = [island[name] for name in _INPUTS]
    M, q, stick = friction_lcp.island_lcp(*args, np.zeros(island["mu"].size))
    z, basic = _lemke(M, q)
    np.testing.assert_array_equal(basic, island["basic"])
    own = np.abs(q) + np.abs(M) @ z  # each row's scale from its own terms
    assert own[basic].min() < 1e-12 * own.max()
    assert not friction_lcp._complementary(M, q, z, basic, settings.LCP_SHARP)  # so measured
    jac, tangent_jac, ends, bias, tangent_bias, mu, slide = args[:7]
    folded = friction_lcp._folded(jac, tangent_jac, mu, slide)
    rows = (jac, tangent_jac, ends, folded, stick, mu, island["inv_mass"], island["fixed"])
    again = np.full(q.size, np.nan)
    k = mu.size
    assert friction_lcp._warm(rows, bias, tangent_bias, island["free_acc"], q[:k].copy(), basic,
                              again)  # fmt: skip
    np.testing.assert_allclose(again, z, rtol=0, atol=1e-10 * z.max())  # (Lemke: 2e-12)
    w = M @ again + q
    assert again.min() >= 0.0 and w.min() >= -1e-12 * own.max()
    assert np.abs(again * w).max() <= 1e-12 * own.max() * again.max()


def test_lemkes_forces_are_solved_again_on_its_final_basis():
    """A 38-contact island of the falling 20-disc pile with mu = 0.5 (t = 0.662 s), every
    contact sticking: the end of Lemke's path solves the LCP to its own check (1e-9), but the
    tableau's rounding leaves sticking contacts up to 3.8e-9 N (1.3e-10 of the largest force)
    outside their cones, and friction of 2e-10 N at contacts without normal force. solve_island solves Lemke's final
    basis again by one factorization: every friction force in its cone to rounding."""
    island = _island("friction_lemke_rounding.npz")
    args = [island[name] for name in _INPUTS]
    M, q, stick = friction_lcp.island_lcp(*args, np.zeros(island["mu"].size))
    k, s = island["mu"].size, stick.size
    z, _ = _lemke(M, q)
    outside = z[k : k + s] + z[k + s : k + 2 * s] - island["mu"][stick] * z[stick]
    assert outside.max() > 1e-11 * z.max()  # Lemke's tableau, as it ends
    status, normal, tangent, _, _ = _solved(island, _island_solve(hold_first=False))
    assert status == lemke.SOLVED
    mu = island["mu"]
    assert np.all(np.abs(tangent) <= mu * normal + 1e-13 * normal.max())


@pytest.mark.parametrize("seed", range(12))
def test_a_basis_not_the_solutions_is_refused(seed):
    M, q, _ = _p_matrix_problem(seed)
    _, basic = _lemke(M, q)
    for i in range(q.size):  # a P-matrix problem has one solution: every other basis is wrong
        wrong = basic.copy()
        wrong[i] = not wrong[i]
        z = np.zeros(q.size)
        assert not friction_lcp.from_basis(M, q, wrong, z)


def test_a_singular_basis_is_refused_without_nans():
    M = np.array([[1.0, 1.0, 0.0], [1.0, 1.0, 0.0], [0.0, 0.0, 2.0]])  # rows 0, 1 equal
    q = np.array([-1.0, -1.0, -2.0])
    z = np.zeros(3)
    assert not friction_lcp.from_basis(M, q, np.array([True, True, True]), z)
    z, basic = _lemke(M, q)  # Lemke's basis keeps one of the equal rows only
    assert basic.tolist() in ([True, False, True], [False, True, True])
    again = np.zeros(3)
    assert friction_lcp.from_basis(M, q, basic, again)
    np.testing.assert_allclose(M @ again + q, [0.0, 0.0, 0.0], atol=1e-15)


def _frictional_pile(n: int, mu: float):
    scene = pile_scene(n, gap=0.0)
    for body in scene.bodies:
        body.friction = mu
    return scene


def test_a_sticking_pile_gets_lemkes_forces_from_its_remembered_bases():
    """A packed pile of 12 discs with mu = 0.5 (dependent rows: more contacts than velocities):
    the forces of a stepped world's frame solved again with the remembered bases and cold
    (bases cleared) give the same accelerations, and its bases were used: the warm solve
    leaves them as they were."""
    world = runtime.World(_frictional_pile(12, 0.5))
    for _ in range(20):
        world.step(1e-3)
    stepper, contacts = world.stepper, world.contacts
    q, v = world.poses, world.velocities
    assert 2 * len(contacts) > 3 * 12  # normal and tangential rows: more than the velocities
    resting = stepper.contact_forces(contacts, q, v)
    warm = resting.problem.basis.copy()
    assert np.count_nonzero(warm) > 0
    again = stepper.contact_forces(contacts, q, v)
    assert np.array_equal(again.problem.basis, warm)
    stepper.forces.bases = type(stepper.forces.bases)(dtype=np.int8)
    cold = stepper.contact_forces(contacts, q, v)
    np.testing.assert_allclose(again.accelerations, cold.accelerations, atol=1e-9)
    assert np.all(np.abs(again.accelerations[~stepper.fixed]) < 1e-9)  # it sticks: at rest


@pytest.mark.parametrize(
    ("discs", "held_first_frame"), [(12, True), (20, False), (40, True), (60, True)]
)
def test_a_frictional_pile_keeps_coulombs_law_at_every_step(discs, held_first_frame, monkeypatch):
    """Packed piles with mu = 0.5 at rest: forces in the cones, no overlap, and they stay at rest.
    The 12-disc pile's first frame ends Lemke's path with the covering vector of ones and its
    perturbed retries on rays, and the held linear program solves it
    (runtime.solve.friction_lcp.solve_held, counted here) before other covering vectors are
    tried. The first frames of the 40- and 60-disc piles (432 and 660 unknowns) are tried held
    first (settings.HELD_FIRST; the 60-disc pile's Lemke paths all fail, 4 of 25 cycle). The
    20-disc pile is solved by Lemke's method and bases."""
    held, original = [], friction.solve_held

    def counted(*args):
        held.append(original(*args))
        return held[-1]

    monkeypatch.setattr(friction, "solve_held", counted)
    run = runtime.simulate(_frictional_pile(discs, 0.5), duration=0.05, dt=1e-3)
    for f_n, f_t in zip(run.contact_forces, run.friction_forces, strict=True):
        assert np.all(f_n >= 0.0)
        # (+ rounding: contacts without normal force in the 40-disc pile carry |f_t| ~3e-12 N
        # beside normal forces of ~600 N, 25 eps of them, since Lemke's ends are checked)
        assert np.all(np.abs(f_t) <= 0.5 * f_n * (1 + 1e-9) + 1e-13 * max(f_n.max(), 1.0))
    assert run.max_penetration < 1e-9
    assert (True in held) == held_first_frame
    assert False not in held
    assert np.all(np.abs(run.velocities[-1]) < 1e-6)  # it stays at rest


@pytest.mark.parametrize(("discs", "mu", "seed"), [(12, 0.5, 0), (12, 0.5, 1), (8, 0.3, 2)])
def test_the_warm_start_without_the_matrix_is_the_matrixs(discs, mu, seed):
    """solve_island tries a remembered basis without forming the LCP's matrix (n^2 entries,
    1.9 % of them non-zero in a packed 100-disc pile's island): M_BB entry by entry, w = M z + q
    from the accelerations, each row's scale bounded term by term. On a packed pile's island,
    its contacts sticking or, at random, sliding: every entry is island_lcp's to the bit, w is
    M z + q to rounding, the scales bound |q| + |M| e, and on Lemke's basis the z is
    from_basis's to the bit."""
    world = runtime.World(_frictional_pile(discs, mu))
    world.step(1e-3)
    stepper, rng = world.stepper, np.random.default_rng(seed)
    contacts = world.contacts
    labels = np.zeros(len(contacts), dtype=int)  # one island: the packed pile
    problem = stepper.forces.problem(contacts, labels, stepper.collision.keys(contacts))
    rows = stepper.evaluator.rows(problem.contacts, world.poses, world.velocities, False)
    m = len(rows.mu)
    slide = np.where(rng.random(m) < 0.3 * seed, rng.choice([-1.0, 1.0], m), 0.0)
    ends = np.ascontiguousarray(np.column_stack([rows.body1, rows.body2]))
    f = stepper.forces
    args = (rows.jacobian, rows.tangent_jacobian, ends, rows.bias, rows.tangent_bias, rows.mu,
            slide, f.inverse_mass, f.fixed, f.free_acceleration)  # fmt: skip
    M, q, stick = friction_lcp.island_lcp(*args, np.zeros(m))
    island = (*args[:3], friction_lcp._folded(rows.jacobian, rows.tangent_jacobian, rows.mu, slide),
              stick, rows.mu, f.inverse_mass, f.fixed)  # fmt: skip
    n = q.size
    np.testing.assert_array_equal(friction_lcp._basis_matrix(island, np.arange(n)), M)
    some = np.flatnonzero(rng.random(n) < 0.4)
    np.testing.assert_array_equal(friction_lcp._basis_matrix(island, some), M[np.ix_(some, some)])
    z = np.abs(rng.normal(size=n)) * (rng.random(n) < 0.5)
    w = friction_lcp._residuals(island, rows.bias, rows.tangent_bias, f.free_acceleration, z)
    np.testing.assert_allclose(w, M @ z + q, rtol=0, atol=1e-14 * np.abs(M @ z + q).max())
    e = np.abs(rng.normal(size=n))
    k = m
    scales = friction_lcp._scales(island, q[:k], q[k : k + stick.size], e)
    exact = np.abs(q) + np.abs(M) @ e
    assert np.all(scales >= exact * (1 - 1e-12)) and np.all(scales <= 4 * exact)
    z, basic = _lemke(M, q)
    by_matrix, without = np.zeros(n), np.zeros(n)
    assert friction_lcp.from_basis(M, q, basic, by_matrix)
    assert friction_lcp._warm(island, rows.bias, rows.tangent_bias, f.free_acceleration,
                              q[:k].copy(), basic, without)  # fmt: skip
    np.testing.assert_array_equal(without, by_matrix)
    refused = 0
    for i in range(n):  # another basis: refused, unless it solves the LCP too (degenerate)
        wrong, z = basic.copy(), np.zeros(n)
        wrong[i] = not wrong[i]
        if friction_lcp._warm(island, rows.bias, rows.tangent_bias, f.free_acceleration,
                              q[:k].copy(), wrong, z):  # fmt: skip
            w = M @ z + q
            assert z.min() >= 0.0 and w.min() >= -1e-9 * exact.max()
            assert np.abs(z * w).max() <= 1e-9 * exact.max() * max(z.max(), 1.0)
        else:
            refused += 1
    assert refused > n // 2


def _island(name: str) -> dict:
    return dict(np.load(Path(__file__).parent / "data" / name))


_INPUTS = "jac tangent_jac ends bias tangent_bias mu slide inv_mass fixed free_acc".split()


def _solved(island: dict, solve):
    """``solve`` (friction_lcp.solve_held, or solve_island less its last two arguments) on a
    copy of the island: (status, normal, tangent, slack, acc)."""
    k = island["mu"].size
    normal, tangent, slack, a_t, rates = (np.zeros(k) for _ in range(5))
    acc = island["free_acc"].copy()
    args = [island[name].copy() for name in _INPUTS] + [normal, tangent, slack, a_t, rates, acc]
    status = solve(*args, island["flags"].copy())
    return status, normal, tangent, slack, acc


def _island_solve(hold_first: bool):
    return lambda *args: friction_lcp.solve_island(*args, hold_first, settings.LEMKE_COVERS)


def _rates(island: dict, rows: np.ndarray, acc: np.ndarray) -> np.ndarray:
    """J acc over each row's two bodies (numpy, apart from friction_lcp)."""
    ends = island["ends"]
    return np.einsum("kc,kc->k", rows[:, :3], acc[ends[:, 0]]) + np.einsum(
        "kc,kc->k", rows[:, 3:], acc[ends[:, 1]]
    )


def test_an_island_that_can_be_held_is_held_not_moved():
    """An island of 19 sticking contacts (13 discs) of the falling 30-disc pile with mu = 1 at a
    frame in its first second: its friction LCP has a solution (Lemke's method, or the
    remembered basis, finds it) in which a contact slips at ~2 m/s^2, and one with every
    contact held, d'' = 0 and a_t = 0 with forces in the cones. The held one is taken
    (runtime.solve.friction_lcp._moves: a body its contacts can hold stays at rest)."""
    island = _island("friction_held_island.npz")
    mu = island["mu"]
    status, normal, tangent, slack, acc = _solved(island, _island_solve(hold_first=False))
    assert status == lemke.SOLVED
    moving = _rates(island, island["jac"], acc) + island["bias"]
    assert moving.max() > 1.0 or slack.max() > 1.0  # it opens or slips a contact
    assert _solved(island, _island_solve(hold_first=True))[0] == friction_lcp.MOVES
    held, normal, tangent, slack, acc = _solved(island, friction_lcp.solve_held)
    assert held
    scale = (
        np.abs(island["bias"]).max()
        + np.abs(_rates(island, island["jac"], island["free_acc"])).max()
    )
    np.testing.assert_allclose(
        _rates(island, island["jac"], acc) + island["bias"], 0.0, atol=1e-9 * scale
    )
    a_t = _rates(island, island["tangent_jac"], acc) + island["tangent_bias"]
    np.testing.assert_allclose(a_t, 0.0, atol=1e-9 * scale)
    assert normal.min() >= 0.0
    assert np.all(np.abs(tangent) <= mu * normal * (1 + 1e-9) + 1e-13 * normal.max())
