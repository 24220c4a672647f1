"""Settling runs: the disc pile and the rounded stack, until everything rests.

Why this script exists: CI (tests/runtime/test_collisions.py) runs only short pieces of these
scenes. Settling 20 discs in a box takes thousands of impacts, each located in time and
resolved, which is minutes on a small machine. This runs each scene step by step until every
body has been slower than ``--rest-speed`` for ``--rest-time`` seconds (but at least the scene's
duration, or ``--min-time``; at most ``--max-time``) and reports what the issue asks for: steps per second, impacts, the deepest
penetration seen at any step start, the largest speed at the end and when the scene came to rest.

    .venv/bin/python -m bench.settle                        # both scenes
    .venv/bin/python -m bench.settle --scene disc_pile --max-time 4 --json settle.json
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

import runtime

ROOT = Path(__file__).resolve().parents[1]
SCENES = ("disc_pile", "rounded_stack")


def settle(
    name: str,
    max_time: float,
    rest_speed: float,
    rest_time: float,
    progress: bool = True,
    min_time: float | None = None,
) -> dict:
    """Run one scene until it rests (but at least ``min_time``, default the scene's duration)."""
    scene = runtime.load_scene(ROOT / "scenes" / f"{name}.toml")
    min_time = scene.simulation.duration if min_time is None else min_time
    dt = scene.simulation.dt
    world = runtime.World(scene, scene.simulation.method)
    penetration, still_since, rest_at = 0.0, None, None
    steps = int(round(max_time / dt))
    start = time.perf_counter()
    for k in range(steps):
        report = world.step(dt)
        resting = report.recorded
        penetration = max(penetration, -report.frame.min_gap)
        vel = world.velocities
        t = (k + 1) * dt
        speed = float(np.max(np.abs(vel)))
        if speed < rest_speed:
            still_since = t if still_since is None else still_since
            if t - still_since >= rest_time:
                rest_at = still_since
                if t >= min_time:
                    break
        else:
            still_since = rest_at = None
        if progress and k % 100 == 0:
            wall = time.perf_counter() - start
            print(f"  {name} t = {t:.3f} s  max |v| = {speed:.3g}  impacts = "
                  f"{len(world.impact_times)}  resting = {len(resting)}  wall = {wall:.1f} s",
                  file=sys.stderr, flush=True)  # fmt: skip
    wall = time.perf_counter() - start
    done = k + 1
    return {
        "scene": name,
        "dt": dt,
        "simulated_s": done * dt,
        "steps": done,
        "wall_s": wall,
        "steps_per_s": done / wall,
        "impacts": len(world.impact_times),
        "max_penetration_m": penetration,
        "final_max_speed": float(np.max(np.abs(vel))),
        "rest_at_s": rest_at,
    }


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--scene", choices=SCENES, action="append")
    parser.add_argument("--max-time", type=float, default=5.0, help="simulated seconds at most")
    parser.add_argument("--rest-speed", type=float, default=1e-9, help="m/s (and rad/s)")
    parser.add_argument("--rest-time", type=float, default=0.1, help="s below rest speed")
    parser.add_argument("--min-time", type=float, help="s at least (default: the scene's)")
    parser.add_argument("--json", type=Path, help="also write the results here")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)
    results = [
        settle(name, args.max_time, args.rest_speed, args.rest_time, not args.quiet, args.min_time)
        for name in args.scene or SCENES
    ]
    for r in results:
        rest = "not at rest" if r["rest_at_s"] is None else f"at rest from {r['rest_at_s']:.3f} s"
        print(f"{r['scene']}: {r['simulated_s']:.3f} s simulated in {r['wall_s']:.1f} s "
              f"({r['steps_per_s']:.1f} steps/s), {r['impacts']} impacts, max penetration "
              f"{r['max_penetration_m']:.3g} m, final max |v| {r['final_max_speed']:.3g}, {rest}")  # fmt: skip
    if args.json:
        args.json.write_text(json.dumps(results, indent=2) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
