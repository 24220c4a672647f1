"""Tests of the ``simulate`` command (runtime/app/cli.py) and its pictures (runtime/app/).

Why: the command is how people run scenes, so its files must be valid and consistent with each
other, it must never overwrite results by accident, and bad input must give one clear line and
exit status 2 rather than a traceback.  ``main([...])`` runs in-process on short runs; the last
test runs every shipped scene end to end (it is an ordinary test, so CI runs it).
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import re
import textwrap
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import runtime
from runtime.app import animation, cli, plotting, progress
from runtime.model.shapes import Arc, Segment, bowl

SCENES = Path(__file__).resolve().parents[2] / "scenes"
SCENE_FILES = sorted(SCENES.glob("*.toml"))
GIF_SCENE = "disc_in_bowl"  # the shipped scene also animated in the end-to-end test

# A disc resting on a floor next to a second one dropping onto it: contacts from the start.
SMALL_SCENE = """
[scene]
name = "small"

[simulation]
duration = 1.0
dt = 0.001
method = "rk4"

[[body]]
name = "floor"
fixed = true
shape = { type = "wall", start = [-1.0, 0.0], end = [1.0, 0.0] }

[[body]]
name = "resting"
shape = { type = "disc", radius = 0.1 }
density = 1000.0
position = [0.0, 0.1]

[[body]]
name = "falling"
shape = { type = "rounded_rect", width = 0.2, height = 0.1, corner_radius = 0.02 }
density = 500.0
position = [0.4, 0.3]
angle = 0.3
"""

DEFAULT_FILES = ("trajectory.npz", "energy_forces.png", "animation.gif", "summary.json")
NPZ_KEYS = {"t", "poses", "velocities", "energy", "momentum", "min_gap", "total_contact_force"}


def write_scene(directory: Path, text: str = SMALL_SCENE, name: str = "small.toml") -> Path:
    path = directory / name
    path.write_text(textwrap.dedent(text))
    return path


@pytest.fixture(scope="module")
def small_run(tmp_path_factory):
    """One run of the small scene: (exit status, stdout, output directory)."""
    base = tmp_path_factory.mktemp("cli")
    scene = write_scene(base)
    out = base / "out"
    stdout, stderr = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        status = cli.main([str(scene), "--duration", "0.05", "--fps", "60", "--out", str(out)])
    return status, stdout.getvalue(), stderr.getvalue(), out


def snapshot(directory: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(directory.iterdir())}


# -- a normal run -------------------------------------------------------------------------------


def test_run_writes_all_files_and_one_summary_line(small_run):
    status, out_text, err_text, out = small_run
    assert status == 0, err_text
    assert sorted(p.name for p in out.iterdir()) == sorted(DEFAULT_FILES)
    lines = out_text.strip().splitlines()
    assert len(lines) == 1 and "small" in lines[0] and "steps" in lines[0]
    # stderr is not a TTY under pytest: no bar; only plain progress lines, and only if the run is
    # slow (the first run on a fresh machine compiles the engine for half a minute or more)
    assert "\r" not in err_text
    for line in err_text.splitlines():
        assert re.fullmatch(
            r"simulate: ([\d.]+% \(t = .* s simulated\), \d+ s elapsed.*"
            r"|first run of this version: compiling the engine .*)",
            line,
        ), line


def test_trajectory_npz(small_run):
    *_, out = small_run
    with np.load(out / "trajectory.npz") as data:
        assert NPZ_KEYS <= set(data.files)
        assert list(data["body_names"]) == ["floor", "resting", "falling"]
        assert list(data["fixed"]) == [True, False, False]
        k = len(data["t"])
        assert k == 51  # 0.05 s / 0.001 s steps, both ends
        assert data["t"][-1] == pytest.approx(0.05)
        assert data["poses"].shape == (k, 3, 3)
        assert data["velocities"].shape == (k, 3, 3)
        assert data["energy"].shape == (k,)
        assert data["momentum"].shape == (k, 2)
        assert data["min_gap"].shape == (k,)
        assert data["total_contact_force"].shape == (k,)
        assert np.all(np.isfinite(data["poses"]))
        # the resting disc is held by the floor: it carries its weight
        weight = 1000.0 * math.pi * 0.1**2 * 9.81
        assert data["total_contact_force"][0] == pytest.approx(weight, rel=1e-6)
        # the falling box falls freely
        assert data["poses"][-1, 2, 1] < data["poses"][0, 2, 1]


def test_summary_matches_trajectory(small_run):
    *_, out = small_run
    info = json.loads((out / "summary.json").read_text())
    with np.load(out / "trajectory.npz") as data:
        t, energy, min_gap = data["t"], data["energy"], data["min_gap"]
        assert info["scene"] == "small"
        assert info["method"] == "rk4"
        assert info["dt"] == pytest.approx(float(data["dt"]))
        assert info["steps"] == len(t) - 1 == 50
        assert info["duration"] == pytest.approx(t[-1])
        assert info["energy_drift"] == pytest.approx(energy[-1] - energy[0], abs=1e-15)
        assert info["max_abs_energy_drift"] == pytest.approx(np.max(np.abs(energy - energy[0])))
        assert info["max_penetration"] == pytest.approx(max(0.0, -float(np.min(min_gap))))
    assert info["wall_time"] > 0
    assert info["steps_per_second"] == pytest.approx(info["steps"] / info["wall_time"])
    assert info["status"] == "ok" and info["error"] is None


def test_png_and_gif_are_valid(small_run):
    *_, out = small_run
    with Image.open(out / "energy_forces.png") as png:
        assert png.format == "PNG" and png.size[0] > 100 and png.size[1] > 100
    with Image.open(out / "animation.gif") as gif:
        assert gif.format == "GIF"
        assert gif.n_frames > 1
        assert max(gif.size) <= 400  # a small figure


def test_frame_indices_subsample_and_cap():
    t = np.arange(3001) * 1e-3  # 3 s at 1 ms
    frames = animation.frame_indices(t, fps=30)
    assert frames[0] == 0 and frames[-1] == 3000
    assert len(frames) == 91  # 30 per simulated second, both ends
    assert len(animation.frame_indices(t, fps=1000)) == animation.MAX_FRAMES
    assert len(animation.frame_indices(t[:5], fps=1)) == 2  # always first and last


def test_edge_points_follow_arcs_and_concave_arcs():
    convex = plotting.edge_points(Arc((1.0, 2.0), 0.5, 0.0, math.pi / 2))
    assert np.allclose(np.hypot(convex[:, 0] - 1.0, convex[:, 1] - 2.0), 0.5)
    assert np.allclose(convex[0], (1.5, 2.0)) and np.allclose(convex[-1], (1.0, 2.5))
    concave = plotting.edge_points(bowl(1.0, -math.pi, 0.0).edges[0])
    assert np.allclose(np.hypot(*concave.T), 1.0)
    assert np.allclose(concave[0], (1.0, 0.0)) and np.allclose(concave[-1], (-1.0, 0.0))
    assert np.all(concave[1:-1, 1] < 0)  # the lower half: the bowl's own span
    assert np.allclose(plotting.edge_points(Segment((0, 0), (1, 2))), [[0, 0], [1, 2]])


def test_progress_bar_draws_and_erases_itself():
    stream = io.StringIO()
    bar = progress.ProgressBar(stream, delay=0.0, interval=0.0, width=10)
    bar(0.5)
    assert "[#####.....]" in stream.getvalue() and "50.0%" in stream.getvalue()
    bar.close()
    assert stream.getvalue().endswith("\r") and "\n" not in stream.getvalue()
    quiet = io.StringIO()
    late = progress.ProgressBar(quiet, delay=60.0)  # short runs print nothing
    late(0.5)
    late.close()
    assert quiet.getvalue() == ""


def test_view_follows_a_small_body_on_a_long_floor():
    scene = runtime.scene_from_dict(
        {
            "body": [
                {"name": "floor", "fixed": True,
                 "shape": {"type": "wall", "start": [-50.0, 0.0], "end": [50.0, 0.0]}},
                {"name": "disc", "shape": {"type": "disc", "radius": 0.1},
                 "density": 1.0, "position": [3.0, 0.1]},
            ]
        }
    )  # fmt: skip
    view = animation.scene_view(scene, scene.poses()[None])
    # three times the disc's size, and a margin
    assert view.half_x == view.half_y == pytest.approx(0.3 / (1 - 2 * animation.MARGIN))
    assert view.centre == pytest.approx([3.0, 0.1])


# -- overwriting ----------------------------------------------------------------------------------


def test_refuses_non_empty_directory_without_force(tmp_path, capsys):
    scene = write_scene(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    (out / "trajectory.npz").write_bytes(b"an earlier run")
    before = snapshot(out)
    status = cli.main([str(scene), "--duration", "0.01", "--out", str(out), "--no-gif"])
    err = capsys.readouterr().err
    assert status == 2
    assert str(out) in err and "--force" in err
    assert len(err.strip().splitlines()) == 1
    assert snapshot(out) == before


def test_force_overwrites_our_files_and_keeps_others(tmp_path, capsys):
    scene = write_scene(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    (out / "animation.gif").write_bytes(b"stale")
    status = cli.main(
        [str(scene), "--duration", "0.01", "--out", str(out), "--no-gif", "--force", "--quiet"]
    )
    assert status == 0, capsys.readouterr().err
    assert (out / "notes.txt").read_text() == "mine"
    assert not (out / "animation.gif").exists()  # not written this time: the stale one is gone
    with np.load(out / "trajectory.npz") as data:
        assert len(data["t"]) == 11
    assert json.loads((out / "summary.json").read_text())["steps"] == 10


def test_empty_existing_directory_is_fine(tmp_path, capsys):
    scene = write_scene(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    assert cli.main([str(scene), "--duration", "0.005", "--out", str(out), "--no-gif"]) == 0
    assert (out / "summary.json").exists()


# -- bad input --------------------------------------------------------------------------------------


BAD_SCENE = SMALL_SCENE.replace("radius = 0.1 }", "radius = -0.1 }")


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (["--dt", "0"], ["--dt", "0"]),
        (["--dt", "-0.001"], ["--dt", "-0.001"]),
        (["--dt", "nan"], ["--dt", "nan"]),
        (["--dt", "abc"], ["--dt", "abc"]),
        (["--method", "leapfrog"], ["method", "leapfrog", "rk4"]),
        (["--duration", "inf"], ["--duration", "inf"]),
        (["--dt", "0.5", "--duration", "0.1"], ["--dt", "duration"]),
        (["--fps", "0"], ["--fps"]),
        (["--max-penetration", "0"], ["--max-penetration", "'off'"]),
        (["--max-energy-growth", "lots"], ["--max-energy-growth", "lots", "'off'"]),
    ],
    ids=[
        "dt-zero",
        "dt-negative",
        "dt-nan",
        "dt-text",
        "method",
        "duration",
        "dt-long",
        "fps",
        "penetration-zero",
        "energy-text",
    ],
)
def test_bad_arguments_exit_2_with_one_line(tmp_path, capsys, args, expected):
    scene = write_scene(tmp_path)
    out = tmp_path / "out"
    status = cli.main([str(scene), "--out", str(out), *args])
    captured = capsys.readouterr()
    assert status == 2
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in captured.err
    for word in expected:
        assert word in lines[0]
    assert not out.exists()


def test_missing_scene_file(tmp_path, capsys):
    missing = tmp_path / "nowhere.toml"
    assert cli.main([str(missing), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert str(missing) in err and "not found" in err
    assert len(err.strip().splitlines()) == 1


def test_invalid_scene_names_file_body_and_field(tmp_path, capsys):
    scene = write_scene(tmp_path, BAD_SCENE, "bad.toml")
    assert cli.main([str(scene), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert "bad.toml" in err and "resting" in err and "radius" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not (tmp_path / "out").exists()


def test_output_path_that_is_a_file(tmp_path, capsys):
    target = tmp_path / "taken"
    target.write_text("x")
    assert cli.main([str(write_scene(tmp_path)), "--out", str(target)]) == 2
    err = capsys.readouterr().err
    assert str(target) in err and "not a directory" in err
    assert target.read_text() == "x"


def test_out_defaults_to_out_slash_scene_name(tmp_path, capsys, monkeypatch):
    """No --out: out/<scene name> under the working directory, the name made a safe folder."""
    scene = write_scene(tmp_path, SMALL_SCENE.replace('name = "small"', 'name = "../up/a b"'))
    monkeypatch.chdir(tmp_path)
    assert cli.main([str(scene), "--duration", "0.005", "--no-gif"]) == 0
    assert capsys.readouterr().out.rstrip().endswith("-> out/up_a_b")
    assert json.loads((tmp_path / "out" / "up_a_b" / "summary.json").read_text())["steps"] == 5
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out", "small.toml"]


def test_simulation_error_writes_partial_run_and_exits_1(tmp_path, capsys, monkeypatch):
    scene_path = write_scene(tmp_path)
    real = runtime.simulate

    def failing(scene, duration=None, dt=None, method=None, **kwargs):
        run = real(scene, 0.01, dt, method, **kwargs)
        raise runtime.SimulationError("step 11 at t = 0.011 s failed (test)", run, (None, None))

    monkeypatch.setattr("runtime.step.simulation.simulate", failing)
    out = tmp_path / "out"
    status = cli.main([str(scene_path), "--duration", "0.05", "--out", str(out), "--fps", "200"])
    captured = capsys.readouterr()
    assert status == 1
    assert "step 11" in captured.err and "Traceback" not in captured.err
    with np.load(out / "trajectory.npz") as data:
        assert len(data["t"]) == 11
    info = json.loads((out / "summary.json").read_text())
    assert info["status"] == "failed" and "step 11" in info["error"]
    assert info["steps"] == 10
    assert (out / "energy_forces.png").exists() and (out / "animation.gif").exists()


# -- every shipped scene, end to end (runs in CI) -----------------------------------------------


def test_there_are_shipped_scenes():
    assert GIF_SCENE in {p.stem for p in SCENE_FILES}


@pytest.mark.parametrize("path", SCENE_FILES, ids=lambda p: p.stem)
def test_every_shipped_scene_end_to_end(tmp_path, capsys, path):
    out = tmp_path / path.stem
    gif = path.stem == GIF_SCENE
    args = [str(path), "--duration", "0.02", "--out", str(out), "--fps", "150"]
    status = cli.main(args if gif else [*args, "--no-gif"])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    expected = set(DEFAULT_FILES) - (set() if gif else {"animation.gif"})
    assert {p.name for p in out.iterdir()} == expected
    scene = runtime.load_scene(path)
    with np.load(out / "trajectory.npz") as data:
        assert data["poses"].shape == (21, len(scene.bodies), 3)
        assert np.all(np.isfinite(data["poses"]))
    info = json.loads((out / "summary.json").read_text())
    assert info["scene"] == scene.name and info["steps"] == 20
    if gif:
        with Image.open(out / "animation.gif") as image:
            assert image.n_frames > 1


def test_guards_stop_a_spoilt_run_unless_turned_off(tmp_path, capsys):
    """Explicit Euler at 0.05 s lets the disc drift into the bowl: the penetration guard stops
    the run (exit 1, the steps before written); with both guards off it runs to the end."""
    scene = str(SCENES / "disc_in_bowl.toml")
    args = [scene, "--duration", "1", "--dt", "0.05", "--method", "euler", "--no-gif"]
    assert cli.main([*args, "--out", str(tmp_path / "on")]) == 1
    err = capsys.readouterr().err
    assert "simulation failed: step 5 at t = 0.25 s left disc/bowl overlapping by" in err
    summary = json.loads((tmp_path / "on" / "summary.json").read_text())
    assert summary["status"] == "failed"
    off = ["--max-penetration", "off", "--max-energy-growth", "off"]
    assert cli.main([*args, *off, "--out", str(tmp_path / "off")]) == 0
    assert np.load(tmp_path / "off" / "trajectory.npz")["t"][-1] == pytest.approx(1.0)
