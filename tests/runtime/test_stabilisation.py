"""`[simulation] stabilisation = true`: a penetration left in a resting contact decays (issue #13).

Why: without stabilisation a resting contact is held by d'' = 0, so a penetration it carries
(left by an impact located late, a feature switch at an arc's end, an exactly fitting disc)
stays for ever. The scene flag turns on a critically damped Baumgarte term with the time scale
T = 10 dt (runtime.step.world.World): d'' = -(2/T) d' - (1/T^2) d, whose solution from rest at
d0 is d(t) = d0 (1 + t/T) exp(-t/T) -- the reference here. (It used to be ignored from a file;
then the resting contacts' press, runtime.step.resting, took the recovery speed away at every
step and the penetration decayed ~20x slower than that.)
"""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import runtime

SCENES = Path(__file__).resolve().parents[2] / "scenes"
DEPTH = 1e-6  # m, the disc's initial penetration into the floor
DT = 1e-3

SCENE = """
[scene]
name = "sunk disc"
overlap_tolerance = 1e-5

[simulation]
duration = 0.1
dt = {dt}
{flag}

[[body]]
name = "floor"
fixed = true
shape = {{ type = "wall", start = [-1.0, 0.0], end = [1.0, 0.0] }}

[[body]]
name = "disc"
shape = {{ type = "disc", radius = 0.1 }}
density = 1000.0
position = [0.0, {y!r}]
"""


def _sunk_disc(tmp_path: Path, flag: str, dt: float = DT) -> runtime.Scene:
    path = tmp_path / f"sunk{len(flag)}-{dt}.toml"
    path.write_text(SCENE.format(dt=dt, flag=flag, y=0.1 - DEPTH))
    return runtime.load_scene(path)


def test_the_flag_in_a_scene_file_makes_a_penetration_decay_critically_damped(tmp_path):
    """A disc 1e-6 m into a floor, at rest. Without the flag the penetration stays exactly;
    with it, it follows d0 (1 + t/T) exp(-t/T), T = 10 dt, to 1e-4 of d0 at every step
    (measured 1.1e-12 m, 1e-6 of d0: RK4's error on the damped mode)."""
    plain = runtime.simulate(_sunk_disc(tmp_path, ""))
    stable = runtime.simulate(_sunk_disc(tmp_path, "stabilisation = true"))
    depth_plain = 0.1 - plain.poses[:, 1, 1]
    depth_stable = 0.1 - stable.poses[:, 1, 1]
    np.testing.assert_allclose(depth_plain, DEPTH, rtol=1e-9)
    T = 10 * DT
    reference = DEPTH * (1 + stable.t / T) * np.exp(-stable.t / T)
    assert np.max(np.abs(depth_stable - reference)) <= 1e-4 * DEPTH
    assert depth_stable[-1] <= 1e-3 * DEPTH  # 10 time scales: 5e-4 of d0 left
    assert np.all(stable.velocities[:, 1, 0] == 0.0)  # straight up, nothing sideways


def test_the_flag_changes_the_run_of_the_shipped_bowl_and_keeps_it_on_the_bowl():
    """disc_in_bowl.toml with and without the flag: the runs differ (the flag is read), and
    with it the gap stays within 1e-9 m of the bowl over 1 s (measured 3.1e-10 m; without it
    3.9e-13 m: on a curved contact the Baumgarte term reacts to the RK4 stages' own excursions
    off the circle, O(dt^2 v^2 / L), so it costs accuracy where nothing needs correcting)."""
    data = tomllib.loads((SCENES / "disc_in_bowl.toml").read_text())
    runs = {}
    for flag in (False, True):
        data["simulation"]["stabilisation"] = flag
        runs[flag] = runtime.simulate(runtime.scene_from_dict(data), duration=1.0)
    assert not np.array_equal(runs[False].poses, runs[True].poses)
    for flag, bound in ((False, 1e-12), (True, 1e-9)):
        centre = runs[flag].poses[:, 1, :2]
        gap = 0.9 - np.hypot(centre[:, 0], centre[:, 1])
        assert np.max(np.abs(gap)) <= bound, flag


@pytest.mark.parametrize("dt", [2e-3, 5e-4])
def test_the_time_scale_is_ten_of_the_scenes_steps(tmp_path, dt):
    """The flag's time scale follows the scene's dt (simulate given another dt keeps it): at
    t = T = 10 dt the penetration is d0 2/e."""
    scene = _sunk_disc(tmp_path, "stabilisation = true", dt)
    T = 10 * dt
    run = runtime.simulate(scene, duration=T, dt=1e-4)
    assert 0.1 - run.poses[-1, 1, 1] == pytest.approx(2 * DEPTH / math.e, rel=1e-4)
