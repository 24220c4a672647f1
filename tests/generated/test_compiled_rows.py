"""The compiled friction and joint modules compute what their NumPy kernels do, the contract in
generated/__init__.py describes them, and a frictionless scene's kernels import no friction module.

The NumPy kernels are checked against the mpmath oracle (test_rows_vs_oracle.py); here every batch
output is compared with them on random contacts or joints: body 2 moving, fixed (static2) and, for
a joint, the world (body2 < 0: pose 0, at rest).
"""

from __future__ import annotations

import importlib
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from test_compiled_kernels import EPS, _contacts, _numpy_values

import generated
import runtime.compiled  # noqa: F401  (the cache folder, before numba compiles anything)

ROOT = Path(__file__).resolve().parents[2]


def _close(got, want) -> float:
    return float(np.max(np.abs(got - want) / (np.abs(want) + 1.0)))


@pytest.mark.parametrize("case", generated.FRICTION_CASES)
def test_friction_batch_loops_equal_the_numpy_kernels(case):
    numpy_module = importlib.import_module(f"generated.{case}_friction")
    compiled = importlib.import_module(f"generated.compiled.{case}_friction")
    poses, velocities, body1, body2, geometry, static2 = _contacts(case, np.random.default_rng(7))
    m = len(body1)
    members = np.arange(m)[::-1].copy()
    rate, bias, jacobian = np.zeros(m), np.zeros(m), np.full((m, 6), np.nan)
    args = (poses, velocities, body1, body2, geometry, static2, members)
    compiled.batch_tangent_all(*args, rate, jacobian, bias)
    values = _numpy_values(case, poses, velocities, body1, body2, geometry)

    def call(name):
        f = getattr(numpy_module, name)
        return f(**{a: values[a] for a in numpy_module.ARGUMENTS[name]})

    def either(name):
        return np.where(static2, call(name + "_static2"), call(name))

    fixed = np.column_stack([*call("tangent_jacobian_static2"), *np.zeros((3, m))])
    free = np.column_stack(call("tangent_jacobian"))
    assert _close(rate, either("tangent_velocity")) <= 4 * EPS
    assert _close(bias, either("tangent_bias")) <= 4 * EPS
    assert _close(jacobian, np.where(static2[:, None], fixed, free)) <= 4 * EPS
    assert np.all(jacobian[static2, 3:] == 0.0)


def _joints(joint: str, rng: np.random.Generator, m: int = 48, n: int = 7):
    columns = generated.JOINT_GEOMETRY_COLUMNS[joint]
    poses = rng.normal(size=(n, 3)) * [1.0, 1.0, 3.0]
    velocities = rng.normal(size=(n, 3)) * 2.0
    body1 = rng.integers(0, n, m)
    body2 = (body1 + 1 + rng.integers(0, n - 1, m)) % n
    body2[rng.random(m) < 0.25] = -1  # the world
    geometry = np.full((m, 7), np.nan)
    for column in columns.values():
        geometry[:, column] = rng.normal(size=m)
    static2 = rng.random(m) < 0.25
    return poses, velocities, body1, body2, geometry, static2


@pytest.mark.parametrize("joint", generated.JOINTS)
def test_joint_batch_loops_equal_the_numpy_kernels(joint):
    numpy_module = importlib.import_module(f"generated.{joint}")
    compiled = importlib.import_module(f"generated.compiled.{joint}")
    rows = generated.JOINT_ROWS[joint]
    poses, velocities, body1, body2, geometry, static2 = _joints(joint, np.random.default_rng(11))
    m = len(body1)
    members = np.arange(m)
    gap, rate, bias = np.zeros((m, rows)), np.zeros((m, rows)), np.zeros((m, rows))
    jacobian = np.full((m, rows, 6), np.nan)
    args = (poses, velocities, body1, body2, geometry, static2, members)
    compiled.batch_all(*args, gap, rate, jacobian, bias)
    # the world as body 2: pose 0 and at rest, the *_static2 kernels
    world = body2 < 0
    values = {}
    for digit, bodies in (("1", body1), ("2", body2)):
        for c, name in enumerate(("x", "y", "th")):
            values[name + digit] = np.where(bodies < 0, 0.0, poses[bodies, c])
        for c, name in enumerate(("vx", "vy", "w")):
            values[name + digit] = np.where(bodies < 0, 0.0, velocities[bodies, c])
    for name, column in generated.JOINT_GEOMETRY_COLUMNS[joint].items():
        values[name] = geometry[:, column]
    fixed2 = static2 | world

    def call(name):
        f = getattr(numpy_module, name)
        out = f(**{a: values[a] for a in numpy_module.ARGUMENTS[name]})
        out = out if isinstance(out, tuple) else (out,)
        return np.column_stack(np.broadcast_arrays(*out, values["th1"]))[:, :-1]  # constants

    def either(name):
        return np.where(fixed2[:, None], call(name + "_static2"), call(name))

    free = call("jacobian").reshape(m, rows, 6)
    fixed = np.concatenate(
        [call("jacobian_static2").reshape(m, rows, 3), np.zeros((m, rows, 3))], 2
    )
    assert _close(gap, call("gap")) <= 4 * EPS
    assert _close(rate, either("gap_velocity")) <= 4 * EPS
    assert _close(bias, either("bias")) <= 4 * EPS
    assert _close(jacobian, np.where(fixed2[:, None, None], fixed, free)) <= 4 * EPS


def test_the_contract_lists_the_joints_and_the_friction_modules():
    """The joints' geometry columns are every geometry argument of their kernels (anchor 1 from
    column 0, anchor 2 from 3, the length after); friction kernels take only their case's
    geometry; the contact cases keep their ids."""
    assert generated.CASE_ID == {
        "vertex_edge": 0,
        "vertex_circle": 1,
        "circle_edge": 2,
        "circle_circle": 3,
    }
    assert sorted(generated.JOINT_ID.values()) == list(range(len(generated.JOINT_ID)))
    motion = ("x", "y", "th", "vx", "vy", "w", "ax", "ay", "al")
    for joint in generated.JOINTS:
        used = set().union(*importlib.import_module(f"generated.{joint}").ARGUMENTS.values())
        columns = generated.JOINT_GEOMETRY_COLUMNS[joint]
        assert set(columns) == {a for a in used if a[:-1] not in motion}
        assert columns["px1"] == 0 and columns["py1"] == 1
        assert columns["px2"] == 3 and columns["py2"] == 4
    assert generated.JOINT_ROWS == {"pin_joint": 2, "distance_joint": 1}
    for case in generated.FRICTION_CASES:
        used = set().union(
            *importlib.import_module(f"generated.{case}_friction").ARGUMENTS.values()
        )
        geometry = {a for a in used if a[:-1] not in motion}
        assert geometry <= set(generated.GEOMETRY_COLUMNS[case])


def test_normal_kernels_import_no_friction_module():
    """A scene with every friction coefficient 0 loads only the normal kernels: importing every
    contact case (NumPy and compiled) imports no friction or joint module."""
    code = (
        "import importlib, json, sys, generated\n"
        "for c in generated.CASES:\n"
        "    importlib.import_module('generated.' + c)\n"
        "    importlib.import_module('generated.compiled.' + c)\n"
        "print(json.dumps(sorted(m for m in sys.modules if m.startswith('generated'))))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    loaded = json.loads(done.stdout)
    assert not [m for m in loaded if m.endswith("_friction") or m.endswith("_joint")], loaded
    assert "generated.compiled.circle_circle" in loaded
