"""The animation: its size, frame rate, arrows, the view that frames the whole scene, and MP4.

References: the recorded poses themselves (every body over its whole path must be inside the
one fixed view), the pixel counts asked for, GIF's frame delay, and the bytes a fake ffmpeg
receives (frames x width x height x 3).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import runtime
from runtime.app import animation, cli
from runtime.app.animation import Look

FALL = {
    "body": [
        {"name": "floor", "fixed": True,
         "shape": {"type": "wall", "start": [-0.5, 0.0], "end": [0.5, 0.0]}},
        {"name": "disc", "density": 1000.0, "position": [0.0, 2.0],
         "shape": {"type": "disc", "radius": 0.1}},
        {"name": "pebble", "density": 1000.0, "position": [0.3, 0.05],
         "shape": {"type": "disc", "radius": 0.05}},
    ]
}  # fmt: skip


@pytest.fixture(scope="module")
def fall():
    """A disc falling 1.9 m onto a floor, beside a pebble resting there."""
    scene = runtime.scene_from_dict(FALL)
    return scene, runtime.simulate(scene, 0.7, 2e-3, "rk4")


def test_the_view_frames_every_body_over_its_whole_path(fall):
    scene, run = fall
    poses = np.asarray(run.poses)
    assert poses[:, 1, 1].max() - poses[:, 1, 1].min() > 1.8  # it did fall
    for aspect in (1.0, 16 / 9, 0.5):
        view = animation.scene_view(scene, poses, aspect)
        assert view.half_x / view.half_y == pytest.approx(aspect)
        for i, body in enumerate(scene.bodies[1:], start=1):
            r = body.shape.bounding_radius
            assert np.all(poses[:, i, 0] - r >= view.centre[0] - view.half_x)
            assert np.all(poses[:, i, 0] + r <= view.centre[0] + view.half_x)
            assert np.all(poses[:, i, 1] - r >= view.centre[1] - view.half_y)
            assert np.all(poses[:, i, 1] + r <= view.centre[1] + view.half_y)
        # and not much more: the scene spans y from 0 to 2.1
        assert 2 * view.half_y < 2.1 / (1 - 2 * animation.MARGIN) * max(1.0, 1 / aspect) + 1e-9


def test_a_pendulum_is_drawn_with_its_string_and_pivot_in_view(monkeypatch):
    """A disc on a distance joint from a pivot 1 m above it: the view holds the pivot, and the
    frame differs from the same frame without the joint by a vertical line (the string)."""
    scene = runtime.scene_from_dict(
        {"body": [{"name": "bob", "mass": 1.0, "position": [0.0, -1.0],
                   "shape": {"type": "disc", "radius": 0.1}}],
         "joint": [{"type": "distance", "body1": "bob", "body2": "world",
                    "anchor2": [0.0, 0.0]}]}
    )  # fmt: skip
    run = runtime.simulate(scene, 0.01, 1e-3)
    view = animation.scene_view(scene, np.asarray(run.poses))
    assert view.centre[1] + view.half_y > 0.0  # the pivot at y = 0
    look = Look(200, 200, dpi=72, fps=100)
    monkeypatch.setattr(animation, "scene_view", lambda *args: view)
    drawn = next(animation.render_frames(scene, run, look)).astype(int)
    scene.joints = []
    bare = next(animation.render_frames(scene, run, look)).astype(int)
    rows, columns = np.nonzero(np.abs(drawn - bare).sum(axis=2) > 60)
    assert np.ptp(rows) > 0.3 * look.height and np.ptp(columns) <= 3, (np.ptp(rows), columns)


def test_size_dpi_and_frame_rate_are_those_asked_for(fall, tmp_path):
    scene, run = fall
    for look in (Look(320, 200, dpi=72, fps=10), Look(200, 320, dpi=150, fps=100)):
        path = tmp_path / "a.gif"
        count = animation.save_animation(scene, run, path, look)
        assert count == len(animation.frame_indices(run.t, look.fps))
        with Image.open(path) as gif:
            assert gif.size == (look.width, look.height)
            assert gif.n_frames == count
            assert gif.info["duration"] == round(1000 / min(look.fps, 50))
    assert len(animation.frame_indices(run.t, 10)) == 8  # 0.7 s at 10 per second, both ends


def red_pixels(frame: np.ndarray) -> int:
    r, g, b = (frame[..., k].astype(int) for k in range(3))
    return int(np.sum((r > 150) & (g < 80) & (b < 100)))


def test_no_arrows_leaves_the_contact_points_only(fall):
    scene, run = fall
    with_arrows = list(animation.render_frames(scene, run, Look(fps=5)))
    without = list(animation.render_frames(scene, run, Look(fps=5, arrows=False)))
    # the pebble rests on the floor in every frame: a point, and with arrows a normal too
    for a, b in zip(with_arrows, without, strict=True):
        assert red_pixels(b) > 0
        assert red_pixels(a) >= red_pixels(b) + 5


FAKE_FFMPEG = """#!{python}
import json, os, sys
data = sys.stdin.buffer.read()
open(sys.argv[-1], "wb").write(b"not really an mp4")
json.dump({{"args": sys.argv[1:], "bytes": len(data)}}, open(os.environ["FAKE_FFMPEG_LOG"], "w"))
"""


def test_mp4_streams_every_frame_to_ffmpeg(tmp_path, monkeypatch, scene_file, capsys):
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    ffmpeg = bin_dir / "ffmpeg"
    ffmpeg.write_text(FAKE_FFMPEG.format(python=sys.executable))
    ffmpeg.chmod(0o755)
    log = tmp_path / "ffmpeg.json"
    monkeypatch.setenv("PATH", f"{bin_dir}:/usr/bin:/bin")
    monkeypatch.setenv("FAKE_FFMPEG_LOG", str(log))
    out = tmp_path / "out"
    args = ["--duration", "0.1", "--out", str(out), "--mp4", "--size", "160x120", "--fps", "40"]
    assert cli.main([str(scene_file()), *args, "--quiet"]) == 0, capsys.readouterr().err
    record = json.loads(log.read_text())
    frames = json.loads((out / "summary.json").read_text())["animation_frames"]
    assert frames == 5  # 0.1 s at 40 per second, both ends
    assert record["bytes"] == frames * 160 * 120 * 3
    argv = record["args"]
    assert argv[argv.index("-s") + 1] == "160x120" and argv[argv.index("-r") + 1] == "40"
    assert argv[-1].endswith("animation.mp4")
    assert (out / "animation.mp4").read_bytes() == b"not really an mp4"


def test_mp4_without_ffmpeg_is_refused_before_the_run(tmp_path, monkeypatch, scene_file, capsys):
    monkeypatch.setenv("PATH", str(tmp_path))  # no ffmpeg there
    out = tmp_path / "out"
    assert cli.main([str(scene_file()), "--out", str(out), "--mp4"]) == 2
    err = capsys.readouterr().err
    assert err == (
        "simulate: error: --mp4 needs ffmpeg on PATH and there is none; install it (Debian: "
        "apt-get install ffmpeg) or leave out --mp4 (animation.gif is written either way)\n"
    )
    assert not out.exists()


def test_a_failing_ffmpeg_is_reported_and_the_other_files_kept(
    tmp_path, monkeypatch, scene_file, capsys
):
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    broken = bin_dir / "ffmpeg"
    broken.write_text(
        f"#!{sys.executable}\nimport sys\nsys.stderr.write('Unknown encoder\\n')\nsys.exit(1)\n"
    )
    broken.chmod(0o755)
    monkeypatch.setenv("PATH", f"{bin_dir}:/usr/bin:/bin")
    out = tmp_path / "out"
    status = cli.main(
        [str(scene_file()), "--duration", "0.02", "--out", str(out), "--mp4", "--quiet"]
    )
    err = capsys.readouterr().err
    assert status == 1
    assert (
        "simulate: error: animation.mp4 not written: ffmpeg failed (exit status 1): Unknown encoder"
        in err
    )
    assert sorted(p.name for p in out.iterdir()) == [
        "animation.gif", "energy_forces.png", "summary.json", "trajectory.npz",
    ]  # fmt: skip


@pytest.mark.skipif(not Path("/usr/bin/ffmpeg").exists(), reason="no real ffmpeg here")
def test_a_real_ffmpeg_writes_a_video(tmp_path, scene_file, capsys):
    out = tmp_path / "out"
    assert cli.main([str(scene_file()), "--duration", "0.1", "--out", str(out), "--mp4"]) == 0
    assert (out / "animation.mp4").read_bytes()[4:8] == b"ftyp"
