"""Long runs: 10^5 steps of the disc in the bowl and of the stack of 5 rounded blocks (RK4, 1 ms).

What is measured, per scene: wall time and steps per second; the drift of the mechanical energy
(largest |E - E0| so far at 10^3, 5*10^3, 10^4, 5*10^4 and 10^5 steps, and the drift per step,
max |E - E0| / (|E0| k)); the largest penetration (-gap of the contacts the engine found at the
start of the recorded steps, `Run.min_gap`, and independently the smallest gap
`Scene.contacts` reports at the recorded poses); NaN, solver failures and impacts. For the
disc in the bowl also the phase error against the exact pendulum of length R - r (solve_ivp,
DOP853, rtol 1e-12); for the stack, how far the blocks crept from their initial poses (they
start exactly at rest on each other).

tests/runtime/test_long_runs.py runs the same scenes for 5*10^3 (bowl) and 10^3 (stack) steps in
CI and asserts the per-step bounds that docs/numerics.md derives from these figures.

    python -m bench.long_runs                  # both scenes, 10^5 steps; adds/refreshes the
                                               # "## Long runs" section of bench/README.md
    python -m bench.long_runs --jobs 2         # the two scenes in two processes
    python -m bench.long_runs --steps 2000 --no-readme   # a quick look, README untouched
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from bench.machine import cpu
from bench.markdown import replace_section

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Long runs"
SCENES = ("disc_in_bowl", "rounded_stack")
STEPS = 100_000
DT = 1e-3
RECORD_EVERY = 20  # the recorded steps sample min_gap and energy; every step would hold 10^5 frames
CHECKPOINTS = (1_000, 5_000, 10_000, 50_000, 100_000)
G = 9.81
# Per-step laws a k + b k^2 (k = step number), asserted at every step by
# tests/runtime/test_long_runs.py and checked here over the 10^5 steps (docs/numerics.md, section 3):
# relative energy drift |E(k) - E(0)| / |E(0)| (+ 4 ulp(E0)), and constraint drift in metres
# (+ 4 ulp(1)): |gap| of the bowl's one contact, the penetration of the stack's contacts.
ENERGY_LAW = {"disc_in_bowl": (2e-15, 1e-18), "rounded_stack": (1e-16, 0.0)}
GAP_LAW = {"disc_in_bowl": (1e-15, 1e-18), "rounded_stack": (1e-17, 5e-22)}
# the stack's blocks creep sideways (a neutral direction): largest |pose - pose0| (m and rad)
# grows like k^3; asserted <= CREEP_LAW k^3 + 4 ulp(1)
CREEP_LAW = 1e-21


def law(coefficients: tuple[float, float], k) -> np.ndarray:
    """a k + b k^2 for the step numbers k."""
    a, b = coefficients
    k = np.asarray(k, dtype=float)
    return a * k + b * k**2


def energy_bound(name: str, energy0: float, k) -> np.ndarray:
    return abs(energy0) * law(ENERGY_LAW[name], k) + 4 * float(np.spacing(abs(energy0)))


def gap_bound(name: str, k) -> np.ndarray:
    return law(GAP_LAW[name], k) + 4 * float(np.spacing(1.0))


def creep_bound(k) -> np.ndarray:
    return CREEP_LAW * np.asarray(k, dtype=float) ** 3 + 4 * float(np.spacing(1.0))


def creep(poses, moving) -> np.ndarray:
    """Largest |pose - pose0| of the moving bodies at each record (x, y in m, angle in rad)."""
    p = np.asarray(poses)[:, moving]
    return np.max(np.abs(p - p[0]), axis=(1, 2))


def constraint_drift(name: str, min_gap) -> np.ndarray:
    """|gap| for the bowl (either way), the penetration for the stack (its largest gap is 0)."""
    gaps = np.asarray(min_gap, dtype=float)
    return np.abs(gaps) if name == "disc_in_bowl" else np.maximum(0.0, -gaps)


def measure(name: str, steps: int = STEPS, dt: float = DT) -> dict:
    """Run one scene for `steps` steps and return its figures (a plain dict, picklable)."""
    if str(ROOT) not in sys.path:
        sys.path.insert(0, str(ROOT))
    import runtime

    scene = runtime.load_scene(ROOT / "scenes" / f"{name}.toml")
    every = max(1, min(RECORD_EVERY, steps // 100))
    failure = None
    try:
        run = runtime.simulate(scene, steps * dt, dt, "rk4", record_every=every)
    except runtime.SimulationError as exc:  # keep what was recorded; the figure says it failed
        run, failure = exc.run, str(exc)
    t = np.asarray(run.t)
    k = np.rint(t / dt).astype(int)  # step index of each record
    energy = np.asarray(run.energy)
    poses = np.asarray(run.poses)
    drift = np.abs(energy - energy[0])
    gaps = np.asarray(run.min_gap)
    independent = min(
        (g for p in run.poses[:: max(1, len(run.poses) // 2000)] for g in scene.contacts(p).gap),
        default=math.inf,
    )
    out = {
        "scene": name,
        "steps": int(k[-1]),
        "dt": dt,
        "record_every": every,
        "wall_time": run.wall_time,
        "steps_per_second": k[-1] / run.wall_time if run.wall_time else math.nan,
        "rhs_evaluations": run.rhs_evaluations,
        "failure": failure,
        "finite": bool(np.all(np.isfinite(poses)) and np.all(np.isfinite(run.velocities))),
        "impacts": len(run.impact_times),
        "energy0": float(energy[0]),
        "max_drift": float(drift.max()),
        "final_drift": float(energy[-1] - energy[0]),
        "drift_per_step": float(np.max(drift[1:] / (abs(energy[0]) * k[1:])))
        if len(k) > 1
        else 0.0,
        "penetration": float(max(0.0, -np.min(gaps))),
        "largest_gap": float(np.max(gaps[np.isfinite(gaps)], initial=-math.inf)),
        "independent_min_gap": float(independent),
        "checkpoints": [
            (c, float(drift[k <= c].max()), float(max(0.0, -np.min(gaps[k <= c]))))
            for c in CHECKPOINTS
            if c <= k[-1]
        ],
    }
    out["energy_law"] = float(np.max(drift / energy_bound(name, energy[0], k)))
    out["gap_law"] = float(np.max(constraint_drift(name, gaps) / gap_bound(name, k)))
    moving = [i for i, b in enumerate(scene.bodies) if not b.fixed]
    if name == "disc_in_bowl":
        from bench.references import BowlReference  # the report's pendulum (solve_ivp)

        reference = BowlReference(scene, float(t[-1]))
        rel = poses[:, scene.index("disc"), :2] - reference.centre
        phi = np.arctan2(rel[:, 0], -rel[:, 1])
        out["phase_error"] = float(np.max(np.abs(phi - reference.solution.sol(t)[0])))
    else:
        out["creep_xy"] = float(np.max(np.abs(poses[:, moving, :2] - poses[0, moving, :2])))
        out["creep_angle"] = float(np.max(np.abs(poses[:, moving, 2] - poses[0, moving, 2])))
        crept = creep(poses, moving)
        out["creep_law"] = float(np.max(crept / creep_bound(k)))
        out["creep_checkpoints"] = [
            (c, float(crept[k <= c].max())) for c in CHECKPOINTS if c <= k[-1]
        ]
    return out


def _machine() -> str:
    return f"{cpu()}; Python {platform.python_version()}, NumPy {np.__version__}"


def report(results: list[dict], elapsed: float, jobs: int, load: tuple[float, float]) -> str:
    date = datetime.datetime.now().astimezone().strftime("%Y-%m-%d %H:%M %Z")
    rows = []
    for r in results:
        extra = (
            f"phase error {r['phase_error']:.1e} rad"
            if "phase_error" in r
            else f"creep {r['creep_xy']:.1e} m, {r['creep_angle']:.1e} rad"
        )
        laws = f"{r['energy_law']:.2f} / {r['gap_law']:.2f}"
        if "creep_law" in r:
            laws += f" (creep {r['creep_law']:.2f})"
        rows.append(
            [
                r["scene"],
                f"{r['steps']:,}",
                f"{r['wall_time']:.0f} s ({r['steps_per_second']:.0f}/s)",
                f"{r['max_drift']:.2e} J ({r['max_drift'] / abs(r['energy0']):.1e})",
                f"{r['drift_per_step']:.1e}",
                f"{r['penetration']:.1e} m",
                f"{r['largest_gap']:.1e} m",
                extra,
                laws,
                "none" if r["failure"] is None and r["finite"] else (r["failure"] or "NaN"),
            ]
        )
    table = _table(
        [
            "scene",
            "steps",
            "wall time",
            "max abs(E - E0) (relative)",
            "drift per step",
            "max penetration",
            "largest gap",
            "accuracy",
            "per-step laws: worst drift / bound (energy / gap)",
            "NaN / failure",
        ],
        rows,
    )
    growth = []
    for r in results:
        crept = dict(r.get("creep_checkpoints", []))
        for c, drift, pen in r["checkpoints"]:
            growth.append(
                [
                    r["scene"],
                    f"{c:,}",
                    f"{drift:.2e}",
                    f"{drift / abs(r['energy0']):.1e}",
                    f"{pen:.1e}",
                    f"{crept[c]:.1e}" if c in crept else "-",
                ]
            )
    growth_table = _table(
        [
            "scene",
            "steps so far",
            "max abs(E - E0) (J)",
            "relative",
            "max penetration (m)",
            "creep (m, rad)",
        ],
        growth,
    )
    impacts = ", ".join(f"{r['scene']} {r['impacts']}" for r in results)
    smallest = ", ".join(f"{r['scene']} {r['independent_min_gap']:.1e} m" for r in results)
    return "\n".join(
        [
            SECTION,
            "",
            "Written by `python -m bench.long_runs`; rerun it to refresh this section. "
            "The CI version is tests/runtime/test_long_runs.py; the bounds are explained in "
            "docs/numerics.md.",
            "",
            f"Run {date} on {_machine()}; {jobs} process(es) (other work shared the cores: 1-minute "
            f"load average {load[0]:.1f} before, {load[1]:.1f} after). RK4, dt = {results[0]['dt']:g} s, "
            f"no stabilisation, scenes as shipped; energy and gaps sampled every "
            f"{results[0]['record_every']} steps. Whole benchmark: {elapsed:.0f} s.",
            "",
            table,
            "",
            "Growth with the number of steps:",
            "",
            growth_table,
            "",
            f"Impacts located: {impacts}. Smallest gap `Scene.contacts` reports at the "
            f"recorded poses: {smallest}.",
            "",
        ]
    )


def _table(header: list[str], rows: list[list[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=STEPS)
    parser.add_argument("--scenes", nargs="+", default=list(SCENES), choices=SCENES)
    parser.add_argument("--jobs", type=int, default=1, help="processes (one scene each)")
    parser.add_argument("--no-readme", action="store_true", help="print only")
    args = parser.parse_args(argv)
    start, load_before = time.perf_counter(), os.getloadavg()[0]
    if args.jobs > 1:
        with ProcessPoolExecutor(args.jobs) as pool:
            results = list(pool.map(measure, args.scenes, [args.steps] * len(args.scenes)))
    else:
        results = [measure(name, args.steps) for name in args.scenes]
    for r in results:
        print(r, file=sys.stderr)
    section = report(
        results, time.perf_counter() - start, args.jobs, (load_before, os.getloadavg()[0])
    )
    print(section)
    if not args.no_readme:
        replace_section(README, SECTION, section)
        print(f"\nwritten to {README.relative_to(ROOT)}", file=sys.stderr)


if __name__ == "__main__":
    main()
