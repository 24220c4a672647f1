"""Speed against error: work-precision diagrams of our engine, pymunk and Box2D (`make report`).

For every scene with an exact or high-precision reference (bench/references.py) every engine is
swept over its cost knobs -- ours over the integrator and dt (rtol for the adaptive ones), the
peers (bench/peers.py: pymunk, and Box2D when the optional `box2d` package is installed) over dt,
solver iterations and, for the bowl, the number of straight segments -- and every run's wall
time and errors are recorded. bench/compare.py reads ours against each peer off the Pareto
fronts measured in this one run, and bench/report_pages.py writes, into docs/report/:

- one PNG per scene: error against wall time on log-log axes, one line per method (a
  work-precision diagram as DiffEqDevTools draws them);
- README.md: the same numbers as tables, the comparison ours/peer (error at equal cost, cost at
  equal error), the date, the machine and the versions;

and the "## Report" section of bench/README.md (the headline numbers). Each scene's runs are
also kept as docs/report/<scene>.json, so a run of some scenes (--scenes) rewrites the pages
with the other scenes as last measured (each section says when).

    python -m bench.report            # everything (about 15 minutes on 2 cores)
    python -m bench.report --scenes disc_rolling_in_bowl,block_on_incline   # only these
    python -m bench.report --quick    # a few runs per engine, into a scratch folder (smoke test)
"""

from __future__ import annotations

import argparse
import datetime
import os
import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import runtime
from bench import peers, report_store
from bench.compare import Point, compare
from bench.markdown import replace_section
from bench.references import Reference, Trajectory
from bench.report_pages import (
    SECTION,
    PeerInfo,
    SceneResult,
    bench_section,
    plot_scene,
    report_markdown,
    summary_table,
)
from bench.report_scenes import ADAPTIVE_DT, SCENES, SceneSpec
from runtime import settings

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "docs" / "report"
BENCH_README = ROOT / "bench" / "README.md"

# Our sweep. Fixed-step methods over dt; the adaptive ones over rtol (atol = rtol / 1000) with
# the engine's outer step (where contacts are classified and recorded) at ADAPTIVE_DT.
OUR_FIXED_DT = {
    "euler": (2e-2, 1e-2, 5e-3, 2e-3, 1e-3),
    "midpoint": (1e-1, 5e-2, 2e-2, 1e-2, 5e-3, 2e-3),
    "rk4": (2e-1, 1e-1, 5e-2, 2e-2, 1e-2, 5e-3),
}
OUR_RTOL = (1e-2, 1e-4, 1e-6, 1e-8, 1e-10)
# The peers' sweep: dt from one 60 Hz frame down to 1/61440 s, two iteration counts (each
# engine's default first), and the bowl as N chords. (With one contact the iterations change
# nothing; the sweep shows it.)
PEER_DT = tuple(1.0 / (60 * 2**k) for k in range(11))
BOWL_SEGMENTS = (16, 64, 256)

QUICK_FIXED_DT = {"rk4": (1e-1, 2e-2), "euler": (1e-2,)}
QUICK_RTOL = (1e-4,)
QUICK_PEER_DT = tuple(1.0 / (60 * 2**k) for k in (0, 4))


@dataclass(frozen=True)
class Peer:
    """A peer engine of the report: how to configure and run it, and its default iterations."""

    name: str
    config: Callable  # (dt=, iterations=, segments=) -> a config of bench/peers.py
    simulate: Callable  # (scene, duration, config, with_segments) -> Trajectory
    iterations: tuple[int, ...]  # solver iterations swept, the engine's default first
    version: Callable[[], str]
    sweep: str

    def info(self) -> PeerInfo:
        return PeerInfo(self.name, self.version(), self.iterations[0], self.sweep)


PYMUNK = Peer(
    "pymunk",
    peers.PeerConfig,
    peers.simulate_pymunk,
    (10, 50),
    peers.version,
    "dt from 1/60 s to 1/61440 s, iterations 10 and 50, elasticity 0, friction the scene's "
    "(sqrt(mu) per shape: pymunk multiplies them), collision "
    f"slop {peers.COLLISION_SLOP:g} m (its default 0.1 would let the bodies sink 10 cm).",
)
BOX2D = Peer(
    "Box2D",
    peers.Box2DConfig,
    peers.simulate_box2d,
    (8, 50),
    peers.box2d_version,
    "dt from 1/60 s to 1/61440 s, velocity iterations 8 and 50 (3 position iterations), "
    "friction the scene's (Box2D mixes sqrt(mu1 mu2), as we do), restitution 0, the polygon "
    "and edge skin (b2_polygonRadius) set to 0 so the surfaces are the scene's; its b2_linearSlop of 5 mm (the overlap its position correction "
    "tolerates) is compiled in, and it computes in float32.",
)


def available_peers() -> tuple[list[Peer], list[str]]:
    """The peers to run, and a sentence for each that cannot be."""
    if peers.box2d_available():
        return [PYMUNK, BOX2D], []
    return [PYMUNK], [
        "Box2D is not compared in this run: the optional `box2d` package is not installed "
        "(`pip install -e '.[peers]'`, as `make report` does)."
    ]


def repeats_for(wall_time: float) -> int:
    """How often to time a run: short runs are repeated (best of 3) to beat the noise of the
    other processes on the two cores; long ones, whose noise is relatively small, twice (a
    run slowed down by a burst of load is then taken again)."""
    return 3 if wall_time < 0.5 else 2


@contextmanager
def adaptive_tolerances(rtol: float, atol: float) -> Iterator[None]:
    """The engine's adaptive methods take rtol and atol from runtime.settings (RTOL, ATOL); the
    report sweeps them, and puts them back after each run."""
    saved = settings.RTOL, settings.ATOL
    settings.RTOL, settings.ATOL = rtol, atol
    try:
        yield
    finally:
        settings.RTOL, settings.ATOL = saved


def our_trajectory(scene, duration: float, method: str, dt: float, rtol: float) -> Trajectory:
    """Run our engine once and reduce the run to the moving body's trajectory. The engine's
    guards are off: the report measures penetration and energy itself, also for the coarse
    Euler and midpoint runs that the penetration guard would stop."""
    off = runtime.Guards(penetration=None, energy_growth=None)
    with adaptive_tolerances(rtol, rtol * 1e-3):
        run = runtime.simulate(scene, duration, dt, method, guards=off)
    (index,) = [i for i, b in enumerate(scene.bodies) if not b.fixed]
    setting = f"dt={dt:g}" if method in OUR_FIXED_DT else f"rtol={rtol:.0e}"
    return Trajectory(
        engine="ours",
        method=method,
        setting=setting,
        t=np.asarray(run.t),
        pose=np.asarray(run.poses)[:, index],
        velocity=np.asarray(run.velocities)[:, index],
        force=np.array([float(np.sum(f)) for f in run.contact_forces]),
        penetration=run.max_penetration,
        wall_time=run.wall_time,
        lift_times=np.asarray(run.lift_times),
    )


def best_of(run_once: Callable[[], Trajectory]) -> Trajectory:
    """The run with the smallest wall time of `repeats_for` runs (the errors are identical),
    their number decided by the fastest so far."""
    best, runs = run_once(), 1
    while runs < repeats_for(best.wall_time):
        again, runs = run_once(), runs + 1
        if again.wall_time < best.wall_time:
            best = again
    return best


def our_configurations(quick: bool) -> list[tuple[str, float, float]]:
    """(method, dt, rtol) of our sweep."""
    fixed = QUICK_FIXED_DT if quick else OUR_FIXED_DT
    rtols = QUICK_RTOL if quick else OUR_RTOL
    configs = [(m, dt, 1e-9) for m, dts in fixed.items() for dt in dts]
    adaptive = ("rk45",) if quick else ("rk45", "dop853")
    configs += [(m, ADAPTIVE_DT, rtol) for m in adaptive for rtol in rtols]
    return configs


def peer_configurations(spec: SceneSpec, quick: bool, peer: Peer) -> list:
    """A peer's sweep; the extra iteration counts only at the finest bowl (they change
    nothing with one contact, which the report shows)."""
    dts = QUICK_PEER_DT if quick else PEER_DT
    segments = BOWL_SEGMENTS if spec.has_bowl else (peers.PeerConfig.segments,)
    default, *more = peer.iterations
    configs = [peer.config(dt=dt, iterations=default, segments=n) for n in segments for dt in dts]
    configs += [
        peer.config(dt=dt, iterations=it, segments=segments[-1]) for it in more for dt in dts
    ]
    return configs


def sweep_ours(spec: SceneSpec, scene, reference: Reference, quick: bool) -> list[Point]:
    """Every (method, dt/rtol) of our sweep on one scene; a failed run is reported, not fatal.
    Each method first runs two steps untimed: the compiled engine loads (or, after a change of
    its sources, compiles: minutes) on its first run, which is no run's cost."""
    points = []
    configs = our_configurations(quick)
    for method, dt, rtol in {c[0]: c for c in configs}.values():
        our_trajectory(scene, min(spec.duration, 2 * dt), method, dt, rtol)
    for method, dt, rtol in configs:
        try:
            traj = best_of(
                lambda m=method, d=dt, r=rtol: our_trajectory(scene, spec.duration, m, d, r)
            )
        except runtime.SimulationError as exc:
            print(f"  ours {method} dt={dt:g}: failed ({exc})", file=sys.stderr)
            continue
        points.append(_point(traj, reference))
    return points


def sweep_peer(spec: SceneSpec, scene, reference: Reference, quick: bool, peer: Peer):
    """Every configuration of a peer's sweep on one scene."""
    return [
        _point(peer.simulate(scene, spec.duration, config, spec.has_bowl), reference)
        for config in peer_configurations(spec, quick, peer)
    ]


def _point(traj: Trajectory, reference: Reference) -> Point:
    point = Point(
        traj.engine,
        traj.method,
        traj.setting,
        traj.wall_time,
        reference.errors(traj),
        len(traj.t) - 1,
    )
    primary = point.errors[reference.primary]
    print(
        f"  {traj.engine:6s} {traj.method:18s} {traj.setting:14s} {traj.wall_time:8.3f} s  "
        f"{reference.primary} {primary:.2e}",
        file=sys.stderr,
    )
    return point


def run_scene(spec: SceneSpec, quick: bool, peer_list: list[Peer]) -> SceneResult:
    """Sweep every engine on one scene and compare ours with each peer on its primary error."""
    scene = runtime.load_scene(spec.path)
    reference = spec.reference(scene, spec.duration)
    print(f"{spec.name}:", file=sys.stderr)
    ours = sweep_ours(spec, scene, reference, quick)
    theirs = {p.name: sweep_peer(spec, scene, reference, quick, p) for p in peer_list}
    comparisons = {name: compare(ours, pts, reference.primary) for name, pts in theirs.items()}
    return SceneResult(spec, ours, theirs, comparisons)


OURS_SWEEP = (
    "Ours: euler, midpoint, rk4 over dt; rk45 and dop853 over rtol (atol = rtol/1000) with the "
    f"engine's step (contact classification, recording) at {ADAPTIVE_DT:g} s."
)


def measured_now() -> str:
    """When a scene is measured, and the load then: each scene's section says it."""
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    return f"{now}, 1-minute load average {os.getloadavg()[0]:.1f}"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a few runs, into --out")
    parser.add_argument("--out", type=Path, default=None, help="output folder")
    parser.add_argument(
        "--scenes",
        default=None,
        help="comma-separated scenes to measure (default: all); the others as last measured",
    )
    args = parser.parse_args(argv)
    names = [spec.name for spec in SCENES]
    chosen = names if args.scenes is None else [n.strip() for n in args.scenes.split(",")]
    unknown = [n for n in chosen if n not in names]
    if unknown or not chosen:
        parser.error(f"unknown scene(s) {', '.join(unknown)}: the report's are {', '.join(names)}")
    out = args.out or (ROOT / "out" / "report-quick" if args.quick else OUT)
    out.mkdir(parents=True, exist_ok=True)
    peer_list, missing = available_peers()
    start = time.perf_counter()
    results = []
    for spec in SCENES:
        stored = out / f"{spec.name}.json"
        if spec.name in chosen:
            result = run_scene(spec, args.quick, peer_list)
            result.measured = measured_now()
            report_store.save(result, stored)
            plot_scene(result, out / f"{spec.name}.png")
        elif stored.exists():
            result = report_store.load(spec, stored)
        else:
            missing.append(f"{spec.name} has not been measured yet (`--scenes {spec.name}`).")
            continue
        results.append(result)
    elapsed = time.perf_counter() - start
    text = report_markdown(
        results,
        [p.info() for p in peer_list],
        ours=OURS_SWEEP,
        missing=missing,
        elapsed=elapsed,
        quick=args.quick,
        rerun=chosen,
    )
    (out / "README.md").write_text(text)
    if not args.quick and args.out is None:
        replace_section(BENCH_README, SECTION, bench_section(results, elapsed, chosen))
    print("\n".join(summary_table(results)))
    print(f"written to {out} in {elapsed:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
