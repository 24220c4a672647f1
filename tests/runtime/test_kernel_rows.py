"""runtime/solve/rows.py: contact rows from the generated kernels.

Why: the engine evaluates every contact through the compiled batch loops, grouped by case; the
grouping must not change a contact's numbers (a run would depend on which other contacts happen
to be active), and they must be the public NumPy kernels' numbers for the same contact (the
geometry columns, the fixed body 2 and the case dispatch are where a mix-up would hide).
"""

from __future__ import annotations

import importlib
from pathlib import Path

import numpy as np
import pytest

import generated
import runtime
from bench.steps import pile_scene
from runtime.solve.rows import RowEvaluator

SCENES = Path(__file__).resolve().parents[2] / "scenes"
EPS = float(np.finfo(float).eps)


def _scene(name: str):
    return pile_scene(20) if name == "pile" else runtime.load_scene(SCENES / f"{name}.toml")


TOLERANCE = {"pile": 0.05, "rounded_stack": 0.05, "rounded_box_into_bowl": 0.6}  # m: every case


@pytest.mark.parametrize("scene_name", ["pile", "rounded_stack", "rounded_box_into_bowl"])
def test_one_contact_alone_gives_the_bits_it_gets_in_a_batch(scene_name):
    """Every contact of a pile of 20 discs (circle_circle, circle_edge against the fixed box),
    of the rounded stack and of the rounded box near the bowl (wide tolerance: every case
    they have), with random velocities, evaluated alone and all together."""
    scene = _scene(scene_name)
    rng = np.random.default_rng(3)
    poses = scene.poses()
    velocities = rng.normal(size=poses.shape)
    contacts = scene.contacts(poses, tolerance=TOLERANCE[scene_name])
    fixed = np.asarray(scene.fixed)
    kinds = set(zip(contacts.case.tolist(), fixed[contacts.body2].tolist(), strict=True))
    assert len(contacts) >= 1 and (scene_name == "rounded_box_into_bowl" or len(kinds) >= 2)
    evaluator = RowEvaluator(scene.contact_cases(), fixed)
    batch = evaluator.rows(contacts, poses, velocities)
    for k in range(len(contacts)):
        alone = evaluator.rows(contacts.take([k]), poses, velocities)
        for name in ("gap", "gap_velocity", "jacobian", "bias"):
            a, b = getattr(alone, name), getattr(batch, name)[k : k + 1]
            assert a.tobytes() == b.tobytes(), (contacts.describe(k), name)


@pytest.mark.parametrize("scene_name", ["pile", "rounded_stack", "rounded_box_into_bowl"])
def test_one_contact_watched_over_states_gives_the_bits_of_the_batch(scene_name):
    """The event search's watcher of one contact (RowEvaluator.watch), asked at three states in
    turn (so nothing of one state is left for the next): d and d' with the bits of the whole
    set's evaluation at each state."""
    scene = _scene(scene_name)
    rng = np.random.default_rng(5)
    poses = scene.poses()
    contacts = scene.contacts(poses, tolerance=TOLERANCE[scene_name])
    fixed = np.asarray(scene.fixed)
    evaluator = RowEvaluator(scene.contact_cases(), fixed)
    moving = ~fixed[:, None]
    states = [
        (poses + moving * rng.normal(scale=1e-3, size=poses.shape), rng.normal(size=poses.shape))
        for _ in range(3)
    ]
    batches = [evaluator.gap_and_rate(contacts, q, v) for q, v in states]
    for k in range(len(contacts)):
        watched = evaluator.watch(contacts, k)
        for (q, v), (gap, rate) in zip(states, batches, strict=True):
            d, d_rate = watched(q, v)
            assert isinstance(d, float) and isinstance(d_rate, float)
            assert np.float64(d).tobytes() == gap[k].tobytes(), contacts.describe(k)
            assert np.float64(d_rate).tobytes() == rate[k].tobytes(), contacts.describe(k)


@pytest.mark.parametrize("scene_name", ["pile", "rounded_stack", "rounded_box_into_bowl"])
def test_rows_are_the_numpy_kernels_numbers(scene_name):
    """The same contacts through the public NumPy kernels (generated/<case>.py) with keyword
    arguments built from the contract's geometry columns: equal to 4 eps relative."""
    scene = _scene(scene_name)
    rng = np.random.default_rng(4)
    poses = scene.poses()
    velocities = rng.normal(size=poses.shape) * ~np.asarray(scene.fixed)[:, None]
    contacts = scene.contacts(poses, tolerance=TOLERANCE[scene_name])
    fixed = np.asarray(scene.fixed)
    rows = RowEvaluator(scene.contact_cases(), fixed).rows(contacts, poses, velocities)
    for k in range(len(contacts)):
        case = contacts.case_name(k)
        module = importlib.import_module(f"generated.{case}")
        i, j = int(contacts.body1[k]), int(contacts.body2[k])
        values = {}
        for digit, body in (("1", i), ("2", j)):
            values.update(zip((f"x{digit}", f"y{digit}", f"th{digit}"), poses[body], strict=True))
            values.update(
                zip((f"vx{digit}", f"vy{digit}", f"w{digit}"), velocities[body], strict=True)
            )
        for name, column in generated.GEOMETRY_COLUMNS[case].items():
            values[name] = contacts.geometry[k, column]
        suffix = "_static2" if fixed[j] else ""

        def call(name, module=module, values=values):
            f = getattr(module, name)
            return f(**{a: values[a] for a in module.ARGUMENTS[name]})

        jacobian = np.zeros(6)
        jacobian[: 3 if fixed[j] else 6] = call("jacobian" + suffix)
        expected = {
            "gap": call("gap"),
            "gap_velocity": call("gap_velocity" + suffix),
            "bias": call("bias" + suffix),
            "jacobian": jacobian,
        }
        for name, want in expected.items():
            got = getattr(rows, name)[k]
            assert np.all(np.abs(got - want) <= 4 * EPS * (np.abs(want) + 1.0)), (case, name)
