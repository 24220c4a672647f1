"""Ensembles and sweeps (`make bench`): time per copy per step of 10,000 disc-in-a-bowl copies,
their error against the exact pendulum, where the step's time goes, and a sweep's speed-up on
two local Dask workers.

- 10,000 copies of scenes/disc_in_bowl.toml, start angles evenly from -0.5 to 0.5 rad, 1 s at
  RK4 dt = 1 ms as one `runtime.simulate_ensemble` (recorded every 10 steps): wall time per copy
  per step (after a warm-up that compiles), and each copy's largest angle error over the
  records against the exact pendulum of length L = R - r (released from rest at phi0:
  phi(t) = 2 arcsin(k cd(w t | k^2)), k = sin(phi0 / 2), w = sqrt(g / L); checked against
  bench/references.py's DOP853 pendulum on a few copies);
- the same per copy per step for 100 and 1,000 copies (how the cost grows), and one copy alone
  (`runtime.simulate`);
- where a step of 10,000 copies goes, stage by stage (cProfile: it inflates Python-level calls,
  so the shares matter more than the sum);
- a sweep of 200 runs (the bowl's disc dropped from 100 x positions, restitution 0 and 0.5, 1 s)
  with the `sweep` command on 1 and on 2 local worker processes: wall time, speed-up.

    python -m bench.ensemble            # rewrites the "## Ensemble" section of bench/README.md
    python -m bench.ensemble --quick    # small sizes, README untouched (smoke test)
"""

from __future__ import annotations

import argparse
import cProfile
import datetime
import math
import os
import platform
import pstats
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.special import ellipj

import runtime
import runtime.settings
from bench.machine import cpu
from bench.markdown import replace_section
from bench.references import BowlReference

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Ensemble"
SCENE = ROOT / "scenes" / "disc_in_bowl.toml"
DT, METHOD = 1e-3, "rk4"
EVERY = 10  # record every 10th step: 10,000 copies x 101 records x 2 bodies is 100 MB


def stages() -> list[tuple[str, tuple]]:
    """(label, the functions whose cumulative times it sums; a string: a compiled function's
    name as the profiler shows it)."""
    from runtime.collide.finder import ContactFinder
    from runtime.solve.forces import ContactForces
    from runtime.step import classify, ensemble, resting
    from runtime.step.copy_guards import CopyGuards
    from runtime.step.events import EventSearch
    from runtime.step.stepper import Stepper

    return [
        ("the engine's step (Stepper.step), all of it", (Stepper.step,)),
        ("stages 1-4: contacts, classify, impacts, settle, forces (Stepper.settled_frame)",
         (Stepper.settled_frame,)),
        ("&nbsp;&nbsp;contacts (ContactFinder.find)", (ContactFinder.find,)),
        ("&nbsp;&nbsp;the compiled frame (compiled_frame.settle_frame)",
         ("compiled_frame.settle_frame",)),
        ("&nbsp;&nbsp;or by the general path: classify + impacts (make_frame)",
         (classify.make_frame,)),
        ("&nbsp;&nbsp;and settle + its force solves (resting.settle)", (resting.settle,)),
        ("&nbsp;&nbsp;&nbsp;&nbsp;of which ForceProblem: contact keys, warm-start guesses",
         (ContactForces.problem,)),
        ("remember the resting set (Stepper._hold)", (Stepper._hold,)),
        ("integrate: compiled RK4 with the island LCPs", ("compiled_stages.step",)),
        ("events (EventSearch.first)", (EventSearch.first,)),
        ("ensemble: per-copy guards and energy",
         (CopyGuards.overlaps, CopyGuards.after_step, CopyGuards.energy)),
        ("ensemble: records", (ensemble._Recorder.add,)),
    ]  # fmt: skip


def start_angles(n: int) -> np.ndarray:
    return np.linspace(-0.5, 0.5, n)


def bowl_ensemble(n: int, duration: float, every: int = EVERY):
    """(ensemble, wall seconds) of n copies released from rest at start_angles(n)."""
    scene = runtime.load_scene(SCENE)
    phi = start_angles(n)
    start = {"disc.position": np.c_[0.9 * np.sin(phi), -0.9 * np.cos(phi)]}
    begin = time.perf_counter()
    ensemble = runtime.simulate_ensemble(scene, start, duration, DT, METHOD, record_every=every)
    return ensemble, time.perf_counter() - begin


def exact_angle(phi0: np.ndarray, t: np.ndarray, g: float, length: float) -> np.ndarray:
    """(N, K) pendulum angles at times t, released from rest at phi0 (N,)."""
    k = np.sin(0.5 * phi0)[:, None]
    _, cn, dn, _ = ellipj(math.sqrt(g / length) * t[None, :], k * k)
    return 2.0 * np.arcsin(k * cn / dn)


def angle_errors(ensemble) -> np.ndarray:
    """(N,) largest |angle - exact| over each copy's records (rad)."""
    scene = runtime.load_scene(SCENE)
    g, length = -scene.gravity[1], 1.0 - 0.1
    disc = ensemble.poses[:, :, 1, :2]
    angle = np.arctan2(disc[..., 0], -disc[..., 1])
    exact = exact_angle(start_angles(ensemble.copies), ensemble.t, g, length)
    return np.max(np.abs(angle - exact), axis=1)


def check_exact_against_references(ensemble) -> float:
    """Largest difference of the closed form from bench/references.py's DOP853 pendulum on
    five copies (rad): the two references agree."""
    scene = runtime.load_scene(SCENE)
    worst = 0.0
    for c in np.linspace(0, ensemble.copies - 1, 5).astype(int):
        copy = scene.copy()
        phi = start_angles(ensemble.copies)[c]
        copy.body("disc").position = (0.9 * math.sin(phi), -0.9 * math.cos(phi))
        pos, _, _ = BowlReference(copy, float(ensemble.t[-1])).state(ensemble.t)
        reference = np.arctan2(pos[:, 0], -pos[:, 1])
        exact = exact_angle(np.array([phi]), ensemble.t, 9.81, 0.9)[0]
        worst = max(worst, float(np.max(np.abs(reference - exact))))
    return worst


def per_copy_step(n: int, steps: int) -> float:
    """Seconds per copy per step of n copies over ``steps`` steps (best of 2 runs)."""
    return min(bowl_ensemble(n, steps * DT)[1] for _ in range(2)) / (n * steps)


def single_step() -> float:
    """Seconds per step of one copy alone (runtime.simulate, best of 3)."""
    scene = runtime.load_scene(SCENE)
    return min(runtime.simulate(scene, 0.2, DT, METHOD).wall_time for _ in range(3)) / 200


def profile(n: int, steps: int) -> tuple[list[tuple[str, float]], float, float]:
    """[(stage, seconds per step)] of ``steps`` steps of n copies under cProfile, after their
    first two steps (the first solves every island's LCP cold, without a warm start); the
    profiled time per step; and the first step's time (unprofiled)."""
    from runtime.step import ensemble as internals

    scene = runtime.load_scene(SCENE)
    phi = start_angles(n)
    start = {"disc.position": np.c_[0.9 * np.sin(phi), -0.9 * np.cos(phi)]}
    copies = internals.Copies(scene, internals.read_variations(scene, start))
    driver = internals._Driver(
        copies, METHOD, None, runtime.settings.RESTING_SPEED, runtime.Guards()
    )
    driver.start(internals._Recorder(copies, [DT] * (steps + 2), steps))
    begin = time.perf_counter()
    driver.step(0, DT, False)
    first = time.perf_counter() - begin
    driver.step(1, DT, False)
    profiler = cProfile.Profile()
    begin = time.perf_counter()
    profiler.enable()
    for k in range(2, steps + 2):
        driver.step(k, DT, False)
    profiler.disable()
    wall = time.perf_counter() - begin
    table = pstats.Stats(profiler).stats
    out = []
    for label, functions in stages():
        total = 0.0
        for f in functions:
            if isinstance(f, str):
                total += sum(v[3] for (_, _, name), v in table.items() if f in name)
            else:
                code = f.__code__
                found = table.get((code.co_filename, code.co_firstlineno, code.co_name))
                total += found[3] if found else 0.0
        out.append((label, total / steps))
    return out, wall / steps, first


def sweep_time(workers: int, runs: int, duration: float) -> float:
    """Wall seconds of `sweep` on ``workers`` local processes (this process already compiled:
    the workers are forked from it) over ``runs`` runs of the bowl."""
    from runtime.app import sweep

    with tempfile.TemporaryDirectory() as folder:
        args = [str(SCENE), "--vary", f"disc.position[0]=linspace(-0.25,0.25,{runs // 2})",
                "--vary", "disc.restitution=0,0.5", "--duration", str(duration),
                "--out", str(Path(folder) / "sweep"), "--workers", str(workers), "--quiet"]  # fmt: skip
        begin = time.perf_counter()
        if sweep.main(args) != 0:
            raise RuntimeError("the sweep failed")
        return time.perf_counter() - begin


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small sizes; README untouched")
    args = parser.parse_args(argv)
    n, duration = (500, 0.2) if args.quick else (10_000, 1.0)
    wall, load0 = time.perf_counter(), os.getloadavg()[0]
    bowl_ensemble(3, 2 * DT)  # compile first
    ensemble, seconds = bowl_ensemble(n, duration)
    steps = round(duration / DT)
    per = seconds / (n * steps)
    errors = angle_errors(ensemble)
    agree = check_exact_against_references(ensemble)
    failed = int(np.sum(ensemble.failed != ""))
    print(f"{n} copies x {steps} steps: {seconds:.1f} s, {per * 1e6:.2f} us per copy-step; "
          f"angle error max {errors.max():.2e} rad; failed {failed}; refs agree {agree:.1e}")  # fmt: skip
    del ensemble
    growth = [(m, per_copy_step(m, 100)) for m in ((100, 1000) if not args.quick else (100,))]
    growth.append((n, per))
    alone = single_step()
    print("growth", [(m, f"{t * 1e6:.2f} us") for m, t in growth], f"alone {alone * 1e6:.0f} us")
    split, profiled, first = profile(n, 20 if args.quick else 50)
    print(f"first step {first:.2f} s; profiled {profiled * 1e3:.0f} ms per step")
    for label, t in split:
        print(f"  {label}: {t * 1e3:.1f} ms per step")
    runs, sweep_duration = (20, 0.2) if args.quick else (200, 1.0)
    times: dict[int, list[float]] = {1: [], 2: []}
    for _ in range(1 if args.quick else 3):  # interleaved: the load of the others changes
        for workers in (1, 2):
            times[workers].append(sweep_time(workers, runs, sweep_duration))
    one, two = min(times[1]), min(times[2])
    print(f"sweep of {runs} runs: 1 worker {one:.1f} s, 2 workers {two:.1f} s: {one / two:.2f}x")
    if args.quick:
        return 0
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    us = 1e6
    lines = [
        SECTION,
        "",
        f"Written by `python -m bench.ensemble` (`make bench`); run {stamp} on {cpu()}, Python "
        f"{platform.python_version()}, NumPy {np.__version__}; {time.perf_counter() - wall:.0f} "
        f"s, 1-minute load average {load0:.1f} before, {os.getloadavg()[0]:.1f} after (the 2 "
        "cores are shared: figures are best-of-runs where repeated).",
        "",
        f"**{n:,} disc-in-a-bowl copies**, start angles -0.5 to 0.5 rad, {duration:g} s at RK4 "
        f"dt = 1 ms, one `runtime.simulate_ensemble` (recorded every {EVERY} steps): "
        f"{seconds:.1f} s, **{per * us:.2f} µs per copy per step** (target <= 1 µs; pymunk "
        f"takes 2-3.5 µs for one step of its single-disc bowl); one copy alone "
        f"(`runtime.simulate`) {alone * us:.0f} µs per step. Angle error against the exact "
        f"pendulum, worst copy: **{errors.max():.2e} rad** (median {np.median(errors):.2e}; "
        f"target <= 1e-6), {failed} copies failed; the closed form and bench/references.py's "
        f"DOP853 pendulum agree to {agree:.1e} rad.",
        "",
        "Per copy per step against the number of copies (100 steps, best of 2): "
        + ", ".join(f"{m:,}: {t * us:.2f} µs" for m, t in growth)
        + ".",
        "",
        f"Where a step of {n:,} copies goes, after the first two (cProfile, {profiled * 1e3:.0f} "
        "ms per step under the profiler, which inflates the Python-level rows; cumulative "
        f"times, an indented row is part of the row above). The first step takes {first:.2f} s: "
        "no island has a warm-start guess yet, so each starts from the compiled dense solver "
        "(runtime.solve.lcp_dense) instead of the guess.",
        "",
        "| stage | ms per step | µs per copy-step |",
        "|---|---|---|",
    ]
    for label, t in split:
        lines.append(f"| {label} | {t * 1e3:.1f} | {t / n * us:.2f} |")
    lines += [
        "",
        f"**Sweep** of {runs} runs (the disc dropped from 100 positions x restitution 0, 0.5; "
        f"{sweep_duration:g} s each, 16 chunks) with `sweep` on local worker processes: "
        f"1 worker {one:.1f} s, 2 workers {two:.1f} s: **{one / two:.2f}x** (target >= 1.8x; "
        "wall time of the whole command after this process compiled the engine, so the forked "
        "workers start compiled; best of 3, interleaved: "
        + ", ".join(f"{a:.1f}/{b:.1f} s" for a, b in zip(times[1], times[2], strict=True))
        + "). With the cores shared with other processes (load above), the second worker "
        "gets at best what the others leave of a core.",
    ]
    replace_section(README, SECTION, "\n".join(lines), before="## Report")
    print(f"wrote the {SECTION!r} section of {README}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
