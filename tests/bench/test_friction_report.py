"""The report's friction scenes (bench/report_scenes.py): their references against closed forms
typed here, the peers' friction set so that each contact's coefficient is the scene's, and the
stored runs giving back the same comparison."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import runtime
from bench import report_store
from bench.compare import Point
from bench.references import InclineReference, RollingBowlReference, Trajectory
from bench.report_pages import SceneResult
from bench.report_scenes import SCENES

SCENE_DIR = Path(__file__).resolve().parents[2] / "scenes"
G = 9.81


def our_trajectory(scene, duration: float, dt: float) -> Trajectory:
    """Our RK4 run of the scene's one moving body, as bench/report.py reduces it."""
    run = runtime.simulate(scene, duration, dt, "rk4")
    forces = np.array([float(np.sum(f)) for f in run.contact_forces])
    return Trajectory("ours", "rk4", f"dt={dt}", run.t, run.poses[:, 1], run.velocities[:, 1],
                      forces, run.max_penetration, run.wall_time)  # fmt: skip


def test_the_block_slides_with_g_sin_minus_mu_cos_in_the_reference_and_in_our_engine():
    scene = runtime.load_scene(SCENE_DIR / "block_on_incline.toml")
    reference = InclineReference(scene, 0.5)
    a = G * (math.sin(math.pi / 6) - 0.3 * math.cos(math.pi / 6))
    assert np.linalg.norm(reference.acceleration) == pytest.approx(a, rel=1e-14)
    errors = reference.errors(our_trajectory(scene, 0.5, 0.05))
    assert errors["position"] < 1e-12 and errors["energy"] < 1e-12  # RK4: exact here
    assert errors["force"] < 1e-12


def test_the_rolling_disc_is_a_pendulum_in_two_thirds_g_and_needs_enough_mu():
    scene = runtime.load_scene(SCENE_DIR / "disc_rolling_in_bowl.toml")
    reference = RollingBowlReference(scene, 2.0)
    assert reference.pull == pytest.approx(2.0 * G / 3.0, rel=1e-14)
    errors = reference.errors(our_trajectory(scene, 2.0, 0.02))
    assert errors["position"] < 1e-6 and errors["slip"] < 1e-9
    data = tomllib.loads((SCENE_DIR / "disc_rolling_in_bowl.toml").read_text())
    for body in data["body"]:
        body["friction"] = 0.05
    with pytest.raises(ValueError, match=r"the disc would slip: rolling needs mu >= 0\.103"):
        RollingBowlReference(runtime.scene_from_dict(data), 2.0)


@pytest.mark.parametrize("engine", ["pymunk", "Box2D"])
def test_a_peer_slides_the_block_with_the_scene_s_contact_mu(engine):
    """pymunk multiplies its shapes' coefficients, Box2D takes sqrt(mu1 mu2): either way the
    block slides 0.5 a t^2 with a = g (sin - 0.3 cos) (to 1 %: their first-order stepping);
    with mu = 0.3 per shape given to pymunk as such (0.09) it would slide 76 % farther."""
    pytest.importorskip("pymunk" if engine == "pymunk" else "Box2D")  # the `peers` extra
    from bench import peers

    scene = runtime.load_scene(SCENE_DIR / "block_on_incline.toml")
    if engine == "pymunk":
        traj = peers.simulate_pymunk(scene, 0.5, peers.PeerConfig(dt=1 / 960), False, repeats=1)
    else:
        traj = peers.simulate_box2d(scene, 0.5, peers.Box2DConfig(dt=1 / 960), False, repeats=1)
    slid = np.linalg.norm(traj.pose[-1, :2] - traj.pose[0, :2])
    a = G * (math.sin(math.pi / 6) - 0.3 * math.cos(math.pi / 6))
    assert slid == pytest.approx(0.5 * a * 0.5**2, rel=0.01)


def test_stored_runs_give_back_the_same_comparison(tmp_path):
    spec = next(s for s in SCENES if s.name == "block_on_incline")
    ours = [Point("ours", "rk4", "dt=0.1", 0.02, {"position": 1e-15, "energy": 0.0}, 5)]
    theirs = {
        "pymunk": [
            Point("pymunk", "pymunk", f"dt={dt}", cost, {"position": err, "energy": math.inf}, 9)
            for dt, cost, err in ((0.1, 0.001, 1e-2), (0.01, 0.03, 1e-3))
        ]
    }
    result = report_store.load(spec, _saved(spec, ours, theirs, tmp_path / "b.json"))
    assert result.ours == ours and result.theirs == theirs and result.measured == "then"
    cmp = result.comparisons["pymunk"]
    assert cmp.cost_range == (0.02, 0.02)
    expected = 1e-15 / 10 ** np.interp(np.log(0.02), np.log([0.001, 0.03]), [-2, -3])
    assert cmp.error_ratio_mid == pytest.approx(expected, rel=1e-12)
    with pytest.raises(ValueError, match="holds scene 'block_on_incline', not 'disc_in_bowl'"):
        report_store.load(SCENES[0], tmp_path / "b.json")


def _saved(spec, ours, theirs, path: Path) -> Path:
    report_store.save(SceneResult(spec, ours, theirs, {}, "then"), path)
    return path
