"""The engine's warm-started island solve (runtime.solve.assembly.solve_with_guess, the first
try of every small island at every step) accepts a guessed clamped set only when its forces
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
from runtime.solve.assembly import solve_with_guess

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


def _guessed(A: np.ndarray, b: np.ndarray, guess: np.ndarray) -> tuple[bool, np.ndarray]:
    f = np.full(len(b), np.nan)
    return bool(solve_with_guess(A, b.copy(), len(b), guess.copy(), TOL, f)), f


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
