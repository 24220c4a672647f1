"""The ``sweep`` command: a scene run over a grid of parameters, as ensembles on Dask workers.

    sweep scenes/disc_in_bowl.toml --vary "disc.position[0]=linspace(-0.5,0.5,1000)" \\
          --vary "disc.restitution=0.2,0.5" --duration 2 --out out/bowl-sweep
    python -m runtime.app.sweep ...                      # the same
    sweep ... --scheduler tcp://host:8786                # on a running Dask cluster
    sweep ... --workers 4                                # local worker processes (default: cores)

Why Dask: a sweep of thousands of runs outgrows one process; Dask's distributed scheduler
runs the chunks on local processes (a LocalCluster on 127.0.0.1) or on any cluster, with the
same code. Each chunk is one ensemble (runtime.simulate_ensemble: its copies share every step's
cost); the client writes each finished chunk into DIR at once (runtime.app.sweep_store), so an
interrupted sweep resumes when the same command is run again, and a finished DIR needs --force.

Bad input (a --vary, a number, the scene, DIR) is one line on stderr, exit status 2, before any
worker starts; runs that fail (runtime.SimulationError) are rows with their error, not a
failure of the sweep; a chunk that raises stops the sweep (exit 1; its finished chunks stay);
Ctrl-C or SIGTERM exit 130 / 143 and keep the finished chunks.
"""

from __future__ import annotations

import argparse
import logging
import os
import signal
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from runtime.app.cli import (
    INTERRUPTIBLE,
    Terminated,
    UsageError,
    _guard_limit,
    _load,
    _number,
    _Parser,
    _say,
    interrupted,
)

PROG = "sweep"
__all__ = ["main"]


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog=PROG,
        description="Run a scene over every combination of --vary values, in chunks on Dask "
        "workers, and write table.parquet, table.csv and each run's trajectory into --out DIR.",
    )
    add = parser.add_argument
    add("scene", metavar="SCENE.toml", help="scene file (docs/scene-format.md)")
    add("--vary", metavar="KEY=VALUES", action="append", default=[],
        help="a body field or scene.gravity[i] and its values: 'a,b,c' or "
        "'linspace(start,stop,count)'; repeat for a grid, e.g. disc.restitution=0.2,0.5")  # fmt: skip
    add("--out", metavar="DIR", required=True, help="output directory")
    add("--duration", metavar="S", help="simulated time in s (default: the scene's)")
    add("--dt", metavar="S", help="time step in s (default: the scene's)")
    add("--method", metavar="euler|midpoint|rk4", help="integrator (default: the scene's)")
    add("--record-every", metavar="K", default="1", help="record every K-th step (default 1)")
    add("--max-penetration", metavar="X|off", default="0.01", help="as simulate's")
    add("--max-energy-growth", metavar="X|off", default="0.5", help="as simulate's")
    add("--scheduler", metavar="ADDRESS", help="a Dask scheduler, e.g. tcp://host:8786 "
        "(default: a local cluster)")  # fmt: skip
    add("--workers", metavar="N", help="local worker processes (default: the cores)")
    add("--chunk", metavar="N", help="runs per chunk (default: about 1/16 of the grid)")
    add("--force", action="store_true", help="replace a sweep (or other files) in DIR")
    add("--quiet", action="store_true", help="no progress bar")
    return parser


def _options(args: argparse.Namespace, scene) -> dict[str, Any]:
    """simulate_ensemble's options from the command line, checked."""
    import runtime
    from runtime.app.cli import TIME_RANGE
    from runtime.step.integrators import FIXED_STEP

    duration = (
        scene.simulation.duration
        if args.duration is None
        else _number("--duration", args.duration, *TIME_RANGE, " s")
    )
    dt = scene.simulation.dt if args.dt is None else _number("--dt", args.dt, *TIME_RANGE, " s")
    if dt > duration:
        raise UsageError(f"--dt {dt:g} s is longer than the duration {duration:g} s")
    method = (scene.simulation.method if args.method is None else args.method).lower()
    if method not in FIXED_STEP:
        raise UsageError(
            f"--method {method!r}: a sweep runs ensembles, which take {', '.join(FIXED_STEP)}"
        )
    every = args.record_every
    if not (every.isdigit() and int(every) >= 1):
        raise UsageError(f"--record-every must be a whole number >= 1, got {every!r}")
    guards = runtime.Guards(
        _guard_limit("--max-penetration", args.max_penetration),
        _guard_limit("--max-energy-growth", args.max_energy_growth),
    )
    return {"duration": duration, "dt": dt, "method": method, "record_every": int(every),
            "guards": guards}  # fmt: skip


def _count(flag: str, text: str | None, high: int) -> int | None:
    if text is None:
        return None
    if not (text.isdigit() and 1 <= int(text) <= high):
        raise UsageError(f"{flag} must be a whole number from 1 to {high}, got {text!r}")
    return int(text)


def _client(args: argparse.Namespace, warm_up):
    """A Dask client: of the scheduler at --scheduler, or of a local cluster of --workers
    single-threaded processes on 127.0.0.1 (closed with the client). The local workers are
    forked from this process after ``warm_up()`` (one step of the scene) has compiled the
    engine, so they start with its compiled code instead of each compiling it again."""
    import dask
    from distributed import Client, LocalCluster

    logging.getLogger("distributed").setLevel(logging.ERROR)
    if args.scheduler:
        try:
            return Client(args.scheduler, timeout="10s")
        except (OSError, TimeoutError, ValueError) as exc:
            raise UsageError(f"--scheduler {args.scheduler!r}: cannot connect ({exc})") from None
    workers = args.workers or os.cpu_count() or 1
    warm_up()
    method = "fork" if hasattr(os, "fork") else "spawn"
    with dask.config.set({"distributed.worker.multiprocessing-method": method}):
        cluster = LocalCluster(
            n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
            dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR,
        )  # fmt: skip
    client = Client(cluster)
    client._sweep_cluster = cluster  # closed with the client (see _close)
    return client


def _close(client) -> None:
    cluster = getattr(client, "_sweep_cluster", None)
    client.close()
    if cluster is not None:
        cluster.close()


def run_command(args: argparse.Namespace) -> int:
    """Check everything, run the pending chunks, write the table; the exit status."""
    from runtime.app import sweep_chunk
    from runtime.app.output_dir import OutputError
    from runtime.app.sweep_grid import GridError, default_chunk, make_grid
    from runtime.app.sweep_store import SweepFolder, scene_hash

    scene = _load(args.scene)
    options = _options(args, scene)
    try:
        grid = make_grid(scene, args.vary)
    except GridError as exc:
        raise UsageError(str(exc)) from None
    args.workers = _count("--workers", args.workers, 4096)
    if args.workers and args.scheduler:
        raise UsageError("--workers is for the local cluster; a --scheduler has its own workers")
    chunk = _count("--chunk", args.chunk, grid.runs)
    guards = options["guards"]
    spec = {
        "scene_file": str(args.scene), "scene_sha256": scene_hash(Path(args.scene)),
        "vary": grid.specs, "runs": grid.runs, "chunk": chunk,
        "duration": options["duration"], "dt": options["dt"], "method": options["method"],
        "record_every": options["record_every"],
        "guards": [guards.penetration, guards.energy_growth],
    }  # fmt: skip
    folder = SweepFolder(Path(args.out), spec, force=args.force)
    try:
        done = folder.open(default_chunk(grid.runs))
    except OutputError as exc:
        raise UsageError(str(exc)) from None
    try:
        chunks = grid.chunks(folder.spec["chunk"])
        pending = [c for c in range(len(chunks)) if c not in done]
        if done:
            _say(sys.stderr, PROG, f"resuming: {len(done)} of {len(chunks)} chunks are done")
        start = time.perf_counter()
        failed = _run(args, scene, grid, options, chunks, pending, folder, sweep_chunk)
        rows = folder.finish()
    except KeyboardInterrupt as exc:
        what = "terminated" if isinstance(exc, Terminated) else "interrupted"
        written = len(folder.done_chunks())
        raise type(exc)(
            f"{what}; {written} of {len(grid.chunks(folder.spec['chunk']))} chunks are in "
            f"{args.out!r}: run the same command again to resume"
        ) from None
    finally:
        folder.close()
    errors = f"; {failed} runs failed (see the error column)" if failed else ""
    print(
        f"{PROG}: {rows} runs ({len(pending)} of {len(chunks)} chunks run now) in "
        f"{time.perf_counter() - start:.1f} s{errors} -> {args.out}"
    )
    return 0


def _run(args, scene, grid, options, chunks, pending, folder, sweep_chunk) -> int:
    """The pending chunks on Dask, each written as it finishes; the number of failed runs
    (of this session's chunks)."""
    from distributed import as_completed

    if not pending:
        return 0
    a, b = chunks[pending[0]]
    one_step = {**options, "duration": options["dt"]}
    client = _client(
        args, lambda: sweep_chunk.run_chunk(scene, grid.variations(a, a + 1), one_step)
    )
    bar = None
    try:
        if not args.quiet:
            from tqdm import tqdm

            done_runs = grid.runs - sum(chunks[c][1] - chunks[c][0] for c in pending)
            bar = tqdm(total=grid.runs, initial=done_runs, unit="run", file=sys.stderr)
        shared = client.scatter(scene, broadcast=True)
        futures = {}
        for c in pending:
            a, b = chunks[c]
            future = client.submit(
                sweep_chunk.run_chunk, shared, grid.variations(a, b), options, pure=False
            )
            futures[future] = c
        failed = 0
        for future in as_completed(futures):
            c = futures[future]
            try:
                ensemble = future.result()
            except Exception as exc:  # a chunk that raised: stop, keep what is written
                for other in futures:
                    other.cancel()
                a, b = chunks[c]
                _say(sys.stderr, PROG, f"error: chunk {c} (runs {a}-{b - 1}) failed: {exc}")
                raise _ChunkFailed from None
            folder.write_chunk(c, chunks[c][0], grid, ensemble)
            failed += int(sum(1 for e in ensemble.failed if e))
            if bar is not None:
                bar.update(ensemble.copies)
        return failed
    finally:
        if bar is not None:
            bar.close()
        _close(client)


class _ChunkFailed(Exception):
    """A chunk raised (reported already): the sweep stops with status 1."""


def _terminate(_signum: int, _frame: Any) -> None:
    raise Terminated("terminated")


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``sweep`` console script; returns the exit status."""
    try:
        previous = signal.signal(signal.SIGTERM, _terminate)
    except ValueError:  # not the main thread
        previous = None
    try:
        return run_command(_parser().parse_args(argv))
    except UsageError as exc:
        _say(sys.stderr, PROG, f"error: {exc}")
        return 2
    except _ChunkFailed:
        return 1
    except INTERRUPTIBLE as exc:
        return interrupted(exc, PROG)
    finally:
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


if __name__ == "__main__":
    sys.exit(main())
