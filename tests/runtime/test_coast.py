"""Coasting (runtime.step.coast: quiet steps in one compiled loop) gives the run that steps one by
one gives, bit for bit -- states, energies, momenta, gaps, impact times and losses, every record's
contacts and forces, the failure a guard names -- and leaves the World and its memory (the
contacts held, the warm-start guesses) as the steps one by one leave them. Each comparison also
checks that the loop did steps and declined some, so the equality is not vacuous."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import runtime
import runtime.step.simulation as simulation
from bench.scenes import falling_pile
from runtime.step.coast import Coaster
from runtime.step.guards import Guards
from tests.runtime.test_friction import _pile

SCENES = Path(__file__).resolve().parents[2] / "scenes"
ARRAYS = ("t", "poses", "velocities", "energy", "momentum", "min_gap", "impact_losses",
          "impact_times")  # fmt: skip
FIELDS = ("case", "body1", "body2", "geometry", "feature", "gap", "point", "normal")


def _simulate(scene, coasting: bool, monkeypatch, **options):
    """The run (or the SimulationError) with coasting on or off, and the steps that coasted."""
    coasted = []
    if coasting:
        run = Coaster.run

        def counted(self, times):
            stretch = run(self, times)
            coasted.append(0 if stretch is None else len(stretch))
            return stretch

        monkeypatch.setattr(Coaster, "run", counted)
    else:
        monkeypatch.setattr(simulation, "_coaster", lambda world: None)
    try:
        result = runtime.simulate(scene, **options)
    except runtime.SimulationError as exc:
        result = exc
    monkeypatch.undo()
    return result, coasted


def _assert_same_runs(a, b) -> None:
    for name in ARRAYS:
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    assert a.rhs_evaluations == b.rhs_evaluations
    assert len(a.contacts) == len(b.contacts)
    for k, (x, y) in enumerate(zip(a.contacts, b.contacts, strict=True)):
        for name in FIELDS:
            assert np.array_equal(getattr(x, name), getattr(y, name)), (k, name)
        assert np.array_equal(a.contact_forces[k], b.contact_forces[k]), k
        assert np.array_equal(a.friction_forces[k], b.friction_forces[k]), k


CASES = [  # scene, seconds, what the loop should do: coast only, or coast and decline
    ("disc_in_bowl.toml", 3.0, "only"),  # resting on an arc
    ("box_on_floor.toml", 1.0, "only"),  # resting on its corners
    ("d_shape_rolling.toml", 1.5, "only"),  # an arc rolling on a floor
    ("ball_drop.toml", 2.0, "both"),  # flights without contacts, bounces, apexes
    ("disc_pile.toml", 1.0, "both"),  # simultaneous impacts, a pile settling
    ("rounded_box_into_bowl.toml", 1.5, "both"),  # arcs and corners landing in an arc
    ("plank_on_cylinder.toml", 1.0, "both"),  # a plank rocking on a cylinder
    ("disc_over_cylinder.toml", 1.5, "both"),  # leaves the cylinder: a flight, no contacts
    ("disc_rolling_in_bowl.toml", 3.0, "only"),  # friction: a sticking contact on an arc
    ("block_on_incline.toml", 0.5, "only"),  # friction: a face sliding on its corners
]


@pytest.mark.parametrize(("name", "seconds", "does"), CASES)
def test_shipped_scenes_run_the_same_coasting_or_not(name, seconds, does, monkeypatch):
    scene = runtime.load_scene(SCENES / name)
    coasting, coasted = _simulate(scene, True, monkeypatch, duration=seconds)
    stepping, _ = _simulate(scene, False, monkeypatch, duration=seconds)
    _assert_same_runs(coasting, stepping)
    steps = len(stepping.t) - 1
    assert sum(coasted) > steps // 4  # the loop did much of the run
    declined = min(coasted) == 0 or sum(coasted) < steps - 1  # (the first step: one by one)
    assert declined == (does == "both")


def test_a_landing_pile_runs_the_same_coasting_or_not(monkeypatch):
    options = {"duration": 0.6, "dt": 1e-3}
    coasting, coasted = _simulate(falling_pile(12), True, monkeypatch, **options)
    stepping, _ = _simulate(falling_pile(12), False, monkeypatch, **options)
    _assert_same_runs(coasting, stepping)
    assert len(stepping.impact_times) > 20
    assert sum(coasted) > 50 and 0 in coasted


def test_boxes_and_a_disc_thrown_onto_a_floor_with_friction_run_the_same_coasting_or_not(
    monkeypatch,
):
    """Friction: impacts with restitution, tipping, sticking and sliding, stick <-> slip; the
    friction forces of every record too (runtime.step.coast_friction)."""
    options = {"duration": 1.5, "dt": 1e-3}
    coasting, coasted = _simulate(_pile(0.6), True, monkeypatch, **options)
    stepping, _ = _simulate(_pile(0.6), False, monkeypatch, **options)
    _assert_same_runs(coasting, stepping)
    assert len(stepping.impact_times) > 10
    assert sum(coasted) > 300 and 0 in coasted
    assert max(np.max(np.abs(f), initial=0.0) for f in coasting.friction_forces) > 0.1


def test_records_every_few_steps_and_a_short_last_step_are_the_same(monkeypatch):
    scene = runtime.load_scene(SCENES / "disc_in_bowl.toml")
    options = {"duration": 2.0031, "dt": 0.01, "record_every": 7}  # the last step 0.0031 s
    coasting, coasted = _simulate(scene, True, monkeypatch, **options)
    stepping, _ = _simulate(scene, False, monkeypatch, **options)
    _assert_same_runs(coasting, stepping)
    assert stepping.t[-1] == 2.0031 and len(stepping.t) == 30
    assert sum(coasted) > 150


def test_a_guard_that_trips_inside_a_stretch_names_the_same_step(monkeypatch):
    """The bowl's energy at RK4 dt = 0.01 rises by up to ~9e-10 of its energy scale: a limit of
    1e-10 trips at some step inside what would coast; the loop stops before it and World.step
    names it."""
    scene = runtime.load_scene(SCENES / "disc_in_bowl.toml")
    options = {"duration": 5.0, "dt": 0.01, "guards": Guards(energy_growth=1e-10)}
    coasting, coasted = _simulate(scene, True, monkeypatch, **options)
    stepping, _ = _simulate(scene, False, monkeypatch, **options)
    assert isinstance(stepping, runtime.SimulationError)
    assert "raised the energy" in str(stepping)
    assert str(coasting) == str(stepping)
    assert all(np.array_equal(x, y) for x, y in zip(coasting.state, stepping.state, strict=True))
    _assert_same_runs(coasting.run, stepping.run)
    assert f"step {sum(coasted) + 1} at" in str(stepping)  # the step after the stretch


@pytest.mark.parametrize(
    ("name", "before"),
    [
        ("rounded_box_into_bowl.toml", 150),  # landed, resting on arcs and corners
        ("box_on_floor.toml", 0),  # from the start: the memory is empty, the stretch fills it
        ("disc_rolling_in_bowl.toml", 5),  # friction: the bases remembered too
    ],
)
def test_a_stretch_leaves_the_world_and_its_memory_as_steps_one_by_one(name, before):
    scene = runtime.load_scene(SCENES / name)
    dt = 0.005
    coasting, stepping = runtime.World(scene), runtime.World(scene)
    for world in (coasting, stepping):
        for _ in range(before):
            world.step(dt)
    times = coasting.t + dt * np.arange(1, 41)
    stretch = Coaster(coasting).run(times)
    assert stretch is not None and len(stretch) >= 10
    for tau in times[: len(stretch)]:
        stepping.step(tau - stepping.t)
    assert coasting.t == stepping.t and coasting.steps == stepping.steps
    assert np.array_equal(coasting.poses, stepping.poses)
    assert np.array_equal(coasting.velocities, stepping.velocities)
    assert coasting.energy() == stepping.energy()
    a, b = coasting.stepper, stepping.stepper
    assert np.array_equal(a.held, b.held) and np.array_equal(a.recent, b.recent)
    assert len(b.forces.memory) > 0
    assert np.array_equal(a.forces.memory.keys, b.forces.memory.keys)
    assert np.array_equal(a.forces.memory.clamped, b.forces.memory.clamped)
    if b.friction is not None:
        assert len(b.forces.bases) > 0
        assert np.array_equal(a.forces.bases.keys, b.forces.bases.keys)
        assert np.array_equal(a.forces.bases.clamped, b.forces.bases.clamped)
    assert a.evaluations == b.evaluations
    assert np.array_equal(coasting.contact_forces, stepping.contact_forces)  # at the state now
    for _ in range(20):  # and the steps after
        coasting.step(dt)
        stepping.step(dt)
    assert np.array_equal(coasting.poses, stepping.poses)
    record, forces, _ = stretch.contacts(len(stretch) - 1)
    assert len(record) == len(forces) > 0
    with pytest.raises(ValueError, match="read-only"):  # shared by the stretch's records
        record.body1[0] = 0
