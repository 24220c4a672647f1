"""runtime/kernels.py: contact rows from the generated kernels.

Why: the engine evaluates a group of one contact with Python floats (five times cheaper per
call than 1-element arrays) and larger groups with arrays; both must give the same bits, or a
run would depend on how many contacts of a case happen to be active.
"""

from __future__ import annotations

from dataclasses import fields
from pathlib import Path

import numpy as np
import pytest

import runtime
from bench.steps import pile_scene
from runtime.solve.dynamics import ContactDynamics
from runtime.solve.kernels import evaluate

SCENES = Path(__file__).resolve().parents[2] / "scenes"


@pytest.mark.parametrize("scene_name", ["pile", "rounded_stack"])
def test_one_contact_alone_gives_the_bits_it_gets_in_a_batch(scene_name):
    """Every resting contact of a pile of 20 discs (circle_circle, circle_edge against the fixed
    box) and of the rounded stack (circle_edge between moving blocks and on the fixed floor),
    with random velocities, evaluated alone (floats) and all together (arrays)."""
    if scene_name == "pile":
        scene = pile_scene(20)
    else:
        scene = runtime.load_scene(SCENES / f"{scene_name}.toml")
    rng = np.random.default_rng(3)
    poses = scene.poses()
    velocities = rng.normal(size=poses.shape)
    contacts = scene.find_contacts(poses)
    cases = {(c.case, scene.fixed[c.body2]) for c in contacts}
    assert len(contacts) >= 10 and len(cases) >= 2
    dynamics = ContactDynamics(scene)
    batch = evaluate(contacts, dynamics.modules, poses, velocities, scene.fixed)
    for k, contact in enumerate(contacts):
        alone = evaluate([contact], dynamics.modules, poses, velocities, scene.fixed)
        for f in fields(batch):
            a, b = getattr(alone, f.name), getattr(batch, f.name)[k : k + 1]
            assert a.tobytes() == b.tobytes(), (contact.case, f.name)
