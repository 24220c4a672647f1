"""Contact finding speed: µs per call of the compiled ContactFinder, before/after, and its growth
with the number of bodies (`make bench`).

A step of the engine finds contacts at least once, so this is part of every step's cost. Timed:

- a disc in a bowl (2 bodies), resting piles of discs in a box (bench/steps.py's piles) and
  piles of mixed shapes (polygons, rounded boxes, half discs, D shapes, ellipses) in a box;
- per call: the best of several runs of many calls (`ContactFinder.find` from Python, arrays
  out), and, for comparison, the pure-Python narrow phase it replaced (read from git at BEFORE,
  when git and that commit are at hand);
- `refresh_ovals` on a row of ellipses resting on a floor (the engine calls it per stage);
- the exponent p of time ~ bodies^p over resting piles of 20 to 1000 discs (least squares in
  log-log).

    python -m bench.collide            # rewrites the "## Collide" section of bench/README.md
    python -m bench.collide --quick    # fewer runs, README untouched (smoke test)
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import runtime
from bench.machine import cpu
from bench.markdown import replace_section
from bench.steps import pile_scene

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Collide"
BEFORE = "3a5203e"  # the last commit with the per-pair Python narrow phase
PILES = (20, 50, 100, 200, 500, 1000)  # discs, for the growth exponent
RUN_TIME = 0.05  # s per timed run, about


def best_call_time(call, runs: int) -> float:
    """Best over ``runs`` runs of the mean time per call (each run about RUN_TIME)."""
    call()
    start = time.perf_counter()
    call()
    reps = max(1, int(RUN_TIME / max(time.perf_counter() - start, 1e-7)))
    best = math.inf
    for _ in range(runs):
        start = time.perf_counter()
        for _ in range(reps):
            call()
        best = min(best, (time.perf_counter() - start) / reps)
    return best


def mixed_scene(n: int, seed: int = 1):
    """``n`` bodies of mixed shapes on a grid in a box, turned a little, neighbours a few mm apart
    or touching: many candidate pairs of every case, some contacts (tolerance 5 mm)."""
    rng = np.random.default_rng(seed)
    kinds = [
        {"type": "polygon", "points": [[-0.04, -0.03], [0.045, -0.035], [0.03, 0.04], [-0.035, 0.035]]},
        {"type": "rounded_rect", "width": 0.09, "height": 0.06, "corner_radius": 0.015},
        {"type": "half_disc", "radius": 0.045},
        {"type": "d_shape", "width": 0.08, "height": 0.07},
        {"type": "ellipse", "a": 0.045, "b": 0.03},
        {"type": "disc", "radius": 0.04},
    ]  # fmt: skip
    cols = max(2, int(math.sqrt(n)))
    pitch = 0.092
    bodies = [
        {
            "name": f"b{k:04d}",
            "shape": kinds[k % len(kinds)],
            "density": 1000.0,
            "position": [(k % cols - cols / 2 + 0.5) * pitch, 0.06 + (k // cols) * pitch],
            "angle": float(rng.uniform(-0.2, 0.2)),
        }
        for k in range(n)
    ]
    box = {"name": "box", "fixed": True,
           "shape": {"type": "box_walls", "width": cols * pitch + 0.2, "height": (n // cols + 2) * pitch}}  # fmt: skip
    scene = {"name": f"mixed_{n}", "contact_tolerance": 5e-3, "overlap_tolerance": 5e-3}
    data = {"scene": scene, "body": [box, *bodies]}
    return runtime.scene_from_dict(data, source=f"mixed_{n}")


def oval_row(n: int):
    """``n`` ellipses resting on a floor, each turned a little (contacts on ovals)."""
    bodies = [
        {"name": f"e{k}", "shape": {"type": "ellipse", "a": 0.06, "b": 0.03}, "density": 1000.0,
         "position": [0.2 * k, 0.03], "angle": 0.0}
        for k in range(n)
    ]  # fmt: skip
    floor = {"name": "floor", "fixed": True,
             "shape": {"type": "wall", "start": [-1.0, 0.0], "end": [0.2 * n + 1.0, 0.0]}}  # fmt: skip
    return runtime.scene_from_dict({"scene": {"name": f"ovals_{n}"}, "body": [floor, *bodies]})


def python_narrow_phase():
    """The old ``find_contacts`` (per-pair Python narrow phase) from git at BEFORE, or None."""
    folder = Path(tempfile.mkdtemp(prefix="collide-before-"))
    try:
        for name in ("narrowphase", "contacts"):
            text = subprocess.run(
                ["git", "show", f"{BEFORE}:runtime/collide/{name}.py"],
                cwd=ROOT, capture_output=True, text=True, check=True,
            ).stdout  # fmt: skip
            text = text.replace(
                "from runtime.collide import narrowphase",
                "import before_narrowphase as narrowphase",
            )
            (folder / f"before_{name}.py").write_text(text)
    except (OSError, subprocess.CalledProcessError):
        return None
    sys.path.insert(0, str(folder))
    spec = importlib.util.spec_from_file_location("before_contacts", folder / "before_contacts.py")
    module = sys.modules["before_contacts"] = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.find_contacts


def measure(scene, runs: int, before) -> dict:
    finder, poses, tol = scene.contact_finder(), scene.poses(), scene.contact_tolerance
    row = {
        "scene": scene.name,
        "bodies": len(scene.bodies),
        "contacts": len(finder.find(poses, tol)),
        "find": best_call_time(lambda: finder.find(poses, tol), runs),
    }
    if before is not None:
        shapes, fixed = scene.shapes, scene.fixed
        row["before"] = best_call_time(lambda: before(shapes, poses, fixed, tol), max(2, runs // 3))
    return row


def us(seconds: float) -> str:
    return f"{seconds * 1e6:.3g}"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer runs; README untouched")
    args = parser.parse_args(argv)
    runs = 3 if args.quick else 9
    wall, load0 = time.perf_counter(), os.getloadavg()[0]
    before = None if args.quick else python_narrow_phase()
    scenes = [runtime.load_scene(ROOT / "scenes" / "disc_in_bowl.toml"), pile_scene(20),
              pile_scene(200), mixed_scene(20), mixed_scene(200)]  # fmt: skip
    rows = [measure(s, runs, before) for s in scenes]
    for r in rows:
        print(r, flush=True)
    growth = []
    for n in PILES[:3] if args.quick else PILES:
        scene = pile_scene(n)
        finder, poses = scene.contact_finder(), scene.poses()
        growth.append((n + 1, best_call_time(lambda f=finder, p=poses: f.find(p, 1e-4), runs)))
    p = np.polyfit(np.log([g[0] for g in growth]), np.log([g[1] for g in growth]), 1)[0]
    ovals = oval_row(20)
    finder, poses = ovals.contact_finder(), ovals.poses()
    found = finder.find(poses, ovals.contact_tolerance)
    turned = poses + [0.0, 0.0, 0.01]
    refresh = best_call_time(lambda: finder.refresh_ovals(turned, found), runs)
    print(f"growth {growth}, p = {p:.2f}; refresh_ovals {us(refresh)} us for {len(found)}")
    if args.quick:
        return 0
    stamp = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    lines = [
        SECTION,
        "",
        f"Written by `python -m bench.collide` (`make bench`); run {stamp} on {cpu()}, Python "
        f"{platform.python_version()}, NumPy {np.__version__}; {time.perf_counter() - wall:.0f} s, "
        f"1-minute load average {load0:.1f} before, {os.getloadavg()[0]:.1f} after (other "
        "processes share the cores: figures are best-of-runs).",
        "",
        "µs per call from Python at the scene's initial poses and contact tolerance. *find*: "
        "`ContactFinder.find` (compiled broad phase, candidates, generated kernels' gaps, "
        "selection; arrays out). "
        f"*before*: the per-pair Python narrow phase it replaced (git {BEFORE}), same poses.",
        "",
        "| scene | bodies | contacts | find µs | before µs | before / find |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        b = r.get("before")
        ratio = f"{b / r['find']:.0f}×" if b else "–"
        lines.append(f"| {r['scene']} | {r['bodies']} | {r['contacts']} | {us(r['find'])} | "
                     f"{us(b) if b else '–'} | {ratio} |")  # fmt: skip
    lines += [
        "",
        "Growth over resting piles (bodies: µs per find): "
        + ", ".join(f"{n}: {us(t)}" for n, t in growth)
        + f"; time ~ bodies^p with **p = {p:.2f}** (least squares in log-log).",
        "",
        f"`refresh_ovals` (osculating circles found again after a turn of 0.01 rad): "
        f"{us(refresh)} µs per call for {len(found)} contacts on ellipses.",
    ]
    replace_section(README, SECTION, "\n".join(lines), before="## Steps")
    print(f"wrote the {SECTION!r} section of {README}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
