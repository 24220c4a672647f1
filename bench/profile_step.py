"""Where a step's time goes, stage by stage, for 1, 10, 50 and 200 bodies (issue #12, item 1).

The piles of 50 and 200 are packed wall to wall, at rest (bench/steps.py, gap = 0); the 50 discs
are also timed late in their fall (t = 0.8-0.9 s), where the falling-pile target spends its time.

Each scene is stepped by runtime.World after a warm-up (compiled code loaded, warm starts
built), under cProfile; the cumulative time of each stage function of the step pipeline
(runtime/step/stepper.py) is divided by the steps. The stages nest: "frame" (stages 1-4:
contacts, classify, impacts, settle, resting forces) holds the compiled frame or the general
path's parts; "integrate" the compiled RK step or the Python integrator with its force
solves; "events" the search for the first impact; what is left is the World's own work
(guards, energy, angle wrap) and Python glue. cProfile inflates the Python-level rows; the
unprofiled time per step is given beside them.

The "before" table (the engine before issue #12, commit 3e92813: Python per contact, per
pair) was measured by module in the same way and is kept in bench/profile_before.md.

    python -m bench.profile_step          # writes the "## Where a step goes" section
    python -m bench.profile_step --quick  # fewer steps, README untouched
"""

from __future__ import annotations

import argparse
import cProfile
import datetime
import os
import pstats
import time
from pathlib import Path

import runtime
from bench.machine import cpu
from bench.markdown import replace_section
from bench.scenes import falling_pile
from bench.steps import pile_scene

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Where a step goes"

# (label, function names as "file:function" suffixes, cumulative)
STAGES = [
    ("frame: contacts, classify, impacts, settle, forces", ("stepper.py:settled_frame",)),
    ("&nbsp;&nbsp;of which the compiled frame", ("settle_frame",)),
    ("&nbsp;&nbsp;of which the general path's settle rounds", ("resting.py:settle",)),
    ("integrate (trial step and trial times)", ("integrators.py:_integrate",)),
    ("events: the first impact of each island", ("events.py:first",)),
    ("contact forces by the general path (in the frame and the stages)", ("forces.py:solve",)),
]


def scenes(quick: bool) -> list[tuple[str, object, int, int]]:
    """(label, scene, warm-up steps, timed steps)."""
    bowl = runtime.load_scene(ROOT / "scenes" / "disc_in_bowl.toml")
    few = 20 if quick else 100
    return [
        ("1 body: disc in a bowl", bowl, 20, 5 * few),
        ("10 bodies: falling pile (t = 0.2-0.3 s)", falling_pile(10), 200, few),
        ("50 bodies: falling pile (t = 0.8-0.9 s)", falling_pile(50), 800, few),
        ("50 bodies: resting pile, packed", pile_scene(50, gap=0.0), 5, few),
        ("200 bodies: resting pile, packed", pile_scene(200, gap=0.0), 5, few // 2),
    ]


def _stage_times(stats: pstats.Stats, steps: int) -> dict[str, float]:
    out = {}
    for label, names in STAGES:
        total = 0.0
        for (path, _line, func), (_cc, _nc, _tt, ct, _callers) in stats.stats.items():
            where = f"{Path(path).name}:{func}"
            if any(where.endswith(n) or (":" not in n and n in func) for n in names):
                total += ct
        out[label] = total / steps
    return out


def profile(scene, warm: int, steps: int, dt: float) -> tuple[float, float, dict[str, float]]:
    """(unprofiled s/step, profiled s/step, {stage: s/step}): the same steps twice, from two
    worlds warmed up alike (a pile's later steps cost more or less than its earlier ones)."""
    times, profiler = [], cProfile.Profile()
    for profiled in (False, True):
        world = runtime.World(scene)
        for _ in range(warm):
            world.step(dt)
        start = time.perf_counter()
        if profiled:
            profiler.enable()
        for _ in range(steps):
            world.step(dt)
        profiler.disable()
        times.append((time.perf_counter() - start) / steps)
    return times[0], times[1], _stage_times(pstats.Stats(profiler), steps)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    load = os.getloadavg()[0]
    rows = []
    for label, scene, warm, steps in scenes(args.quick):
        dt = 0.01 if "bowl" in label else 1e-3
        plain, profiled, stages = profile(scene, warm, steps, dt)
        rows.append((label, dt, plain, profiled, stages))
    head = "| stage (ms per step, under cProfile) | " + " | ".join(r[0] for r in rows) + " |"
    lines = [
        SECTION,
        "",
        f"Written by `python -m bench.profile_step` (`make bench`); run "
        f"{datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC on {cpu()}; 1-minute load "
        f"{load:.1f} before, {os.getloadavg()[0]:.1f} after (the cores are shared). RK4; the "
        "bowl at dt = 0.01 s, the piles at 1 ms. See the module docstring for what each stage "
        "holds; the stages nest, so the rows do not add up.",
        "",
        head,
        "|---|" + "---|" * len(rows),
        "| **whole step, unprofiled** | "
        + " | ".join(f"**{1e3 * r[2]:.3g}**" for r in rows)
        + " |",
        "| whole step, under cProfile | " + " | ".join(f"{1e3 * r[3]:.3g}" for r in rows) + " |",
    ]
    for label, _names in STAGES:
        lines.append(f"| {label} | " + " | ".join(f"{1e3 * r[4][label]:.3g}" for r in rows) + " |")
    lines += [
        "",
        "Before (the engine at commit 3e92813, Python per contact and per pair; the same "
        "scenes, by module, bench/profile_before.md), unprofiled: disc in a bowl 0.64 ms per "
        "step, falling pile of 10 3.6 ms, resting pile of 50 3.5 ms, resting pile of 200 65 ms "
        "(those two piles were the gapped ones, which are not at rest, in their first steps; the "
        "packed piles cost 13.5 ms and 1,231 ms a step before session 12's solver fixes). "
        "The time went to runtime/kernels.py (the kernels called per contact from Python: "
        "17-41 %), NumPy/SciPy calls on tiny arrays (18-27 %), the narrow phase per pair "
        "(2-12 %) and the LCP (2-9 %).",
    ]
    text = "\n".join(lines)
    print(text)
    if not args.quick:
        replace_section(README, SECTION, text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
