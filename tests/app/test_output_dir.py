"""The output folder: checked before the run, locked against a second run, written atomically.

Why: results are what the user keeps (issue #13, "Data that is lost"). Each test sets up the
situation for real -- a second process holding the lock, a process that died with it, a signal
in the middle of a --force rerun, a folder that cannot be written -- and compares the folder's
bytes before and after.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from app_helpers import ROOT, snapshot, start_command, wait_for

import runtime.step.simulation
from runtime.app import cli, outputs
from runtime.app.output_dir import OutputDir, OutputError, _signals_held


def first_run(scene: Path, out: Path) -> dict[str, bytes]:
    """A complete run into ``out``; returns its files."""
    assert cli.main([str(scene), "--duration", "0.01", "--out", str(out), "--quiet"]) == 0
    return snapshot(out)


def leftovers(out: Path) -> list[str]:
    """Staging folders and lock files left beside ``out``."""
    return sorted(p.name for p in out.parent.iterdir() if p.name.startswith(f".{out.name}."))


# -- two runs into one folder ----------------------------------------------------------------------


HOLD_LOCK = """
import sys, time
from pathlib import Path
from runtime.app.output_dir import OutputDir
with OutputDir(Path(sys.argv[1]), force=True):
    print("locked", flush=True)
    time.sleep(120)
"""


def test_a_second_run_into_the_same_folder_refuses_naming_the_first(tmp_path, scene_file, capsys):
    out = tmp_path / "out"
    holder = subprocess.Popen(
        [sys.executable, "-c", HOLD_LOCK, str(out)],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    )
    try:
        assert holder.stdout.readline().strip() == "locked"
        status = cli.main([str(scene_file()), "--out", str(out), "--force", "--quiet"])
        err = capsys.readouterr().err
        assert status == 2
        assert len(err.strip().splitlines()) == 1
        assert f"output {str(out)!r} is in use by another simulate run (pid {holder.pid}" in err
        assert ".out.lock" in err
        assert not out.exists() or not any(out.iterdir())
    finally:
        holder.kill()
        holder.wait()
    # once the holder is gone (killed: its lock file is still there), the folder is free again
    assert (tmp_path / ".out.lock").exists()
    assert cli.main([str(scene_file()), "--duration", "0.01", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert f"took over the lock of a run that ended (pid {holder.pid}" in err
    assert leftovers(out) == []


def test_stale_staging_folders_of_dead_runs_are_removed(tmp_path, scene_file):
    out = tmp_path / "out"
    dead = tmp_path / ".out.partial-999999999"
    dead.mkdir()
    (dead / "trajectory.npz").write_bytes(b"half a file")
    first_run(scene_file(), out)
    assert leftovers(out) == []


def test_two_real_runs_at_once_one_refuses(tmp_path, scene_file):
    """Two processes started together into one folder: exactly one writes it, the other exits
    with 2 naming the first's pid."""
    scene = scene_file()
    args = [str(scene), "--duration", "0.3", "--out", "out", "--no-gif"]
    runs = [start_command(args, tmp_path) for _ in range(2)]
    results = [(p.wait(timeout=300), *p.communicate()) for p in runs]
    statuses = sorted(r[0] for r in results)
    assert statuses == [0, 2], results
    loser = next(r for r in results if r[0] == 2)
    winner = next(p for p, r in zip(runs, results, strict=True) if r[0] == 0)
    assert f"is in use by another simulate run (pid {winner.pid}" in loser[2]
    assert json.loads((tmp_path / "out" / "summary.json").read_text())["steps"] == 300


# -- interrupted runs keep the previous results ----------------------------------------------------


@pytest.mark.parametrize(
    ("sig", "status", "word"),
    [(signal.SIGINT, 130, "interrupted"), (signal.SIGTERM, 143, "terminated")],
    ids=["ctrl-c", "sigterm"],
)
def test_a_signal_during_a_force_rerun_keeps_the_previous_results(
    tmp_path, scene_file, sig, status, word
):
    scene = scene_file()
    out = tmp_path / "out"
    before = first_run(scene, out)
    run = start_command([str(scene), "--duration", "100", "--out", "out", "--force"], tmp_path)
    try:
        wait_for(lambda: any(tmp_path.glob(".out.partial-*")), what="the run to start")
        time.sleep(0.5)  # into the run
        run.send_signal(sig)
        _, err = run.communicate(timeout=60)
    finally:
        run.kill()
    assert run.returncode == status, err
    assert err.strip().splitlines()[-1] == (
        f"python -m runtime: {word}; 'out' keeps its previous contents"
    )
    assert "Traceback" not in err
    assert snapshot(out) == before
    assert leftovers(out) == []


def test_an_interrupt_while_the_files_are_written_leaves_no_truncated_file(
    tmp_path, scene_file, monkeypatch, capsys
):
    """Ctrl-C after the trajectory was half written: the earlier complete results stay."""
    scene = scene_file()
    out = tmp_path / "out"
    before = first_run(scene, out)

    def half_written(scene, run, folder, options, **kwargs):
        (folder / outputs.TRAJECTORY).write_bytes(b"PK\x03\x04 truncated")
        raise KeyboardInterrupt

    monkeypatch.setattr(outputs, "write_outputs", half_written)
    status = cli.main([str(scene), "--duration", "0.01", "--out", str(out), "--force"])
    assert status == 130
    assert (
        capsys.readouterr().err
        == f"simulate: interrupted; {str(out)!r} keeps its previous contents\n"
    )
    assert snapshot(out) == before
    with np.load(out / "trajectory.npz") as data:
        assert len(data["t"]) == 11
    assert leftovers(out) == []


def test_signals_wait_while_the_files_are_moved_into_place():
    reached = False
    with pytest.raises(KeyboardInterrupt):  # the held signal arrives once the block is left
        with _signals_held():
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.05)  # delivered here if it were not held
            reached = True
        time.sleep(0.5)
    assert reached


def test_a_commit_replaces_our_files_and_keeps_the_users(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    (out / "animation.gif").write_bytes(b"old gif")
    (out / "summary.json").write_text("old")
    with OutputDir(out, force=True, owned=outputs.OUTPUT_FILES) as output:
        (output.staging / "summary.json").write_text("new")
        output.commit(["summary.json"])
    assert snapshot(out) == {"notes.txt": b"mine", "summary.json": b"new"}
    assert leftovers(out) == []


# -- folders that cannot be used, found before the run -------------------------------------------


@pytest.fixture
def no_run(monkeypatch):
    """Fail the test if the engine is asked to run."""

    def refuse(*args, **kwargs):
        raise AssertionError("the run started before the output folder was checked")

    monkeypatch.setattr(runtime.step.simulation, "simulate", refuse)


def test_an_output_below_a_file_is_refused_before_the_run(tmp_path, scene_file, capsys, no_run):
    blocker = tmp_path / "file"
    blocker.write_text("x")
    out = blocker / "results"
    assert cli.main([str(scene_file()), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == (
        f"simulate: error: cannot create the output {str(out)!r}: {str(blocker)!r} is a file, "
        "not a directory\n"
    )
    assert blocker.read_text() == "x"


def test_an_output_folder_that_cannot_be_written_is_refused_before_the_run(
    tmp_path, scene_file, capsys, no_run
):
    """A folder marked immutable (chattr +i): not even root can create files in it."""
    out = tmp_path / "results"
    out.mkdir()
    (out / "old.txt").write_text("kept")
    if subprocess.run(["chattr", "+i", str(out)], capture_output=True).returncode != 0:
        pytest.skip("chattr +i is not available here")
    try:
        status = cli.main([str(scene_file()), "--out", str(out), "--force"])
    finally:
        subprocess.run(["chattr", "-i", str(out)], check=True)
    err = capsys.readouterr().err
    assert status == 2
    assert err == (
        f"simulate: error: cannot write into the output directory {str(out)!r}: "
        "Operation not permitted\n"
    )
    assert snapshot(out) == {"old.txt": b"kept"}
    assert leftovers(out) == []


def test_output_error_is_one_line_naming_the_path(tmp_path):
    target = tmp_path / "taken"
    target.write_text("x")
    with pytest.raises(OutputError, match="exists and is not a directory"):
        OutputDir(target, force=True).__enter__()
