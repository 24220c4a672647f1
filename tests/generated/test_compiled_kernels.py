"""The compiled variant (generated/compiled/<case>.py) computes what the NumPy kernels do.

The engine evaluates contacts through the compiled batch loops; the NumPy kernels are the public
API, checked against the mpmath oracle (test_kernels_vs_oracle.py). So every batch output is
compared with the NumPy kernel on the same random contacts: free and fixed body 2, every case,
and the geometry columns of the contract in generated/__init__.py.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest

import generated
import runtime.compiled  # noqa: F401  (the cache folder, before numba compiles anything)

EPS = float(np.finfo(float).eps)


def _contacts(case: str, rng: np.random.Generator, m: int = 64, n: int = 9):
    columns = generated.GEOMETRY_COLUMNS[case]
    poses = rng.normal(size=(n, 3)) * [1.0, 1.0, 3.0]
    velocities = rng.normal(size=(n, 3)) * 2.0
    body1 = rng.integers(0, n, m)
    body2 = (body1 + 1 + rng.integers(0, n - 1, m)) % n
    geometry = np.full((m, 7), np.nan)  # unused columns stay NaN: a wrong column shows
    for column in columns.values():
        geometry[:, column] = rng.normal(size=m)
    if "nx2" in columns:
        a = rng.uniform(-np.pi, np.pi, m)
        geometry[:, columns["nx2"]], geometry[:, columns["ny2"]] = np.cos(a), np.sin(a)
    if "r1" in columns:
        geometry[:, columns["r1"]] = rng.uniform(0.05, 2.0, m)
    if "r2" in columns:
        geometry[:, columns["r2"]] = rng.uniform(0.05, 2.0, m) * rng.choice([-1.0, 1.0], m)
    static2 = rng.random(m) < 0.5
    return poses, velocities, body1, body2, geometry, static2


def _numpy_values(case, poses, velocities, body1, body2, geometry):
    values = {}
    for digit, bodies in (("1", body1), ("2", body2)):
        for c, name in enumerate(("x", "y", "th")):
            values[name + digit] = poses[bodies, c]
        for c, name in enumerate(("vx", "vy", "w")):
            values[name + digit] = velocities[bodies, c]
    for name, column in generated.GEOMETRY_COLUMNS[case].items():
        values[name] = geometry[:, column]
    return values


@pytest.mark.parametrize("case", generated.CASES)
def test_batch_loops_equal_the_numpy_kernels(case):
    numpy_module = importlib.import_module(f"generated.{case}")
    compiled = importlib.import_module(f"generated.compiled.{case}")
    rng = np.random.default_rng(20261201)
    poses, velocities, body1, body2, geometry, static2 = _contacts(case, rng)
    m = len(body1)
    members = np.arange(m)[::-1].copy()  # any order of members
    gap, gap_velocity, bias = np.zeros(m), np.zeros(m), np.zeros(m)
    jacobian = np.full((m, 6), np.nan)
    compiled.batch_gap(poses, body1, body2, geometry, members, gap)
    compiled.batch_gap_velocity(
        poses, velocities, body1, body2, geometry, static2, members, gap_velocity
    )
    compiled.batch_rows(poses, velocities, body1, body2, geometry, static2, members, jacobian, bias)

    values = _numpy_values(case, poses, velocities, body1, body2, geometry)

    def call(name):
        f = getattr(numpy_module, name)
        return f(**{a: values[a] for a in numpy_module.ARGUMENTS[name]})

    free_jacobian = np.column_stack(call("jacobian"))
    fixed_jacobian = np.column_stack([*call("jacobian_static2"), *np.zeros((3, m))])
    expected = {
        "gap": call("gap"),
        "gap_velocity": np.where(static2, call("gap_velocity_static2"), call("gap_velocity")),
        "bias": np.where(static2, call("bias_static2"), call("bias")),
        "jacobian": np.where(static2[:, None], fixed_jacobian, free_jacobian),
    }
    got = {"gap": gap, "gap_velocity": gap_velocity, "bias": bias, "jacobian": jacobian}
    for name, want in expected.items():
        scale = np.abs(want) + 1.0
        worst = float(np.max(np.abs(got[name] - want) / scale))
        assert worst <= 4 * EPS, f"{case}.{name}: {worst:.3g} relative"
    assert np.all(jacobian[static2, 3:] == 0.0)


def test_the_contract_lists_every_geometry_argument_once():
    """Each case's geometry arguments (from the NumPy kernels) have a column; body 1's feature
    uses columns 0-2 and body 2's 3-6."""
    for case in generated.CASES:
        module = importlib.import_module(f"generated.{case}")
        used = set().union(*module.ARGUMENTS.values())
        geometry = {
            a for a in used if a[:-1] not in ("x", "y", "th", "vx", "vy", "w", "ax", "ay", "al")
        }
        columns = generated.GEOMETRY_COLUMNS[case]
        assert set(columns) == geometry
        assert all((c < 3) == name.endswith("1") for name, c in columns.items())
        assert len(set(columns.values())) == len(columns)
    assert sorted(generated.CASE_ID.values()) == list(range(len(generated.CASE_ID)))


@pytest.mark.parametrize("case", ["circle_circle", "vertex_circle"])
def test_coincident_centres_give_nan_rates_as_the_numpy_kernels(case):
    """d' of a contact whose two circle centres coincide (or a vertex on the circle's centre) is
    0/0: NaN from both variants, not a ZeroDivisionError from the compiled one (numba's 'numpy'
    error model), so the engine can treat it (runtime.step.events takes the secant instead)."""
    numpy_module = importlib.import_module(f"generated.{case}")
    compiled = importlib.import_module(f"generated.compiled.{case}")
    columns = generated.GEOMETRY_COLUMNS[case]
    poses = np.array([[0.5, -0.25, 0.0], [0.5, -0.25, 0.0]])  # both bodies' origins together
    velocities = np.array([[1.0, 2.0, 0.0], [0.0, 0.0, 0.0]])
    geometry = np.zeros((1, 7))
    if "r1" in columns:
        geometry[0, columns["r1"]] = 0.1
    geometry[0, columns["r2"]] = 0.1
    out = np.zeros(1)
    args = (poses, velocities, np.array([0]), np.array([1]), geometry)
    compiled.batch_gap_velocity(*args, np.array([False]), np.array([0]), out)
    values = _numpy_values(case, *args)
    with np.errstate(all="ignore"):
        expected = numpy_module.gap_velocity(
            **{k: values[k] for k in numpy_module.ARGUMENTS["gap_velocity"]}
        )
    assert np.isnan(out[0]) and np.isnan(expected)
