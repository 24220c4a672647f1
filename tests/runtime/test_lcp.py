"""runtime.solve.lcp on known problems, each against an independent reference.

* The six myphysicslab pile matrices (shared data): the LCP conditions within the data's own
  tolerance, and the accelerations a = A f + b against projected Gauss-Seidel.
* The cases of issue 11, with exact answers: a nearly opposed pair (closed form in fractions),
  a 2e11 kg disc on a floor (f = m g), a stack of mass ratio 1e9 (each contact carries the
  weight above it), a disc in a slot exactly its width and a wedged disc (redundant rows: the
  least-norm forces in closed form), a box with an off-centre load (least norm with a contact
  at zero).
* Small random problems against brute force over all clamped sets; units (scaling A and b
  scales f exactly); bad input and infeasible problems (the error names rows and residual).
"""

from __future__ import annotations

import json
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from lcp_oracle import Contact, G, brute_force, contact_matrix, gravity_b, row_violation

from runtime import settings
from runtime.solve import lcp, lcp_sparse

TOL = settings.LCP_TOL


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


def check_lcp(A, b, joint, f, accel_tol: float) -> None:
    """The LCP conditions with an absolute bound on |a| (the shared data's tolerance)."""
    a = A @ f + b
    contact = ~joint
    assert np.all(np.isfinite(f))
    assert np.all(f[contact] >= 0.0)
    assert np.all(a[contact] >= -accel_tol)
    assert np.all(np.abs(a[joint]) <= accel_tol)
    assert np.all(np.abs(a[contact & (f > 0)]) <= accel_tol)


def assert_valid(A, b, joint, f, factor: float = 4.0) -> None:
    """The solver's own contract: each row within LCP_TOL of its componentwise scale (plus
    the rounding floor, LCP_FLOOR of the largest term)."""
    violation, scale, unit = row_violation(np.asarray(A, float), np.asarray(b, float), joint, f)
    assert np.all(violation <= factor * (TOL * scale + settings.LCP_FLOOR * unit))


# --- the shared pile cases ---------------------------------------------------------------


def _data_tol(b: np.ndarray, accel_tol: float) -> float:
    """The data's absolute bound on |a| as a relative tol (each row's scale is >= |b_i|)."""
    return 0.5 * accel_tol / np.max(np.abs(b))


@needs_cases
@pytest.mark.parametrize("name", [c["name"] for c in CASES])
def test_shared_case_within_its_tolerance(name: str) -> None:
    """Every case within the data's tolerance; all but testMatrix26_CF also within the default
    LCP_TOL (see test_shared_case_with_inconsistent_joints)."""
    A, b, joint, accel_tol = _case(name)
    f = lcp.solve(A, b, joint, tol=_data_tol(b, accel_tol))
    check_lcp(A, b, joint, f, accel_tol)
    if name != "testMatrix26_CF":
        f = lcp.solve(A, b, joint)
        check_lcp(A, b, joint, f, accel_tol)
        assert_valid(A, b, joint, f)


@needs_cases
def test_shared_case_with_inconsistent_joints() -> None:
    """testMatrix26_CF: four joint rows of rank 3 whose b is 5.6e-7 m/s^2 off their range
    (the reference engine's own joint error; its test allows 2e-6): infeasible at the default
    1e-9 relative tolerance, and the error names the joints and the residual."""
    A, b, joint, _ = _case("testMatrix26_CF")
    assert joint.all() and np.linalg.matrix_rank(A) == 3
    with pytest.raises(lcp.ContactSolverError, match=r"joint 0, .*infeasible.*residual 5.\d+e-07"):
        lcp.solve(A, b, joint)


@needs_cases
@pytest.mark.parametrize("name", [c["name"] for c in CASES])
def test_shared_case_by_the_sparse_path(name: str) -> None:
    """The sparse path (envelope factor, block pivoting) on the same matrices, forced: valid,
    and the dense path's forces (its accelerations where the joints make the data ambiguous)."""
    A, b, joint, accel_tol = _case(name)
    tol = _data_tol(b, accel_tol)
    counts = np.zeros(8, np.int64)
    f, _, status, _ = lcp_sparse.solve_sparse(
        lcp_sparse.sp.csr_array(A), b, joint, np.zeros(len(b), bool), tol, counts
    )
    assert status == 0
    check_lcp(A, b, joint, f, accel_tol)
    dense = lcp.solve(A, b, joint, tol=tol)
    if joint.any():  # b is off the joints' range by 1e-10 (25) to 1e-6 (26): a agrees to that
        np.testing.assert_allclose(A @ f + b, A @ dense + b, rtol=0, atol=accel_tol)
    else:  # the same least-norm forces
        np.testing.assert_allclose(f, dense, atol=1e-9 * max(1, np.max(np.abs(f))))


@needs_cases
@pytest.mark.parametrize("name", [c["name"] for c in CASES])
def test_pgs_agrees_on_accelerations(name: str) -> None:
    """a is unique for PSD A (f is not: the matrices are singular), so compare a only.
    PGS converges to about its own tolerance; bound: 10 x the data's tolerance."""
    A, b, joint, accel_tol = _case(name)
    a = A @ lcp.solve(A, b, joint, tol=_data_tol(b, accel_tol)) + b
    stats: dict[str, float] = {}
    tol = 0.25 * accel_tol / np.max(np.abs(b))
    g = lcp.solve_pgs(A, b, joint, tol=tol, iterations=5000, stats=stats)
    assert stats["iterations"] < 5000
    assert np.max(np.abs(A @ g + b - a)) <= 10 * accel_tol


# --- the cases of issue 11 ---------------------------------------------------------------


def test_nearly_opposed_pair() -> None:
    """[[1, -c], [-c, 1]] f = -b with c = 0.99999999997: f = (1, c) 9.05e-7 / (1 - c^2), the
    exact solution of the float data in fractions; cond(A) = 7e10 bounds the error by ~1e-5."""
    c = -0.99999999997
    A, b = np.array([[1.0, c], [c, 1.0]]), np.array([-9.05e-7, 0.0])
    f = lcp.solve(A, b)
    C, B = Fraction(c), Fraction(-9.05e-7)
    exact = np.array([float(-B / (1 - C * C)), float(C * B / (1 - C * C))])
    np.testing.assert_allclose(f, exact, rtol=1e-5)
    assert_valid(A, b, np.zeros(2, bool), f)


@pytest.mark.parametrize("mass", [2e11, 1.0, 1e-6])
def test_disc_on_a_floor_at_any_mass(mass: float) -> None:
    """One contact, A = 1/m: f = m g whatever the mass (the old path compared A with |b|)."""
    f = lcp.solve([[1.0 / mass]], [-G])
    assert f[0] == pytest.approx(mass * G, rel=1e-15)
    f, clamped = lcp.solve_warm(np.array([[1.0 / mass]]), np.array([-G]))
    assert f[0] == pytest.approx(mass * G, rel=1e-15) and clamped[0]


@pytest.mark.parametrize("masses", [[1.0, 1e9, 1.0, 1e9], [1e9, 1.0, 1e9, 1.0], [1, 1e7, 1e-2]])
def test_stack_of_large_mass_ratio(masses: list[float]) -> None:
    """Discs stacked on the floor: contact k carries the weight of discs k.. above it. The
    forces are determined only to cond(A) eps (4e9 x 2.2e-16 for ratio 1e9: a light disc
    between heavy ones barely feels a common shift of the forces around it), the gap
    accelerations a to rounding: |a_i| <= 16 eps (sum_j |A_ij f_j| + |b_i|), 6e7 x tighter
    than LCP_TOL (the light disc's acceleration: a few ulp of 2e10 N, 1e-6 m/s^2)."""
    n = len(masses)
    contacts = [Contact(0, -1, (0.0, 1.0), (0.0, -0.5))]
    contacts += [Contact(k, k - 1, (0.0, 1.0), (0.0, -0.5), (0.0, 0.5)) for k in range(1, n)]
    A, J, inverse = contact_matrix(masses, [0.1 * m for m in masses], contacts)
    b = gravity_b(J, inverse)
    f = lcp.solve(A, b)
    exact = G * np.cumsum(np.asarray(masses)[::-1])[::-1]
    np.testing.assert_allclose(f, exact, rtol=4 * np.linalg.cond(A) * np.finfo(float).eps)
    violation, scale, _ = row_violation(A, b, np.zeros(n, bool), f)
    assert np.all(violation <= 16 * np.finfo(float).eps * scale)


@pytest.mark.parametrize("sideways", [0.0, 1.5])
def test_disc_in_a_slot_exactly_its_width(sideways: float) -> None:
    """A disc (m = 2) touching the floor and both walls of a slot its width: the wall rows are
    opposed (A singular). Gravity (sideways, -g) presses it to the left wall only: the least-norm
    forces are m g on the floor, m * sideways on that wall and 0 on the other."""
    m = 2.0
    contacts = [
        Contact(0, -1, (0.0, 1.0), (0.0, -1.0)),
        Contact(0, -1, (1.0, 0.0), (-1.0, 0.0)),
        Contact(0, -1, (-1.0, 0.0), (1.0, 0.0)),
    ]
    A, J, inverse = contact_matrix([m], [1.0], contacts)
    b = gravity_b(J, inverse, (-sideways, -G))
    assert np.linalg.matrix_rank(A) == 2
    f = lcp.solve(A, b)
    np.testing.assert_allclose(f, [m * G, m * sideways, 0.0], rtol=1e-12, atol=1e-12)


def test_wedged_disc_takes_the_least_norm_forces() -> None:
    """A disc in a 90-degree V that also touches a floor at its bottom: three contacts through
    the centre, rank 2. Least norm over N^T f = (0, m g): f = N (N^T N)^-1 (0, m g) =
    m g / 2 (1/sqrt 2, 1/sqrt 2, 1), all positive."""
    m, s = 3.0, np.sqrt(0.5)
    normals = [(s, s), (-s, s), (0.0, 1.0)]
    contacts = [Contact(0, -1, n, (-n[0], -n[1])) for n in normals]
    A, J, inverse = contact_matrix([m], [1.0], contacts)
    f = lcp.solve(A, gravity_b(J, inverse))
    np.testing.assert_allclose(f, m * G / 2 * np.array([s, s, 1.0]), rtol=1e-13)


def test_box_with_off_centre_load_takes_the_least_norm_forces() -> None:
    """A box (W = m g) on floor contacts at x = -1, 0, 1 with its centre of mass at x = 0.9:
    equilibrium leaves one free parameter; the least-norm forces put 0 at x = -1 (the unbounded
    least-squares answer would pull there), 0.1 W at 0 and 0.9 W at 1 (KKT checked by hand:
    the multiplier row u = 0.1 W + 0.8 W x is -0.7 W <= 0 at x = -1)."""
    m, xc = 2.0, 0.9
    contacts = [Contact(0, -1, (0.0, 1.0), (x - xc, -0.5)) for x in (-1.0, 0.0, 1.0)]
    A, J, inverse = contact_matrix([m], [0.4], contacts)
    f = lcp.solve(A, gravity_b(J, inverse))
    np.testing.assert_allclose(f, m * G * np.array([0.0, 0.1, 0.9]), rtol=1e-12, atol=1e-12)


def test_redundant_box_forces_stay_bounded() -> None:
    """Duplicated and collinear floor contacts under a centred box: forces share the weight
    equally by symmetry (least norm), never large opposed pairs."""
    contacts = [Contact(0, -1, (0.0, 1.0), (x, -0.5)) for x in (-1, 1, -1, 1, 0, 0)]
    A, J, inverse = contact_matrix([4.0], [1.0], contacts)
    f = lcp.solve(A, gravity_b(J, inverse))
    np.testing.assert_allclose(f, 4.0 * G / 6, rtol=1e-12)


# --- brute force over the clamped sets ----------------------------------------------------


def _random_problem(rng: np.random.Generator, n: int):
    """A = J J^T with J n x m (rank deficient for m < n), joints sometimes, b random (feasible
    or not: brute force decides)."""
    J = rng.normal(size=(n, int(rng.integers(1, n + 3))))
    joint = rng.random(n) < 0.25 if rng.random() < 0.3 else np.zeros(n, bool)
    if rng.random() < 0.5:
        f0 = np.where(rng.random(n) < 0.5, np.abs(rng.normal(size=n)), 0.0)
        f0[joint] = rng.normal(size=joint.sum())
        a0 = np.where((f0 == 0) & ~joint & (rng.random(n) < 0.5), np.abs(rng.normal(size=n)), 0)
        return J @ J.T, a0 - J @ (J.T @ f0), joint
    return J @ J.T, rng.normal(size=n), joint


@pytest.mark.parametrize("seed", range(40))
def test_small_problems_match_brute_force(seed: int) -> None:
    """Brute force finds every basic solution; none means the solver must raise; else a is
    the brute-force a (unique for PSD A), and f too when A is definite."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 8))
    A, b, joint = _random_problem(rng, n)
    found = brute_force(A, b, joint, tol=1e-9)
    if not found:
        with pytest.raises(lcp.ContactSolverError, match="infeasible"):
            lcp.solve(A, b, joint)
        return
    f = lcp.solve(A, b, joint)
    assert_valid(A, b, joint, f)
    for _, a_ref in found:
        np.testing.assert_allclose(A @ f + b, a_ref, atol=1e-7 * max(1.0, np.max(np.abs(b))))
    if np.linalg.eigvalsh(A)[0] > 1e-6 * np.max(np.diagonal(A)):
        np.testing.assert_allclose(f, found[0][0], rtol=1e-6, atol=1e-8)


# --- units, bad input, infeasible problems ------------------------------------------------


@pytest.mark.parametrize(("mass_unit", "accel_unit"), [(1e-12, 1.0), (1e12, 1e-6), (1.0, 1e9)])
def test_units_do_not_change_the_answer(mass_unit: float, accel_unit: float) -> None:
    """A in 1/kg scaled by s, b by t: f scales by t/s (to rounding) -- no threshold in the
    solver depends on the units."""
    contacts = [Contact(0, -1, (0.0, 1.0), (x, -0.5)) for x in (-1, 0.2, 1)]
    contacts += [Contact(1, 0, (0.3, 0.95), (0.1, -0.4), (0.2, 0.5))]
    A, J, inverse = contact_matrix([2.0, 0.5], [0.4, 0.1], contacts)
    b = gravity_b(J, inverse)
    f = lcp.solve(A, b)
    scaled = lcp.solve(A / mass_unit, b * accel_unit)
    np.testing.assert_allclose(scaled, f * accel_unit * mass_unit, rtol=1e-12)


def test_bad_input_is_a_value_error() -> None:
    assert lcp.solve(np.zeros((0, 0)), np.zeros(0)).shape == (0,)
    np.testing.assert_array_equal(lcp.solve(np.eye(2), [1.0, 0.0]), 0.0)  # already valid
    bad = [
        ((np.eye(2), [1.0, np.nan]), "finite"),
        (([[1.0, 2.0], [0.0, 1.0]], [1.0, 1.0]), "symmetric"),
        (([[1.0, 2.0], [2.0, 1.0]], [1.0, 1.0]), "positive semi-definite"),
        (([[-1.0]], [1.0]), "negative diagonal"),
        ((np.eye(3), [1.0, 1.0]), "shape"),
    ]
    for (A, b), words in bad:
        with pytest.raises(ValueError, match=words):
            lcp.solve(A, b)
        with pytest.raises(ValueError, match=words):
            lcp.solve_warm(np.asarray(A, float), np.asarray(b, float))
    with pytest.raises(ValueError, match="joint has 1 entries"):
        lcp.solve(np.eye(2), [1.0, 1.0], joint=[True])
    with pytest.raises(ValueError, match="tol must be a positive"):
        lcp.solve(np.eye(2), [1.0, 1.0], tol=0.0)


def test_infeasible_zero_row_names_the_row() -> None:
    """A row no force moves (A_ii = 0) with b < 0 cannot be held."""
    with pytest.raises(lcp.ContactSolverError, match=r"contact 1 .*infeasible") as info:
        lcp.solve(np.zeros((3, 3)), [1.0, -2.0, 0.5])
    assert info.value.rows == (1,)
    assert "residual 2 m/s^2 at contact 1" in str(info.value)


def test_infeasible_opposed_contacts_name_both_rows_and_the_residual() -> None:
    """a_0 + a_1 = -2 whatever f is (two walls pressing a body from both sides)."""
    with pytest.raises(lcp.ContactSolverError, match="infeasible") as info:
        lcp.solve([[1.0, -1.0], [-1.0, 1.0]], [-1.0, -1.0])
    assert set(info.value.rows) == {0, 1}
    message = str(info.value)
    assert "contact 0, contact 1" in message and "residual 2 m/s^2" in message


def test_inconsistent_joints_raise() -> None:
    with pytest.raises(lcp.ContactSolverError, match=r"joint \d .*infeasible") as info:
        lcp.solve(np.ones((2, 2)), [1.0, -1.0], joint=[True, True])
    assert set(info.value.rows) == {0, 1}


def test_infeasible_island_is_named_by_its_rows_in_the_whole_problem() -> None:
    """Two islands: rows 0-9 a feasible chain, rows 10-11 opposed contacts; the error names
    rows 10 and 11 (not the island's 0 and 1)."""
    A = np.zeros((12, 12))
    A[:10, :10] = np.eye(10) + 0.3 * (np.eye(10, k=1) + np.eye(10, k=-1))
    A[10:, 10:] = [[1.0, -1.0], [-1.0, 1.0]]
    b = np.r_[-np.ones(10), -1.0, -1.0]
    with pytest.raises(lcp.ContactSolverError, match="contact 10, contact 11") as info:
        lcp.solve(A, b)
    assert set(info.value.rows) == {10, 11}


def test_pgs_raises_when_it_cannot_converge() -> None:
    with pytest.raises(lcp.ContactSolverError, match="iteration limit"):
        lcp.solve_pgs(np.zeros((2, 2)), [1.0, -1.0], iterations=10)
