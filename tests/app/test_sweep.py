"""The sweep command: its table and trajectories against single `runtime.simulate` runs, on a
Dask LocalCluster of two worker processes on 127.0.0.1 started here; resuming after a chunk
failed; the rules of --force; bad --vary input."""

from __future__ import annotations

import logging
import re
import tomllib

import numpy as np
import pyarrow.csv as pacsv
import pyarrow.parquet as pq
import pytest

import runtime
from runtime.app import sweep, sweep_chunk
from runtime.app.output_dir import FolderLock

SCENE = """
[scene]
name = "drop_in_bowl"

[simulation]
duration = 0.2
dt = 0.001

[[body]]
name = "bowl"
fixed = true
shape = { type = "bowl", radius = 1.0, start_angle = -2.6, end_angle = -0.54 }

[[body]]
name = "disc"
shape = { type = "disc", radius = 0.1 }
density = 1000.0
position = [0.0, -0.85]
"""
GRID = ["--vary", "disc.position[0]=linspace(-0.2,0.2,4)", "--vary", "disc.restitution=0,0.6"]
STATE = ("x", "y", "angle", "vx", "vy", "angular_velocity")


@pytest.fixture(scope="module")
def scene_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("scene") / "drop.toml"
    path.write_text(SCENE)
    return path


def local_cluster(processes: bool):
    import dask
    from distributed import LocalCluster

    # forked workers start with this process's compiled engine (as the command's own)
    runtime.simulate_ensemble(
        runtime.scene_from_dict(tomllib.loads(SCENE)), {"disc.mass": [1.0]}, 0.001
    )
    with dask.config.set({"distributed.worker.multiprocessing-method": "fork"}):
        return LocalCluster(
            n_workers=2 if processes else 1, threads_per_worker=1, processes=processes,
            protocol="tcp", host="127.0.0.1", dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR,
        )  # fmt: skip


@pytest.fixture(scope="module")
def two_processes():
    cluster = local_cluster(processes=True)
    yield cluster.scheduler_address
    cluster.close()


@pytest.fixture(scope="module")
def in_process():
    cluster = local_cluster(processes=False)
    yield cluster.scheduler_address
    cluster.close()


def run(scene_path, out, scheduler, *extra) -> int:
    args = [str(scene_path), *GRID, "--chunk", "3", "--out", str(out), "--quiet", *extra]
    return sweep.main([*args, "--scheduler", scheduler] if scheduler else args)


def single(x: float, restitution: float):
    data = tomllib.loads(SCENE)
    data["body"][1]["position"][0] = x
    data["body"][1]["restitution"] = restitution
    return runtime.simulate(runtime.scene_from_dict(data))


def table(out) -> list[dict]:
    return pq.read_table(out / "table.parquet").to_pylist()


def test_a_sweep_on_two_worker_processes_matches_single_runs(
    tmp_path, scene_path, two_processes, capsys
):
    out = tmp_path / "sweep"
    args = [str(scene_path), *GRID, "--chunk", "3", "--out", str(out)]
    assert sweep.main([*args, "--scheduler", two_processes]) == 0
    captured = capsys.readouterr()
    assert "8/8" in captured.err  # the progress bar
    assert "sweep: 8 runs (3 of 3 chunks run now)" in captured.out
    rows = table(out)
    assert [r["run"] for r in rows] == list(range(8)) and [r["chunk"] for r in rows] == [
        0,
        0,
        0,
        1,
        1,
        1,
        2,
        2,
    ]
    from_csv = pacsv.read_csv(out / "table.csv").to_pylist()
    assert [r["disc.x"] for r in from_csv] == pytest.approx([r["disc.x"] for r in rows], abs=1e-15)
    xs = np.linspace(-0.2, 0.2, 4)
    for r, row in enumerate(rows):
        x, e = xs[r // 2], (0.0, 0.6)[r % 2]
        assert (row["disc.position[0]"], row["disc.restitution"]) == (x, e)
        reference = single(x, e)
        final = np.r_[reference.poses[-1, 1], reference.velocities[-1, 1]]
        assert [row[f"disc.{name}"] for name in STATE] == pytest.approx(final, abs=1e-12)
        drift = reference.energy[-1] - reference.energy[0]
        assert row["energy_drift"] == pytest.approx(drift, abs=1e-10)
        assert row["max_penetration"] == pytest.approx(reference.max_penetration, abs=1e-12)
        assert row["t_end"] == pytest.approx(0.2, abs=1e-12) and row["error"] == ""
        saved = np.load(out / "runs" / f"run-{r:06d}.npz")
        np.testing.assert_allclose(saved["poses"], reference.poses, rtol=0, atol=1e-12)
        np.testing.assert_allclose(saved["energy"], reference.energy, rtol=0, atol=1e-10)
        assert (np.max(reference.velocities[:, 1, 1]) > 0.1) == (e > 0)  # landed, bounced


def test_a_failed_chunk_stops_the_sweep_and_the_same_command_resumes_it(
    tmp_path, scene_path, in_process, monkeypatch, capsys
):
    original, broken = sweep_chunk.run_chunk, [True]

    def flaky(scene, variations, options):
        if broken[0] and abs(variations["disc.position[0]"][0]) < 0.1:  # the second chunk
            raise RuntimeError("injected")
        return original(scene, variations, options)

    monkeypatch.setattr(sweep_chunk, "run_chunk", flaky)
    out = tmp_path / "sweep"
    assert run(scene_path, out, in_process) == 1
    assert "error: chunk 1 (runs 3-5) failed: injected" in capsys.readouterr().err
    chunks = out / "chunks"
    first = (chunks / "chunk-00000.parquet").stat()
    assert not (chunks / "chunk-00001.parquet").exists() and not (out / "table.parquet").exists()
    done_before = sorted(p.name for p in chunks.iterdir())
    broken[0] = False
    assert run(scene_path, out, in_process) == 0
    captured = capsys.readouterr()
    assert f"resuming: {len(done_before)} of 3 chunks are done" in captured.err
    assert f"({3 - len(done_before)} of 3 chunks run now)" in captured.out  # only those missing
    assert (chunks / "chunk-00000.parquet").stat().st_mtime_ns == first.st_mtime_ns
    fresh = tmp_path / "fresh"
    assert run(scene_path, fresh, in_process) == 0
    drop = {"wall_time"}
    assert [{k: v for k, v in r.items() if k not in drop} for r in table(out)] == [
        {k: v for k, v in r.items() if k not in drop} for r in table(fresh)
    ]
    assert not list(out.rglob(".*.tmp-*"))


def test_force_rules(tmp_path, scene_path, in_process, capsys):
    out = tmp_path / "sweep"
    assert run(scene_path, out, in_process) == 0
    written = (out / "table.parquet").stat().st_mtime_ns
    assert run(scene_path, out, in_process) == 2
    assert "holds this sweep, finished; use --force to run it again" in capsys.readouterr().err
    assert run(scene_path, out, in_process, "--duration", "0.1") == 2
    assert "holds another sweep (its duration is 0.2, this one's 0.1)" in capsys.readouterr().err
    assert run(scene_path, out, in_process, "--force") == 0
    assert (out / "table.parquet").stat().st_mtime_ns != written
    other = tmp_path / "notes"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    assert run(scene_path, other, in_process) == 2
    assert "is not empty and holds no sweep; use --force" in capsys.readouterr().err
    assert run(scene_path, other, in_process, "--force") == 0
    assert (other / "notes.txt").read_text() == "mine" and len(table(other)) == 8
    lock = FolderLock(out, "sweep")
    lock.acquire()
    try:
        assert run(scene_path, out, in_process, "--force") == 2
        assert "is in use by another sweep" in capsys.readouterr().err
    finally:
        lock.release()


@pytest.mark.parametrize(
    ("args", "words"),
    [
        (["--vary", "disc.mass"], "--vary 'disc.mass': expected KEY=VALUES"),
        (["--vary", "disc.mass=linspace(1,2)"], "values are a list 'a,b,c' or 'linspace(start,stop,count)'"),
        (["--vary", "disc.mass=linspace(1,2,0)"], "linspace's count must be a whole number from 1"),
        (["--vary", "disc.mass=1,,2"], "'' is not a number"),
        (["--vary", "disc.position=1,2"], "position is a vector: vary one component at a time"),
        (["--vary", "disk.mass=1"], "no body named 'disk'; bodies: bowl, disc"),
        (["--vary", "disc.restitution=0.5,1.5"], "value 1.5: must be between 0 and 1"),
        (["--vary", "disc.mass=1", "--vary", "disc.mass=2"], "disc.mass is varied twice"),
        ([], "give at least one --vary"),
        (["--vary", "disc.mass=1", "--workers", "0"], "--workers must be a whole number from 1"),
        (["--vary", "disc.mass=1", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"], "--workers is for the local cluster"),
        (["--vary", "disc.mass=1", "--method", "rk45"], "--method 'rk45': a sweep runs ensembles"),
        (["--vary", "disc.mass=1", "--record-every", "0"], "--record-every must be a whole number >= 1"),
        (["--vary", "disc.mass=1,2", "--chunk", "3"], "--chunk must be a whole number from 1 to 2"),
        (["--vary", "disc.mass=1", "--dt", "1"], "--dt 1 s is longer than the duration 0.2 s"),
    ],
)  # fmt: skip
def test_bad_input_is_one_line_and_status_2(tmp_path, scene_path, capsys, args, words):
    out = tmp_path / "sweep"
    assert sweep.main([str(scene_path), *args, "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert re.search(re.escape(words), err) and len(err.strip().splitlines()) == 1
    assert not out.exists()  # checked before anything is written
