"""Ensembles (runtime.simulate_ensemble): every copy against its own `runtime.simulate` run of
a scene built independently (the scene dict with the copy's numbers, through
runtime.scene_from_dict), over copies that bounce, rest, leave a surface, differ in gravity,
mass and a fixed body's pose, and fail in different ways at different steps."""

from __future__ import annotations

import copy
import math
import re
from pathlib import Path

import numpy as np
import pytest

import runtime
import runtime.step.simulation as simulation
from runtime.collide import sweep
from runtime.solve.lcp import ContactSolverError
from runtime.step.stepper import Stepper

TOL = 1e-12
SCENES = Path(__file__).resolve().parents[2] / "scenes"

FLOOR = {"name": "floor", "fixed": True, "shape": {"type": "wall", "start": [-3.0, 0.0], "end": [3.0, 0.0]}}  # fmt: skip
MIXED = {
    "scene": {"name": "mixed", "gravity": [0.0, -9.81]},
    "simulation": {"duration": 0.8, "dt": 1e-3, "method": "rk4"},
    "body": [
        FLOOR,
        {
            "name": "cylinder",
            "fixed": True,
            "shape": {"type": "disc", "radius": 0.5},
            "position": [0.0, 0.5],
        },  # fmt: skip
        {
            "name": "disc",
            "shape": {"type": "disc", "radius": 0.1},
            "density": 1000.0,
            "position": [0.0, 1.1],
        },  # fmt: skip
    ],
}
BOWL = {
    "scene": {"name": "bowl"},
    "simulation": {"duration": 0.3, "dt": 1e-3},
    "body": [
        {
            "name": "bowl",
            "fixed": True,
            "shape": {"type": "bowl", "radius": 1.0, "start_angle": -2.6, "end_angle": -0.54},
        },  # fmt: skip
        {
            "name": "disc",
            "shape": {"type": "disc", "radius": 0.1},
            "density": 1000.0,
            "position": [0.0, -0.9],
        },  # fmt: skip
    ],
}


def in_bowl(angle: float, radius: float = 0.9) -> list[float]:
    return [radius * math.sin(angle), -radius * math.cos(angle)]


def variant(data: dict, changes: dict) -> runtime.Scene:
    """The scene dict with {(body index or "scene", key): value} changed (None: removed): one
    copy's scene."""
    data = copy.deepcopy(data)
    for (where, key), value in changes.items():
        table = data.setdefault("scene", {}) if where == "scene" else data["body"][where]
        table.pop(key, None)
        if value is not None:
            table[key] = value
    return runtime.scene_from_dict(data)


def assert_same(ensemble, c: int, run) -> None:
    """Copy c of the ensemble recorded what `run` recorded (to TOL, absolute and relative: sums
    over a larger system round differently; energy relative)."""
    k = len(run.t)
    assert ensemble.records[c] == k
    np.testing.assert_allclose(ensemble.t[:k], run.t, rtol=0, atol=TOL)
    np.testing.assert_allclose(ensemble.poses[c, :k], run.poses, rtol=TOL, atol=TOL)
    np.testing.assert_allclose(ensemble.velocities[c, :k], run.velocities, rtol=TOL, atol=TOL)
    scale = max(1.0, float(np.max(np.abs(run.energy), initial=0.0)))
    np.testing.assert_allclose(ensemble.energy[c, :k], run.energy, rtol=0, atol=TOL * scale)
    assert np.all(np.isnan(ensemble.poses[c, k:]))
    if k:
        assert ensemble.max_penetration[c] == pytest.approx(run.max_penetration, abs=TOL)


def test_each_copy_equals_its_own_run_bouncing_resting_and_leaving_a_surface():
    position = [[0, 1.1], [0, 1.1], [1.5, 0.1], [1.5, 0.5], [1.5, 1.2], [1.5, 0.3]]
    velocity = [[0, 0], [1.5, 0], [0, 0], [0, 0], [0, 0], [0.5, 0]]
    restitution = [0.0, 0.8, 0.0, 0.5, 0.9, 0.0]
    scene = runtime.scene_from_dict(MIXED)
    ensemble = runtime.simulate_ensemble(
        scene,
        {"disc.position": position, "disc.velocity": velocity, "disc.restitution": restitution},
    )
    assert ensemble.poses.shape == (6, 801, 3, 3) and ensemble.energy.shape == (6, 801)
    assert list(ensemble.failed) == [""] * 6
    impacts = []
    for c in range(6):
        run = runtime.simulate(
            variant(
                MIXED,
                {
                    (2, "position"): position[c],
                    (2, "velocity"): velocity[c],
                    (2, "restitution"): restitution[c],
                },
            )  # fmt: skip
        )
        assert_same(ensemble, c, run)
        impacts.append(len(run.impact_times))
    vy = ensemble.velocities[:, :, 2, 1]
    bounced = np.any((vy[:, :-1] < -0.5) & (vy[:, 1:] > 0.5), axis=1)
    assert bounced.tolist() == [False, True, False, True, True, False]
    speed = np.abs(ensemble.velocities[:, :, 2]).max(axis=(1, 2))
    assert speed[0] < 1e-9 and speed[2] < 1e-9  # resting on the cylinder's top, on the floor
    centre = np.hypot(*(ensemble.poses[1, :, 2, :2] - [0.0, 0.5]).T)
    flying = (centre > 0.6 + 1e-3) & (ensemble.poses[1, :, 2, 1] > 0.5)  # off, above its centre
    assert flying.any() and centre[0] == pytest.approx(0.6)
    assert impacts[1] >= 1 and impacts[3] >= 2


SLOPE = {
    "scene": {"name": "slope"},
    "simulation": {"duration": 0.3, "dt": 1e-3},
    "body": [
        {"name": "slope", "fixed": True, "friction": 0.5,
         "shape": {"type": "wall", "start": [0.0, 0.0], "end": [4 * math.cos(0.4), 4 * math.sin(0.4)]}},
        {"name": "block", "shape": {"type": "rounded_rect", "width": 0.2, "height": 0.1,
         "corner_radius": 0.0}, "mass": 1.0, "friction": 0.5, "angle": 0.4,
         "position": [2 * math.cos(0.4) - 0.05 * math.sin(0.4), 2 * math.sin(0.4) + 0.05 * math.cos(0.4)]},
    ],
}  # fmt: skip


def test_friction_varies_per_copy_a_block_slides_or_sticks_on_a_slope():
    """mu of the slope and of the block per copy (the contact's is sqrt(mu1 mu2)): each copy as
    its own run, and as the closed form: it slides with a = g (sin - mu cos) when tan 0.4 =
    0.42 > mu (0 frictionless: a copy without friction in a frictional ensemble), else stays."""
    slope_mu, block_mu = [0.5, 0.0, 0.3, 0.9], [0.5, 0.5, 0.12, 0.4]
    scene = runtime.scene_from_dict(SLOPE)
    ensemble = runtime.simulate_ensemble(
        scene, {"slope.friction": slope_mu, "block.friction": block_mu}
    )
    assert list(ensemble.failed) == [""] * 4
    along = np.array([math.cos(0.4), math.sin(0.4)])
    for c in range(4):
        run = runtime.simulate(variant(SLOPE, {(0, "friction"): slope_mu[c],
                                               (1, "friction"): block_mu[c]}))  # fmt: skip
        assert_same(ensemble, c, run)
        mu = math.sqrt(slope_mu[c] * block_mu[c])
        a = max(9.81 * (math.sin(0.4) - mu * math.cos(0.4)), 0.0)
        moved = (ensemble.poses[c, :, 1, :2] - ensemble.poses[c, 0, 1, :2]) @ -along
        np.testing.assert_allclose(moved, 0.5 * a * ensemble.t**2, rtol=0, atol=1e-12)
    assert [bool(ensemble.poses[c, -1, 1, 1] < ensemble.poses[c, 0, 1, 1]) for c in range(4)] == [
        False, True, True, False,
    ]  # fmt: skip


def test_gravity_mass_spin_and_a_fixed_body_s_pose_vary_per_copy():
    """Gravity (direction and size), mass, a moving body's angle and spin, and the bowl's own
    angle and position (a fixed body of each copy's own) against single runs."""
    n = 4
    angles = [0.1, 0.3, -0.2, 0.25]
    gravity = [[0.0, -9.81], [0.0, -5.0], [1.0, -12.0], [-2.0, -9.0]]
    values = {
        "disc.position": [in_bowl(a) for a in angles],
        "scene.gravity": gravity,
        "disc.mass": [31.4, 1.0, 500.0, 2.0],
        "disc.angle": [0.0, 1.0, 4.0, -7.0],  # reduced to (-pi, pi] as the scene file does
        "disc.angular_velocity": [0.0, 3.0, -1.0, 10.0],
        "bowl.angle": [0.0, 0.05, -0.1, 0.0],
        "bowl.position[1]": [0.0, 0.0, 0.0, -0.02],  # one component, x keeps the scene's
    }
    ensemble = runtime.simulate_ensemble(runtime.scene_from_dict(BOWL), values)
    assert list(ensemble.failed) == [""] * n
    for c in range(n):
        run = runtime.simulate(
            variant(
                BOWL,
                {
                    (1, "position"): values["disc.position"][c],
                    ("scene", "gravity"): gravity[c],
                    (1, "mass"): values["disc.mass"][c],
                    (1, "density"): None,
                    (1, "angle"): values["disc.angle"][c],
                    (1, "angular_velocity"): values["disc.angular_velocity"][c],
                    (0, "angle"): values["bowl.angle"][c],
                    (0, "position"): [0.0, values["bowl.position[1]"][c]],
                },
            )  # fmt: skip
        )
        assert_same(ensemble, c, run)
    assert np.ptp(ensemble.poses[:, -1, 1, 0]) > 0.1  # the copies went different ways


def test_a_body_placed_by_its_shape_s_own_origin():
    """A D shape (origin at its arc's centre, not its centre of mass): position, velocity and
    angle vary in the scene file's terms."""
    data = {
        "simulation": {"duration": 0.2, "dt": 1e-3},
        "body": [FLOOR, {"name": "d", "shape": {"type": "d_shape", "width": 0.15, "height": 0.2},
                         "density": 1000.0, "position": [0.0, 0.1], "angle": -1.5707963267948966,
                         "velocity": [0.3, 0.0], "angular_velocity": -3.0}],
    }  # fmt: skip
    values = {
        "d.position": [[0.0, 0.1], [1.0, 0.1], [-0.5, 0.3]],
        "d.velocity": [[0.3, 0.0], [-0.6, 0.0], [0.0, 0.0]],
        "d.angular_velocity": [-3.0, 6.0, 0.0],
        "d.angle": [-1.5707963267948966, -1.4, 0.3],
    }
    ensemble = runtime.simulate_ensemble(runtime.scene_from_dict(data), values)
    for c in range(3):
        changes = {(1, key.split(".")[1]): v[c] for key, v in values.items()}
        assert_same(ensemble, c, runtime.simulate(variant(data, changes)))


def test_failing_copies_are_recorded_as_their_own_runs_while_the_others_finish():
    """Euler at dt = 2 ms in the bowl with a tight energy guard: a wide swing raises the
    energy, two fast ones sink into the bowl (a missed contact, at different steps), one starts
    overlapping; the two narrow swings run to the end."""
    positions = [
        in_bowl(0.1),
        in_bowl(0.3),
        in_bowl(0.6),
        in_bowl(0.0),
        in_bowl(0.0),
        in_bowl(0.2, 0.905),
    ]  # fmt: skip  (the last starts 5 mm into the bowl)
    velocities = [[0.0, 0.0]] * 3 + [[3.0, 0.0], [2.5, 0.0], [0.0, 0.0]]
    guards = runtime.Guards(energy_growth=4e-4)
    options = {"duration": 0.5, "dt": 2e-3, "method": "euler", "guards": guards}
    ensemble = runtime.simulate_ensemble(
        runtime.scene_from_dict(BOWL),
        {"disc.position": positions, "disc.velocity": velocities},
        **options,
    )
    messages = []
    for c, position in enumerate(positions):
        scene = runtime.scene_from_dict(BOWL)  # a disc: its position is its centre of mass
        disc = scene.body("disc")  # (a scene file refuses the overlap)
        disc.position, disc.velocity = tuple(position), tuple(velocities[c])
        try:
            run = runtime.simulate(scene, **options)
            messages.append("")
        except runtime.SimulationError as exc:
            run = exc.run
            messages.append(str(exc))
        assert_same(ensemble, c, run)
    assert list(ensemble.failed) == messages
    assert messages[:2] == ["", ""] and "raised the energy" in messages[2]
    assert (
        "left disc/bowl overlapping" in messages[3] and "left disc/bowl overlapping" in messages[4]
    )
    assert messages[5].startswith("step 0 at t = 0 s starts with disc/bowl overlapping")
    assert ensemble.records.tolist() == [251, 251, 191, 52, 79, 0]  # "left" by the step before


def test_a_step_that_raises_drops_only_the_copies_that_raise_alone(monkeypatch):
    """A contact-solver failure injected into the step whenever a disc moves faster than
    1.2 m/s (the swings of 0.5 rad and more, at different times): those copies are found and
    dropped with their own run's message; the step is redone for the others."""
    original = Stepper.step

    def failing(self, q, v, h):
        fast = np.hypot(v[:, 0], v[:, 1]) > 1.2
        if np.any(fast):
            raise ContactSolverError(f"injected: {int(np.sum(fast))} fast")
        return original(self, q, v, h)

    monkeypatch.setattr(Stepper, "step", failing)
    monkeypatch.setattr(simulation, "_coaster", lambda world: None)  # every step through it
    angles = [0.1, 0.55, 0.2, 0.3, 0.7, 0.15, 0.6, 0.25]
    positions = [in_bowl(a) for a in angles]
    ensemble = runtime.simulate_ensemble(
        runtime.scene_from_dict(BOWL), {"disc.position": positions}
    )
    for c, position in enumerate(positions):
        try:
            run = runtime.simulate(variant(BOWL, {(1, "position"): position}))
            assert ensemble.failed[c] == ""
        except runtime.SimulationError as exc:
            run = exc.run
            assert ensemble.failed[c] == str(exc)
            assert "failed (injected: 1 fast)" in str(exc)
        assert_same(ensemble, c, run)
    assert [bool(m) for m in ensemble.failed] == [a >= 0.5 for a in angles]
    assert len(set(ensemble.records[[1, 4, 6]].tolist())) == 3  # three different steps


def test_a_copy_that_tunnels_through_its_own_wall_is_stopped_alone(monkeypatch):
    """wall_shot with the swept contact search off (as test_guards.py does): the disc jumps
    over the 1 cm wall in one step where the wall (each copy's own: its position and angle
    vary) is in its path, and the copies whose wall is beyond reach run on. No copy here meets
    its wall in an impact the crippled search finds: a located impact ends a sub-step for the
    contact-free bodies of every copy too, whose search at that instant can then find the
    crossing its own run misses (the copies' paths stay equal; what the crippled search sees
    does not)."""
    monkeypatch.setattr(sweep, "margins", lambda v, h, radii, moving, g: np.zeros(len(radii)))
    monkeypatch.setattr(sweep, "outran", lambda *args: False)
    monkeypatch.setattr(simulation, "_coaster", lambda world: None)  # (it calls its own)
    scene = runtime.load_scene(SCENES / "wall_shot.toml")
    walls = [[5.0, 0.0], [0.0, 0.3], [0.2, 0.28], [8.0, 0.0]]
    angles = [0.0, 0.3, 0.28, 0.1]
    options = {"duration": 0.05, "dt": 1.0 / 60.0}
    values = {"wall.position": walls, "wall.angle": angles}
    ensemble = runtime.simulate_ensemble(scene, values, **options)
    for c in range(len(walls)):
        alone = runtime.load_scene(SCENES / "wall_shot.toml")
        wall = alone.body("wall")
        wall.position, wall.angle = tuple(walls[c]), angles[c]
        try:
            run, message = runtime.simulate(alone, **options), ""
        except runtime.SimulationError as exc:
            run, message = exc.run, str(exc)
        assert ensemble.failed[c] == message
        assert_same(ensemble, c, run)
    tunnelled = [m.startswith("step 0 at t = 0 s moved the centre of mass of disc through wall")
                 for m in ensemble.failed]  # fmt: skip
    assert tunnelled == [False, True, True, False]


@pytest.mark.parametrize(
    ("variations", "words"),
    [
        ([("disc.mass", [1.0])], "variations must be a mapping"),
        ({}, "variations is empty"),
        ({"disc": [1.0]}, "variations key 'disc' must be '<body name>.<field>'"),
        ({"dics.mass": [1.0]}, "variations['dics.mass']: no body named 'dics'; bodies: bowl, disc"),
        ({"disc.colour": [1.0]}, "variations['disc.colour']: unknown field 'colour'"),
        ({"bowl.velocity": [[1.0, 0.0]]}, "'bowl' is fixed: only its position, angle, restitution"),
        ({"disc.mass": [[1.0, 2.0]]}, "variations['disc.mass'] must have shape (N,)"),
        ({"disc.position": [1.0, 2.0]}, "variations['disc.position'] must have shape (N, 2)"),
        ({"disc.mass": []}, "variations['disc.mass'] is empty"),
        ({"disc.mass": ["heavy"]}, "variations['disc.mass'] must be an array of numbers"),
        ({"disc.mass": [1.0, 2.0], "disc.angle": [0.0]}, "variations['disc.angle'] has 1 values, variations['disc.mass'] 2"),
        ({"disc.mass": [1.0, -2.0]}, "variations['disc.mass'][1] = -2.0: must be a mass >= 1e-50"),
        ({"disc.restitution": [0.5, 1.5]}, "variations['disc.restitution'][1] = 1.5: must be between 0 and 1"),
        ({"disc.friction": [0.5, -0.1]}, "variations['disc.friction'][1] = -0.1: must be >= 0"),
        ({"disc.angle": [float("nan")]}, "variations['disc.angle'][0] = nan: must be finite"),
        ({"scene.gravity": [[0.0, 1e60]]}, "variations['scene.gravity'][0] = [0.0, 1e+60]: must be at most 1e+50"),
        ({"disc.position": [[0.0, 0.0]], "disc.position[0]": [1.0]}, "disc.position given twice"),
        ({"disc.angle[1]": [1.0]}, "angle is a number: no component 1"),
        ({"disc.position[2]": [1.0]}, "position is a vector of 2 components: no component 2"),
    ],
)  # fmt: skip
def test_bad_variations_are_refused_in_one_line_naming_the_key(variations, words):
    scene = runtime.scene_from_dict(BOWL)
    with pytest.raises(ValueError, match=re.escape(words)) as caught:
        runtime.simulate_ensemble(scene, variations, duration=0.01)
    assert "\n" not in str(caught.value)


@pytest.mark.parametrize(
    ("options", "words"),
    [
        ({"method": "rk45"}, "method 'rk45': choose one of euler, midpoint, rk4"),
        ({"method": "leapfrog"}, "unknown method; method 'leapfrog'"),
        ({"dt": 0.0}, "dt must be a finite number > 0"),
        ({"record_every": 0}, "record_every must be an integer >= 1"),
        ({"resting_speed": -1.0}, "resting_speed must be a finite number > 0"),
    ],
)
def test_bad_arguments_are_refused(options, words):
    scene = runtime.scene_from_dict(BOWL)
    with pytest.raises(ValueError, match=re.escape(words)):
        runtime.simulate_ensemble(scene, {"disc.mass": [1.0]}, **{"duration": 0.01, **options})


def test_records_every_few_steps_and_a_zero_duration():
    scene = runtime.scene_from_dict(BOWL)
    positions = [in_bowl(0.2), in_bowl(0.4)]
    ensemble = runtime.simulate_ensemble(
        scene, {"disc.position": positions}, duration=0.05, record_every=7
    )
    run = runtime.simulate(
        variant(BOWL, {(1, "position"): positions[1]}), duration=0.05, record_every=7
    )
    assert_same(ensemble, 1, run)
    still = runtime.simulate_ensemble(scene, {"disc.position": positions}, duration=0.0)
    assert still.t.tolist() == [0.0] and still.records.tolist() == [1, 1]
    np.testing.assert_array_equal(still.poses[:, 0, 1, :2], positions)


def test_an_ensemble_whose_copies_all_fail_ends_cleanly():
    positions = [in_bowl(0.1, 0.905), in_bowl(0.2, 0.906)]
    scene = runtime.scene_from_dict(BOWL)
    ensemble = runtime.simulate_ensemble(scene, {"disc.position": positions}, duration=0.01)
    assert all(m.startswith("step 0 at t = 0 s starts with disc/bowl") for m in ensemble.failed)
    assert ensemble.records.tolist() == [0, 0] and np.isnan(ensemble.poses).all()
