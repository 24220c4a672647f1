"""Tests of runtime/lcp.py, each against an independent reference.

* The six myphysicslab pile matrices (shared data): the LCP conditions with the tolerance the
  data carries, and agreement of the acceleration a with projected Gauss-Seidel.
* Random PSD problems A = J J^T (J random, often rank deficient) against brute-force
  enumeration of all 2^n clamped sets: for PSD A the acceleration a is unique (and f too when
  A is definite), and no valid set means the solver must raise.
* A hypothesis property test, physical examples with redundant contacts, infeasible problems,
  and the O(k^2) Cholesky add/delete updates against a fresh factorization.
"""

from __future__ import annotations

import itertools
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from runtime.solve import lcp


def _find_cases() -> Path | None:
    """The shared data sits next to the repository: <repo>/../shared/data/lcp_cases.json."""
    here = Path(__file__).resolve()
    for parent in here.parents:
        for candidate in (parent / "shared" / "data", parent / ".." / "shared" / "data"):
            if (candidate / "lcp_cases.json").is_file():
                return (candidate / "lcp_cases.json").resolve()
    return None


CASES_FILE = _find_cases()
CASES = json.loads(CASES_FILE.read_text())["cases"] if CASES_FILE else []
needs_cases = pytest.mark.skipif(
    CASES_FILE is None, reason="shared/data/lcp_cases.json not found above the repository"
)


def _case(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    case = next(c for c in CASES if c["name"] == name)
    joint = np.zeros(case["n"], bool) if case["joint"] is None else np.array(case["joint"], bool)
    return np.array(case["A"]), np.array(case["b"]), joint, float(case["accel_tolerance"])


def _relative_tol(b: np.ndarray, accel_tolerance: float) -> float:
    """The data's absolute bound on |a| as the solver's relative tol, with a 2x margin."""
    return 0.5 * accel_tolerance / np.max(np.abs(b))


def check_lcp(A, b, joint, f, accel_tol: float, force_tol: float) -> None:
    """Assert the LCP conditions; complementarity |f_i a_i| <= accel_tol * max(1, |f|_inf)."""
    a = A @ f + b
    contact = ~joint
    assert np.all(np.isfinite(f))
    assert np.all(f[contact] >= -force_tol)
    assert np.all(a[contact] >= -accel_tol)
    assert np.all(np.abs(a[joint]) <= accel_tol)
    assert np.all(np.abs(a[contact & (f > 0)]) <= accel_tol)
    assert np.max(np.abs(f * a)[contact], initial=0.0) <= accel_tol * max(1.0, np.max(np.abs(f)))


# --- the shared pile cases ---------------------------------------------------------------


@needs_cases
@pytest.mark.parametrize("name", [c["name"] for c in CASES])
def test_shared_case_satisfies_lcp(name: str) -> None:
    A, b, joint, accel_tol = _case(name)
    f = lcp.solve(A, b, joint, tol=_relative_tol(b, accel_tol))
    check_lcp(A, b, joint, f, accel_tol, force_tol=1e-12 * max(1.0, np.max(np.abs(f))))


@needs_cases
@pytest.mark.parametrize("name", [c["name"] for c in CASES])
def test_pgs_agrees_on_accelerations(name: str) -> None:
    """a is unique for PSD A (f is not: the matrices are singular), so compare a only.

    PGS needs 7-582 sweeps here (most for testMatrix22_CF, 44 contacts, rank 36) and
    leaves |a_pgs - a| at about its residual, <= 2.2 x the data's tolerance; bound: 10 x.
    """
    A, b, joint, accel_tol = _case(name)
    tol = _relative_tol(b, accel_tol)
    a = A @ lcp.solve(A, b, joint, tol=tol) + b
    stats: dict[str, float] = {}
    g = lcp.solve_pgs(A, b, joint, tol=2 * tol, iterations=5000, stats=stats)
    assert stats["iterations"] < 5000
    assert np.max(np.abs(A @ g + b - a)) <= 10 * accel_tol


# --- brute force over the 2^n clamped sets ----------------------------------------------


def brute_force(A, b, joint, tol: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """All (f, a) with f solving A_SS f_S = -b_S for a nonsingular A_SS and valid everywhere.

    Any solution reduces to one with a nonsingular A_SS (move along a null vector of A_SS,
    which is also one of A, until a force reaches 0), so this finds one if one exists.
    """
    n = len(b)
    found = []
    for bits in itertools.product((False, True), repeat=n):
        S = np.array(bits, bool)
        f = np.zeros(n)
        if S.any():
            ASS = A[np.ix_(S, S)]
            if np.linalg.cond(ASS) > 1e10:
                continue
            f[S] = np.linalg.solve(ASS, -b[S])
        a = A @ f + b
        if (
            np.all(f[S & ~joint] >= -tol)
            and np.all(a[~S & ~joint] >= -tol)
            and np.all(np.abs(a[~S & joint]) <= tol)
        ):
            found.append((f, a))
    return found


def random_problem(rng: np.random.Generator, n: int, m: int, feasible: bool, joints: bool):
    """A = J J^T with J n x m (rank deficient for m < n); feasible b = w - A g, w >= 0."""
    J = rng.normal(size=(n, m))
    A = J @ J.T
    joint = (rng.random(n) < 0.25) if joints else np.zeros(n, bool)
    if feasible:
        g = np.where(rng.random(n) < 0.5, np.abs(rng.normal(size=n)), 0.0)
        g[joint] = rng.normal(size=joint.sum())
        w = np.where(rng.random(n) < 0.5, np.abs(rng.normal(size=n)), 0.0)
        w[joint] = 0.0
        b = w - A @ g
    else:
        b = rng.normal(size=n)
    return A, b, joint


def pile_problem(rng: np.random.Generator, n: int):
    """A 2-D pile: bodies in layers, each contact lifts a body off one below it (or the floor).

    More contacts than body freedoms (A singular), gravity in b; unlike random b these make
    Baraff's algorithm move contacts between C and NC.
    """
    bodies = max(1, n // int(rng.integers(2, 5)))
    width = max(1, int(np.sqrt(bodies)))
    inv_mass = np.repeat(1.0 / rng.uniform(0.5, 2.0, bodies), 3) * np.tile([1, 1, 4], bodies)
    J = np.zeros((n, 3 * bodies))
    for c in range(n):
        body = c % bodies
        th = rng.normal(0.0, 0.15)
        nx, ny = np.sin(th), np.cos(th)  # normal from the lower body up to this one
        x1, x2 = rng.uniform(-0.5, 0.5, 2)  # contact offsets: (x1, -1/2) here, (x2, 1/2) below
        J[c, 3 * body : 3 * body + 3] = [nx, ny, x1 * ny + 0.5 * nx]
        if body >= width:
            below = body - width + int(rng.integers(-1, 2))
            below = min(max(below, body - body % width - width), body - body % width - 1)
            J[c, 3 * below : 3 * below + 3] -= [nx, ny, x2 * ny - 0.5 * nx]
    gravity = np.zeros(3 * bodies)
    gravity[1::3] = -9.81
    return (J * inv_mass) @ J.T, J @ gravity, np.zeros(n, bool)


@pytest.mark.parametrize("kind", ["random", "pile"])
@pytest.mark.parametrize("seed", range(30))
def test_small_problems_match_brute_force(kind: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 9))
    if kind == "pile":
        A, b, joint = pile_problem(rng, n)
    else:
        m = int(rng.integers(1, n + 3))
        A, b, joint = random_problem(rng, n, m, feasible=seed % 2 == 0, joints=seed % 3 == 0)
    found = brute_force(A, b, joint, tol=1e-9)
    if not found:
        with pytest.raises(lcp.ContactSolverError):
            lcp.solve(A, b, joint)
        return
    stats: dict[str, int] = {}
    f = lcp.solve(A, b, joint, stats=stats)
    a = A @ f + b
    check_lcp(A, b, joint, f, accel_tol=1e-8 * max(1.0, np.max(np.abs(b))), force_tol=1e-12)
    if not joint.any():  # Baraff: a contact once driven stays valid, so <= 1 drive per contact
        assert stats["drives"] <= n
    for _, a_ref in found:  # a is unique for PSD A
        np.testing.assert_allclose(a, a_ref, atol=1e-7 * max(1.0, np.max(np.abs(b))))
    if np.linalg.eigvalsh(A)[0] > 1e-6 * np.max(np.diagonal(A)):  # definite: f unique too
        np.testing.assert_allclose(f, found[0][0], rtol=1e-6, atol=1e-8)


@settings(derandomize=True, max_examples=400, deadline=None)
@given(
    kind=st.sampled_from(["random", "pile"]),
    n=st.integers(1, 30),
    rank_deficit=st.integers(-2, 12),
    seed=st.integers(0, 2**32 - 1),
    joints=st.booleans(),
    a_scale=st.sampled_from([1e-6, 1.0, 1e6]),
    b_scale=st.sampled_from([1e-3, 1.0, 1e4]),
)
def test_property_feasible_problems_are_solved(
    kind, n, rank_deficit, seed, joints, a_scale, b_scale
):
    """Feasible PSD problems at any scale: solved, valid to the relative tolerance."""
    rng = np.random.default_rng(seed)
    if kind == "pile":
        A, b, joint = pile_problem(rng, n)
    else:
        A, b, joint = random_problem(rng, n, max(1, n - rank_deficit), True, joints)
    A, b = a_scale * A, b_scale * b
    stats: dict[str, int] = {}
    f = lcp.solve(A, b, joint, stats=stats)
    check_lcp(A, b, joint, f, 1e-8 * np.max(np.abs(b), initial=0.0), force_tol=0.0)
    if not joint.any():
        assert stats["drives"] <= n


# --- physical examples with redundant contacts ------------------------------------------


def _box_on_floor(xs: list[float]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A 2 x 1 box (mass 2, inertia 1) flat on the floor, contacts under x = xs, gravity g."""
    J = np.array([[0.0, 1.0, x] for x in xs])  # d(gap)/d(x, y, th) of each contact
    Minv = np.diag([0.5, 0.5, 1.0])
    F = np.array([0.0, -2 * 9.81, 0.0])
    return J @ Minv @ J.T, J @ Minv @ F, J, F


@pytest.mark.parametrize("xs", [[-1.0, 0.0, 1.0], [-1.0, 1.0, -1.0, 1.0], [-1, -0.5, 0.25, 1]])
def test_box_flat_on_floor_stays_at_rest(xs: list[float]) -> None:
    """Redundant (singular) floor contacts: the forces must hold the box still."""
    A, b, J, F = _box_on_floor(xs)
    assert np.linalg.matrix_rank(A) == 2 < len(xs)
    f = lcp.solve(A, b)
    assert np.all(f >= 0)
    np.testing.assert_allclose(J.T @ f + F, 0.0, atol=1e-9)  # no net force or torque


def test_disc_in_v_groove() -> None:
    """A unit disc (mass 1, inertia 1/2) between two 45-degree walls: each pushes m g / sqrt 2."""
    normals = np.array([[1.0, 1.0], [-1.0, 1.0]]) / np.sqrt(2)
    J = np.hstack([normals, np.zeros((2, 1))])  # contact normals pass through the centre
    Minv = np.diag([1.0, 1.0, 2.0])
    F = np.array([0.0, -9.81, 0.0])
    f = lcp.solve(J @ Minv @ J.T, J @ Minv @ F)
    np.testing.assert_allclose(f, 9.81 / np.sqrt(2), rtol=1e-12)


def test_trivial_inputs() -> None:
    assert lcp.solve(np.zeros((0, 0)), np.zeros(0)).shape == (0,)
    np.testing.assert_array_equal(lcp.solve(np.eye(2), [1.0, 0.0]), 0.0)  # already valid
    with pytest.raises(ValueError):
        lcp.solve(np.eye(2), [1.0, np.nan])
    with pytest.raises(ValueError):
        lcp.solve([[1.0, 2.0], [0.0, 1.0]], [1.0, 1.0])  # not symmetric


# --- infeasible problems ----------------------------------------------------------------


def test_infeasible_zero_matrix_names_the_row() -> None:
    with pytest.raises(lcp.ContactSolverError, match=r"contact 1 .*infeasible") as info:
        lcp.solve(np.zeros((3, 3)), [1.0, -2.0, 0.5])
    assert info.value.rows == (1,)


def test_infeasible_opposed_contacts_name_both_rows() -> None:
    """a_0 + a_1 = -2 whatever f is (two walls pressing a body from both sides)."""
    with pytest.raises(lcp.ContactSolverError, match="infeasible") as info:
        lcp.solve([[1.0, -1.0], [-1.0, 1.0]], [-1.0, -1.0])
    assert set(info.value.rows) == {0, 1}


def test_inconsistent_joints_raise() -> None:
    with pytest.raises(lcp.ContactSolverError, match=r"joint \d .*infeasible"):
        lcp.solve(np.ones((2, 2)), [1.0, -1.0], joint=[True, True])


def test_pgs_raises_when_it_cannot_converge() -> None:
    with pytest.raises(lcp.ContactSolverError, match="iteration limit"):
        lcp.solve_pgs(np.zeros((2, 2)), [1.0, -1.0], iterations=10)


# --- the incremental Cholesky factor ----------------------------------------------------


def test_factor_updates_match_fresh_cholesky() -> None:
    rng = np.random.default_rng(7)
    J = rng.normal(size=(30, 40))
    factor = lcp._Factor(J @ J.T)
    for step in range(200):
        rows = factor.rows
        if rows and (len(rows) == 30 or rng.random() < 0.4):
            factor.remove(rows[int(rng.integers(len(rows)))])
        else:
            j = int(rng.choice(sorted(set(range(30)) - set(rows))))
            row, pivot = factor.trial(j)
            factor.add(j, row, pivot)
        k = len(factor.rows)
        L = factor.L[:k, :k]
        sub = factor.A[np.ix_(factor.rows, factor.rows)]
        np.testing.assert_allclose(L @ L.T, sub, atol=1e-10 * np.max(np.abs(sub), initial=1))
        assert np.all(np.triu(factor.L, 1) == 0) and np.all(factor.L[k:] == 0), step
