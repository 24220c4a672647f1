"""The speed targets of issue #12, ours and pymunk side by side in one run (`make bench`).

- disc in a bowl, 10 s at RK4 dt = 0.01: our wall time and angle error against the pendulum
  reference (bench/references.py); pymunk's wall time and error at its best setting for that
  error level (its bowl as 64 chords, dt = 1/600: bench/report.py's sweep finds that point);
- falling piles of 50 and 200 discs (r = 0.05 m, 1 kg, restitution 0) into a 1 m box
  (bench/scenes.py), 1 s at dt = 1 ms, by RK4 with every impact located and by time stepping
  (runtime.step.time_stepping): our wall time, located impacts, deepest penetration (within a
  600 s budget: the time reached); pymunk's wall time for the same discs, box and dt;
- a resting pile of 200 discs (bench/steps.py): steps per second, ours and pymunk's;
- cost per step against the number of contacts over resting piles of 10 to 1,000 contacts:
  the exponent p of time ~ contacts^p.

Wall times are the best of a few runs; the machine and its load are noted. Timings of ours
include everything a step does (contacts, impacts, forces, integration, events, guards).

    python -m bench.targets            # rewrites the "## Targets" section of bench/README.md
    python -m bench.targets --quick    # shorter runs, README untouched
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import math
import os
import time
from pathlib import Path

import numpy as np

import runtime
from bench.machine import cpu
from bench.markdown import replace_section
from bench.scenes import falling_pile
from bench.steps import pile_scene
from runtime.step.collision import Collision
from runtime.step.integrators import TIME_STEPPING

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Targets"
WARM_STEPS = 3  # resting piles: steps before the timed ones -- the first step pivots (no loaded
# set yet: 0.5 s for 200 discs) and loads compiled code, the second is the first on the
# body-space path (runtime.solve.lcp_loaded) and loads its code: steady state from the third


def _best(run, repeats: int) -> tuple[float, object]:
    best, out = math.inf, None
    for _ in range(repeats):
        start = time.perf_counter()
        out = run()
        best = min(best, time.perf_counter() - start)
    return best, out


def bowl(quick: bool) -> dict:
    """Disc in the bowl, 10 s at RK4 dt = 0.01, against the exact pendulum."""
    from bench.references import BowlReference

    scene = runtime.load_scene(ROOT / "scenes" / "disc_in_bowl.toml")
    duration, dt = (2.0 if quick else 10.0), 0.01
    runtime.simulate(scene, duration=0.05, dt=dt)  # compiled code loaded
    wall, run = _best(lambda: runtime.simulate(scene, duration=duration, dt=dt), 3)
    reference = BowlReference(scene, duration)
    disc = scene.index("disc")
    angle = np.arctan2(run.poses[:, disc, 0], -run.poses[:, disc, 1])
    phi = reference.solution.sol(run.t)[0]
    error = float(np.max(np.abs(angle - phi)))
    return {"scene": "disc in a bowl", "duration": duration, "dt": dt, "wall": wall,
            "steps": len(run.t) - 1, "error": error}  # fmt: skip


def _pymunk_pile(scene, dt: float, steps: int) -> float:
    """Wall time of `steps` pymunk steps of a scene of discs in a box (friction 0)."""
    import pymunk

    space = pymunk.Space()
    space.gravity = tuple(scene.gravity)
    space.collision_slop = 1e-4
    for body in scene.bodies:
        if body.fixed:
            x, y = body.position
            for edge in body.shape.edges:
                a = (x + edge.start[0], y + edge.start[1])
                b = (x + edge.end[0], y + edge.end[1])
                seg = pymunk.Segment(space.static_body, a, b, 0.0)
                seg.friction, seg.elasticity = 0.0, 0.0
                space.add(seg)
            continue
        radius = body.shape.edges[0].radius
        pb = pymunk.Body(body.mass, body.inertia)
        pb.position, pb.velocity = body.position, body.velocity
        circle = pymunk.Circle(pb, radius)
        circle.friction, circle.elasticity = 0.0, body.restitution
        space.add(pb, circle)
    start = time.perf_counter()
    for _ in range(steps):
        space.step(dt)
    return time.perf_counter() - start


def falling(n: int, quick: bool, budget: float = math.inf, method: str = "rk4") -> dict:
    """The pile stepped by runtime.World with ``method`` for its duration, or until ``budget``
    seconds of wall time have gone (then the simulated time reached is reported). The poses
    every 10 steps are kept, and their deepest overlap is found afterwards by the contact
    finder, outside the timing (until session 27 the World's contacts were asked inside it,
    which solves the frame's forces: a cost of the look, not of the steps)."""
    scene = falling_pile(n)
    duration, dt = (0.3 if quick else 1.0), 1e-3
    steps = int(round(duration / dt))
    runtime.simulate(falling_pile(20, seed=2), duration=0.5, dt=dt, method=method)  # code loaded
    world = runtime.World(scene, method)
    error, impacts, done, looks = "", 0, 0, []
    start = time.perf_counter()
    try:
        while done < steps and time.perf_counter() - start < budget:
            impacts += len(world.step(dt).impact_times)
            done += 1
            if done % 10 == 0:
                looks.append(world.poses.copy())
    except runtime.SimulationError as exc:
        error = str(exc)
    wall = time.perf_counter() - start
    theirs = min(_pymunk_pile(scene, dt, steps) for _ in range(3))
    return {"scene": f"falling pile of {n} discs", "duration": duration, "dt": dt, "wall": wall,
            "reached": done * dt, "pymunk": theirs, "impacts": impacts, "method": method,
            "penetration": _deepest(scene, looks), "error": error}  # fmt: skip


def _deepest(scene, poses: list[np.ndarray]) -> float:
    """The deepest overlap (m, >= 0) of any touching pair at any of the poses, by the contact
    finder with no margin."""
    finder = Collision(scene)
    depth = 0.0
    for q in poses:
        contacts = finder.swept(q, np.zeros(len(q)), None)
        if len(contacts):
            depth = max(depth, -float(contacts.gap.min()))
    return depth


def resting(n: int, steps: int) -> dict:
    scene = pile_scene(n, gap=0.0)  # packed wall to wall: at rest (bench/steps.py)
    world = runtime.World(scene)
    for _ in range(WARM_STEPS):
        world.step(1e-3)
    start = time.perf_counter()
    for _ in range(steps):
        report = world.step(1e-3)
    wall = time.perf_counter() - start
    theirs = min(_pymunk_pile(scene, 1e-3, 10 * steps) for _ in range(3)) / 10
    contacts = len(report.recorded)
    return {"discs": n, "contacts": contacts, "per_step": wall / steps, "pymunk": theirs / steps}


def growth(sizes: tuple[int, ...], steps: int) -> tuple[list[dict], float]:
    rows = [resting(n, steps) for n in sizes]
    c = np.log([r["contacts"] for r in rows])
    t = np.log([r["per_step"] for r in rows])
    return rows, float(np.polyfit(c, t, 1)[0])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    if importlib.util.find_spec("pymunk") is None:  # the figures are ratios to pymunk's
        parser.error("pymunk is needed: pip install -e '.[peers]' (make bench installs it)")
    load = os.getloadavg()[0]
    started = time.perf_counter()
    b = bowl(args.quick)
    piles = [falling(50, args.quick)] + ([] if args.quick else [falling(200, False, 600.0)])
    piles += [
        min(
            (falling(50, args.quick, 600.0, TIME_STEPPING) for _ in range(3)),
            key=lambda r: r["wall"],
        ),
        falling(200, args.quick, 600.0, TIME_STEPPING),
    ]
    sizes = (5, 20, 50, 200) if args.quick else (5, 10, 20, 50, 100, 200, 500)
    rows, exponent = growth(sizes, 5 if args.quick else 50)
    rest200 = next((r for r in rows if r["discs"] == 200), rows[-1])
    lines = [
        SECTION,
        "",
        f"Run {datetime.datetime.now(datetime.UTC):%Y-%m-%d %H:%M} UTC on {cpu()}; 1-minute load "
        f"{load:.1f} before, {os.getloadavg()[0]:.1f} after; {time.perf_counter() - started:.0f} s. "
        "Written by `python -m bench.targets` (`make bench`). Best of 3 runs where repeated.",
        "",
        "| target | ours | pymunk | ratio | goal |",
        "|---|---|---|---|---|",
        f"| disc in a bowl, {b['duration']:g} s, RK4 dt = {b['dt']:g} | {1e3 * b['wall']:.1f} ms "
        f"({1e6 * b['wall'] / b['steps']:.0f} µs/step), angle error {b['error']:.1g} rad | "
        "its best error, 0.022 rad, in 14 ms (issue #12; bench/report.py) | "
        f"{b['wall'] / 0.014:.2g}x | <= 30 ms, error <= 1e-7 rad |",
    ]
    for p in piles:
        status = "ok" if not p["error"] else f"FAILED: {p['error'][:80]}"
        if not p["error"] and p["reached"] < p["duration"] - 1e-9:
            status = f"stopped at t = {p['reached']:g} s (a {p['wall']:.0f} s budget)"
        impacts = "" if p["method"] == TIME_STEPPING else f"{p['impacts']} impacts, "
        lines.append(
            f"| {p['scene']}, {p['duration']:g} s at dt = 1 ms, {p['method']} | {p['wall']:.2f} s, "
            f"{impacts}penetration {p['penetration']:.1g} m, {status} | "
            f"{1e3 * p['pymunk']:.0f} ms | {p['wall'] / p['pymunk']:.0f}x | <= 30x, no failure, "
            "penetration <= 1e-9 m |"
        )
    lines.append(
        f"| resting pile of {rest200['discs']} discs ({rest200['contacts']} contacts) | "
        f"{1 / rest200['per_step']:.0f} steps/s | {1 / rest200['pymunk']:.0f} steps/s | "
        f"{rest200['pymunk'] / rest200['per_step']:.2g}x | >= 200 steps/s |"
    )
    lines += [
        "",
        f"Cost per step against contacts (resting piles, RK4 dt = 1 ms): exponent p = "
        f"{exponent:.2f} (goal <= 1.2).",
        "",
        "| discs | contacts | ours ms/step | pymunk ms/step |",
        "|---|---|---|---|",
        *(
            f"| {r['discs']} | {r['contacts']} | {1e3 * r['per_step']:.3f} | "
            f"{1e3 * r['pymunk']:.3f} |"
            for r in rows
        ),  # fmt: skip
    ]
    text = "\n".join(lines)
    print(text)
    if not args.quick:
        replace_section(README, SECTION, text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
