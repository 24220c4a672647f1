"""The compiled assembly and warm-started solve of a small island (runtime.solve.assembly).

island_matrix is A = J M^-1 J^T of the oracle's contact_matrix. The warm-started solve
(solve_with_guess, the first try of every small island at every step) accepts a guessed clamped set only when its forces
satisfy the contact conditions: every force pushes (f >= 0), each clamped row has d'' = 0 and
each free row d'' >= 0. References: the brute-force enumeration and the row violations of
tests/lcp_oracle.py (nothing of runtime.solve), on islands of random bodies and contacts.

Why: a held contact whose free d'' turned positive (a body that should lift off) has
f = -b/A < 0 on the guessed set; accepting that glues the body with a pulling force, which the
engine's scenes barely show (the mutants lcp:guess-one-row-island-pulls and
lcp:guess-single-row-pulls of bench/mutants.py).
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from lcp_oracle import Contact, brute_force, contact_matrix, row_violation

from runtime import settings
from runtime.solve.assembly import SOLVED, island_matrix, solve_with_guess

TOL = settings.LCP_TOL


def _island(rng: np.random.Generator, size: int) -> tuple[np.ndarray, np.ndarray]:
    """(A, b) of `size` contacts between two bodies and the ground, random normals and levers
    (A positive definite: at most 3 rows, generic directions), b of either sign per row."""
    contacts = []
    for _ in range(size):
        body1 = int(rng.integers(2))
        body2 = int(rng.choice([-1, 1 - body1]))
        angle = rng.uniform(0, 2 * np.pi)
        lever1, lever2 = rng.uniform(-0.5, 0.5, 2), rng.uniform(-0.5, 0.5, 2)
        normal = (np.cos(angle), np.sin(angle))
        contacts.append(Contact(body1, body2, normal, tuple(lever1), tuple(lever2)))
    A, _, _ = contact_matrix(rng.uniform(0.5, 3.0, 2), rng.uniform(0.05, 0.5, 2), contacts)
    return np.ascontiguousarray(A), rng.normal(size=size) * 10.0


@pytest.mark.parametrize("seed", range(5))
def test_island_matrix_is_j_m_inverse_j_transposed(seed):
    """Six contacts among three moving bodies and the ground (a fixed body), several on the
    same body and the same side of their contact: the engine's rows give the oracle's A."""
    rng = np.random.default_rng(seed)
    masses, inertias = rng.uniform(0.5, 3.0, 3), rng.uniform(0.05, 0.5, 3)
    contacts = []
    for _ in range(6):
        body1 = int(rng.integers(3))
        body2 = int(rng.choice([-1, *(b for b in range(3) if b != body1)]))
        angle = rng.uniform(0, 2 * np.pi)
        levers = rng.uniform(-0.5, 0.5, (2, 2))
        contacts.append(Contact(body1, body2, (np.cos(angle), np.sin(angle)), *map(tuple, levers)))
    A, J, _ = contact_matrix(masses, inertias, contacts)
    ground = 3  # the engine's fixed body: inverse masses 0
    body1 = np.array([c.body1 for c in contacts])
    body2 = np.array([c.body2 if c.body2 >= 0 else ground for c in contacts])
    jac = np.zeros((len(contacts), 6))
    for k, c in enumerate(contacts):
        jac[k, :3] = J[k, 3 * c.body1 : 3 * c.body1 + 3]
        if c.body2 >= 0:
            jac[k, 3:] = J[k, 3 * c.body2 : 3 * c.body2 + 3]
    inverse = np.zeros((4, 3))
    inverse[:3] = np.column_stack([1 / masses, 1 / masses, 1 / inertias])
    fixed = np.array([False, False, False, True])
    engine = np.empty((6, 6))
    island_matrix(jac, body1, body2, inverse, fixed, 0, 6, engine)
    np.testing.assert_allclose(engine, A, rtol=1e-12, atol=1e-12 * np.max(np.abs(A)))


def _guessed(A: np.ndarray, b: np.ndarray, guess: np.ndarray) -> tuple[bool, np.ndarray]:
    f = np.full(len(b), np.nan)
    return solve_with_guess(A, b.copy(), len(b), guess.copy(), TOL, f) == SOLVED, f


@pytest.mark.parametrize("size", [1, 2, 3])
def test_a_guess_is_accepted_only_with_forces_that_push_and_rows_that_hold(size):
    rng = np.random.default_rng(size)
    accepted = rejected = 0
    for _ in range(60):
        A, b = _island(rng, size)
        (exact, _), *others = brute_force(A, b, np.zeros(size, bool))
        assert not others  # A is positive definite: one solution
        clamped = exact > 0
        for bits in itertools.product((False, True), repeat=size):
            guess = np.array(bits)
            ok, f = _guessed(A, b, guess)
            if not ok:
                rejected += 1
                assert not np.array_equal(guess, clamped), (A, b, guess)
                continue
            accepted += 1
            assert np.all(f >= 0.0), f"a pulling force accepted: f = {f}, b = {b}"
            violation, scale, unit = row_violation(A, b, np.zeros(size, bool), f)
            assert np.all(violation <= 10 * TOL * scale + 1e-12 * unit)
            np.testing.assert_allclose(f, exact, rtol=1e-9, atol=1e-12 * np.max(np.abs(b)))
    assert accepted and rejected  # both answers were reached


@pytest.mark.parametrize("size", [1, 2, 3])
def test_a_held_contact_that_should_lift_off_is_refused(size):
    """Only contact 0 guessed clamped, its free d'' positive (b_0 > 0: it separates without a
    force): its force would be -b_0/A_00 < 0, so the guess must be refused."""
    rng = np.random.default_rng(10 + size)
    for _ in range(20):
        A, b = _island(rng, size)
        b[0] = abs(b[0]) + 1.0
        guess = np.zeros(size, bool)
        guess[0] = True
        ok, f = _guessed(A, b, guess)
        assert not ok, f"f = {f} accepted with b_0 = {b[0]} > 0"
