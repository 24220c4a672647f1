"""Speed against error: work-precision diagrams of our engine and pymunk (`make report`).

For every scene with an exact or high-precision reference (bench/references.py) both engines are
swept over their cost knobs -- ours over the integrator and dt (rtol for the adaptive ones),
pymunk over dt, solver iterations and, for the bowl, the number of straight segments -- and every
run's wall time and errors are recorded. From these it writes, into docs/report/:

- one PNG per scene: error against wall time on log-log axes, one line per method (a
  work-precision diagram as DiffEqDevTools draws them);
- README.md: the same numbers as tables, the comparison ours/pymunk (error at equal cost, cost at
  equal error, both read off the two Pareto fronts measured in this one run), the date, the
  machine and the versions;

and the "## Report" section of bench/README.md (the headline numbers).

    python -m bench.report            # everything (about 10 minutes on 2 cores)
    python -m bench.report --quick    # a few runs per engine, into a scratch folder (smoke test)
"""

from __future__ import annotations

import argparse
import datetime
import importlib.util
import math
import os
import platform
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only; no display on CI

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402

import runtime  # noqa: E402
from bench import peers  # noqa: E402
from bench.machine import cpu as machine  # noqa: E402
from bench.markdown import replace_section  # noqa: E402
from bench.references import (  # noqa: E402
    BowlReference,
    CylinderReference,
    InclineReference,
    PlankReference,
    Reference,
    Trajectory,
)

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "docs" / "report"
BENCH_README = ROOT / "bench" / "README.md"
SECTION = "## Report"

FLOOR = 1e-16  # errors below this are rounding: plotted and compared as "<= 1e-16"
TARGET = 1e-2  # the project's target: at equal wall time our error <= 1/100 of pymunk's
GRID = 41  # points of the log grid over a common range when looking for the worst ratio

# Our sweep. Fixed-step methods over dt; the adaptive ones over rtol (atol = rtol / 1000) with
# the engine's outer step (where contacts are classified and recorded) at ADAPTIVE_DT.
OUR_FIXED_DT = {
    "euler": (2e-2, 1e-2, 5e-3, 2e-3, 1e-3),
    "midpoint": (1e-1, 5e-2, 2e-2, 1e-2, 5e-3, 2e-3),
    "rk4": (2e-1, 1e-1, 5e-2, 2e-2, 1e-2, 5e-3),
}
OUR_RTOL = (1e-2, 1e-4, 1e-6, 1e-8, 1e-10)
ADAPTIVE_DT = 0.02
# pymunk's sweep: dt from one 60 Hz frame down to 1/61440 s, two iteration counts, and the
# bowl as N chords. (With one contact the iterations change nothing; the sweep shows it.)
PEER_DT = tuple(1.0 / (60 * 2**k) for k in range(11))
PEER_ITERATIONS = (10, 50)
BOWL_SEGMENTS = (16, 64, 256)

QUICK_FIXED_DT = {"rk4": (1e-1, 2e-2), "euler": (1e-2,)}
QUICK_RTOL = (1e-4,)
QUICK_PEER_DT = tuple(1.0 / (60 * 2**k) for k in (0, 4))


@dataclass(frozen=True)
class SceneSpec:
    """A report scene: its file, how long to simulate it, its reference and what to plot."""

    name: str
    duration: float  # s of simulated time
    reference: type[Reference]
    panels: tuple[str, ...]  # error measures plotted, the reference's primary first
    title: str

    @property
    def path(self) -> Path:
        return ROOT / "scenes" / f"{self.name}.toml"

    @property
    def has_bowl(self) -> bool:
        return self.reference is BowlReference


SCENES = (
    SceneSpec(
        "disc_in_bowl",
        2.0,
        BowlReference,
        ("position", "force_rms"),
        "Disc in a bowl (concave circle-circle), 2 s: pendulum reference",
    ),
    SceneSpec(
        "disc_over_cylinder",
        1.5,
        CylinderReference,
        ("leaving_angle", "position"),
        "Disc sliding over a cylinder (convex circle-circle), 1.5 s: leaving angle",
    ),
    SceneSpec(
        "plank_on_cylinder",
        1.0,
        PlankReference,
        ("energy", "penetration"),
        "Plank tipping off a cylinder (circle-edge), 1 s: energy conservation",
    ),
    SceneSpec(
        "disc_on_incline",
        0.5,
        InclineReference,
        ("position", "energy"),
        "Disc on a 30° incline (straight edge, the control), 0.5 s: closed form",
    ),
)

LABELS = {
    "position": "max position error [m]",
    "energy": "max energy drift / mg [m]",
    "force": "max contact-force error / mg",
    "force_rms": "rms contact-force error / mg",
    "penetration": "max penetration [m]",
    "leaving_angle": "leaving-angle error [rad]",
}


# --------------------------------------------------------------------------------------------
# Running both engines


@dataclass
class Point:
    """One run of one configuration: its trajectory summary and its errors."""

    engine: str
    method: str
    setting: str
    wall_time: float
    errors: dict[str, float]
    steps: int


def repeats_for(wall_time: float) -> int:
    """How often to time a run: short runs are repeated (best of 3) to beat the noise of the
    other processes on the two cores; long ones, whose noise is relatively small, are not."""
    return 3 if wall_time < 0.5 else 2 if wall_time < 2.0 else 1


def our_trajectory(scene, duration: float, method: str, dt: float, rtol: float) -> Trajectory:
    """Run our engine once and reduce the run to the moving body's trajectory. The engine's
    guards are off: the report measures penetration and energy itself, also for the coarse
    Euler and midpoint runs that the penetration guard would stop."""
    off = runtime.Guards(penetration=None, energy_growth=None)
    run = runtime.simulate(scene, duration, dt, method, rtol=rtol, atol=rtol * 1e-3, guards=off)
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
    )


def best_of(run_once: Callable[[], Trajectory]) -> Trajectory:
    """The run with the smallest wall time of `repeats_for` runs (the errors are identical)."""
    best = run_once()
    for _ in range(repeats_for(best.wall_time) - 1):
        again = run_once()
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


def peer_configurations(spec: SceneSpec, quick: bool) -> list[peers.PeerConfig]:
    """pymunk's sweep; the iteration counts only at the finest bowl (they change nothing)."""
    dts = QUICK_PEER_DT if quick else PEER_DT
    segments = BOWL_SEGMENTS if spec.has_bowl else (peers.PeerConfig.segments,)
    configs = [peers.PeerConfig(dt, 10, n) for n in segments for dt in dts]
    configs += [
        peers.PeerConfig(dt, it, segments[-1]) for it in PEER_ITERATIONS if it != 10 for dt in dts
    ]
    return configs


def sweep_ours(spec: SceneSpec, scene, reference: Reference, quick: bool) -> list[Point]:
    """Every (method, dt/rtol) of our sweep on one scene; a failed run is reported, not fatal."""
    points = []
    for method, dt, rtol in our_configurations(quick):
        try:
            traj = best_of(
                lambda m=method, d=dt, r=rtol: our_trajectory(scene, spec.duration, m, d, r)
            )
        except runtime.SimulationError as exc:
            print(f"  ours {method} dt={dt:g}: failed ({exc})", file=sys.stderr)
            continue
        points.append(_point(traj, reference))
    return points


def sweep_pymunk(spec: SceneSpec, scene, reference: Reference, quick: bool) -> list[Point]:
    """Every configuration of pymunk's sweep on one scene."""
    points = []
    for config in peer_configurations(spec, quick):
        traj = peers.simulate(scene, spec.duration, config, spec.has_bowl)
        points.append(_point(traj, reference))
    return points


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


# --------------------------------------------------------------------------------------------
# Comparing: Pareto fronts, error at equal cost, cost at equal error


@dataclass(frozen=True)
class Front:
    """The runs no other run of the same engine beats in both cost and error, by cost."""

    cost: np.ndarray
    error: np.ndarray

    @classmethod
    def of(cls, points: list[Point], metric: str) -> Front:
        pairs = sorted(
            (p.wall_time, max(p.errors[metric], FLOOR))
            for p in points
            if math.isfinite(p.errors[metric])
        )
        cost, error = [], []
        for c, e in pairs:
            if not error or e < error[-1]:
                cost.append(c)
                error.append(e)
        return cls(np.array(cost), np.array(error))

    def error_at(self, cost: float) -> float:
        """Log-log interpolated error at a wall time inside the front's range."""
        return float(np.exp(np.interp(np.log(cost), np.log(self.cost), np.log(self.error))))

    def cost_at(self, error: float) -> float:
        """Log-log interpolated wall time to reach an error inside the front's range."""
        return float(np.exp(np.interp(-np.log(error), -np.log(self.error), np.log(self.cost))))


@dataclass
class Comparison:
    """Ours/pymunk on one error measure: ratios < 1 are in our favour."""

    metric: str
    cost_range: tuple[float, float] | None  # wall times both engines measured
    error_range: tuple[float, float] | None  # errors both engines reached
    error_ratio_mid: float = math.nan  # error ours/pymunk at the middle of cost_range
    error_ratio_worst: float = math.nan  # the largest such ratio over cost_range
    error_ratio_best: float = math.nan
    ours_at_floor: bool = False  # our error is rounding there: the ratio is an upper bound
    cost_ratio_mid: float = math.nan  # wall time ours/pymunk at the middle of error_range
    cost_ratio_hardest: float = math.nan  # ... at pymunk's best error
    cost_hardest_is_bound: bool = False  # our cheapest run beats it: an upper bound
    target_from: float = math.nan  # wall time from which error ours/pymunk <= TARGET
    extra: dict[str, float] = field(default_factory=dict)

    @property
    def target_met(self) -> bool | None:
        if self.cost_range is None:
            return None
        return self.error_ratio_worst <= TARGET


def _overlap(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float] | None:
    lo, hi = max(a[0], b[0]), min(a[1], b[1])
    return (lo, hi) if lo <= hi else None


def _holds_from(costs: np.ndarray, ratios: np.ndarray) -> float:
    """The smallest wall time from which the error ratio stays <= TARGET (inf: nowhere)."""
    failing = np.flatnonzero(ratios > TARGET)
    if failing.size == 0:
        return float(costs[0])
    return float(costs[failing[-1] + 1]) if failing[-1] + 1 < len(costs) else math.inf


def compare(ours: list[Point], theirs: list[Point], metric: str) -> Comparison:
    """Error at equal cost and cost at equal error, read off both fronts where both measured."""
    fo, ft = Front.of(ours, metric), Front.of(theirs, metric)
    cost_range = _overlap((fo.cost[0], fo.cost[-1]), (ft.cost[0], ft.cost[-1]))
    error_range = _overlap((fo.error[-1], fo.error[0]), (ft.error[-1], ft.error[0]))
    result = Comparison(metric, cost_range, error_range)
    if cost_range is not None:
        grid = np.geomspace(*cost_range, GRID)
        ratios = np.array([fo.error_at(c) / ft.error_at(c) for c in grid])
        mid = math.sqrt(cost_range[0] * cost_range[1])
        result.error_ratio_mid = fo.error_at(mid) / ft.error_at(mid)
        result.error_ratio_worst = float(ratios.max())
        result.error_ratio_best = float(ratios.min())
        result.ours_at_floor = fo.error_at(mid) <= FLOOR * 1.0001
        result.extra["cost_mid"] = mid
        result.target_from = _holds_from(grid, ratios)
    if error_range is not None:
        mid = math.sqrt(error_range[0] * error_range[1])
        result.cost_ratio_mid = fo.cost_at(mid) / ft.cost_at(mid)
        result.extra["error_mid"] = mid
    hardest = ft.error[-1]  # the smallest error pymunk reached
    result.extra["error_hardest"] = hardest
    if hardest >= fo.error[0]:  # our cheapest run is already better: a bound
        result.cost_ratio_hardest = fo.cost[0] / ft.cost_at(hardest)
        result.cost_hardest_is_bound = True
    elif hardest >= fo.error[-1]:
        result.cost_ratio_hardest = fo.cost_at(hardest) / ft.cost_at(hardest)
    return result


# --------------------------------------------------------------------------------------------
# Output: plots and tables


OUR_STYLE = {
    "euler": "tab:red",
    "midpoint": "tab:orange",
    "rk4": "tab:blue",
    "rk45": "tab:green",
    "dop853": "tab:purple",
}
PEER_COLOURS = ("0.15", "0.45", "0.65", "tab:brown")


def _lines(points: list[Point]) -> dict[str, list[Point]]:
    lines: dict[str, list[Point]] = {}
    for p in points:
        lines.setdefault(p.method, []).append(p)
    return lines


def plot_scene(spec: SceneSpec, ours: list[Point], theirs: list[Point], path: Path) -> None:
    """Work-precision diagram: each panel one error measure against wall time, log-log."""
    fig, axes = plt.subplots(1, len(spec.panels), figsize=(5.2 * len(spec.panels), 4.2))
    for ax, metric in zip(np.atleast_1d(axes), spec.panels, strict=True):
        for method, pts in _lines(ours).items():
            _plot_line(ax, pts, metric, method, OUR_STYLE.get(method, "k"), "-", "o")
        for k, (method, pts) in enumerate(_lines(theirs).items()):
            colour = PEER_COLOURS[k % len(PEER_COLOURS)]
            _plot_line(ax, pts, metric, method, colour, "--", "s^vD"[k % 4])
        ax.axhline(FLOOR, color="0.8", lw=0.8, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel(LABELS[metric])
        ax.grid(True, which="major", lw=0.4, alpha=0.5)
    np.atleast_1d(axes)[0].legend(fontsize=7, loc="best")
    fig.suptitle(spec.title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def _plot_line(ax, pts, metric, label, colour, style, marker) -> None:
    """One method, its points joined in the order of the sweep (coarse to fine)."""
    x = [p.wall_time for p in pts if math.isfinite(p.errors[metric])]
    y = [max(p.errors[metric], FLOOR) for p in pts if math.isfinite(p.errors[metric])]
    if x:
        ax.plot(x, y, style, color=colour, marker=marker, ms=4, lw=1.2, label=label)


def _g(x: float, digits: int = 2) -> str:
    if x is None or not math.isfinite(x):
        return "—"
    if x == 0.0:
        return "0"
    return f"{x:.{digits}g}" if 1e-3 <= abs(x) < 1e4 else f"{x:.{digits - 1}e}"


def _ratio(x: float, bound: bool = False) -> str:
    if not math.isfinite(x):
        return "—"
    return ("≤ " if bound else "") + (f"{x:.2g}" if x >= 1e-3 else f"{x:.1e}")


def _verdict(cmp: Comparison) -> str:
    """Whether error ours/pymunk <= 1/100 over the common wall-time range, and where it does."""
    if cmp.target_met is None:
        return "no common wall-time range"
    if cmp.target_met:
        return "**holds** over the whole range"
    if not math.isfinite(cmp.target_from):
        return "**does not hold** anywhere in the range"
    return f"**does not hold** below {_g(cmp.target_from)} s; holds above"


def summary_table(results: list[tuple[SceneSpec, Comparison]]) -> list[str]:
    """One row per scene: the headline ratios ours/pymunk on the scene's primary error."""
    rows = [
        "| scene | error measure | common wall-time range [s] | error ours/pymunk at equal time: "
        "mid-range [best, worst] | common error range | time ours/pymunk at equal error: "
        "mid-range | … at pymunk's best error | target (curved: ≤ 1/100 over the range) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for spec, cmp in results:
        curved = spec.reference.curved
        cost = f"{_g(cmp.cost_range[0])} – {_g(cmp.cost_range[1])}" if cmp.cost_range else "none"
        err = f"{_g(cmp.error_range[0])} – {_g(cmp.error_range[1])}" if cmp.error_range else "none"
        verdict = _verdict(cmp)
        verdict = verdict if curved else f"({verdict}; straight edge, not a target)"
        rows.append(
            f"| {spec.name} | {cmp.metric} | {cost} | "
            f"{_ratio(cmp.error_ratio_mid, cmp.ours_at_floor)} "
            f"[{_ratio(cmp.error_ratio_best, cmp.ours_at_floor)}, "
            f"{_ratio(cmp.error_ratio_worst, cmp.ours_at_floor)}] | {err} | "
            f"{_ratio(cmp.cost_ratio_mid)} | "
            f"{_ratio(cmp.cost_ratio_hardest, cmp.cost_hardest_is_bound)} | {verdict} |"
        )
    return rows


def runs_table(spec: SceneSpec, points: list[Point]) -> list[str]:
    """Every run of one scene: engine, method, setting, steps, wall time and all its errors."""
    metrics = list(points[0].errors)
    head = "| engine | method | setting | steps | wall time [s] | " + " | ".join(
        f"{m} [{spec.reference.units[m]}]" for m in metrics
    )
    rows = [head + " |", "|---" * (5 + len(metrics)) + "|"]
    for p in points:
        errs = " | ".join(_g(p.errors[m], 3) for m in metrics)
        rows.append(
            f"| {p.engine} | {p.method} | {p.setting} | {p.steps} | {p.wall_time:.4g} | {errs} |"
        )
    return rows


def versions() -> str:
    import pymunk

    return (
        f"Python {platform.python_version()}, NumPy {np.__version__}, SciPy {scipy.__version__}, "
        f"matplotlib {matplotlib.__version__}, pymunk {pymunk.version} "
        f"(Chipmunk2D {pymunk.chipmunk_version.split('-')[0]})"
    )


def box2d_status() -> str:
    """Box2D is not compared: say why (box2d-py is an sdist that needs swig to build)."""
    if importlib.util.find_spec("Box2D") is None:
        return (
            "Box2D is not compared: `pip install box2d-py` builds from an sdist that needs `swig`, "
            "which is not installed here (the build fails in seconds), so Box2D was skipped."
        )
    return "Box2D (box2d-py) is importable but not yet wired into the report."


SCENE_NOTES = {
    "disc_in_bowl": (
        "Reference: the pendulum phi'' = -(g/L) sin phi with L = R - r = 0.9 m from 0.3 rad, "
        "scipy DOP853 at rtol 1e-12; contact force m (g cos phi + L phi'^2). pymunk: the bowl's "
        "arc (-150° … -30°) as N chords with their ends on the circle. Position error = max over "
        "the recorded steps of the distance between the disc's centre and the reference's."
    ),
    "disc_over_cylinder": (
        "Reference: the leaving angle cos phi = (2/3) cos phi0 + v0^2 / (3 g (R + r)) "
        "(0.8403 rad here); the run's leaving angle is where its contact force reaches 0: the "
        "zero of the parabola through the last three samples with force, kept between the last "
        "sample with force and the first without. The force is only known once per step, so "
        f"this has a resolution of its own: with our adaptive runs' {ADAPTIVE_DT:g} s step it "
        "gives the same few 1e-6 rad for every rtol, which is more likely the resolution than "
        "the integrator. pymunk's contact comes and goes (an impulse on some steps only), so its "
        "leaving angle is in effect its last step with an impulse. Position error: against the "
        "circle-then-parabola reference trajectory."
    ),
    "plank_on_cylinder": (
        "Reference: energy conservation (frictionless, no impacts). Energy drift = max |E - E0| "
        "/ (m g), a height in metres."
    ),
    "disc_on_incline": (
        "Reference: closed form, the disc slides with g sin 30°. A straight edge: not what the "
        "curved-edge engine is for, but the control -- every method of order >= 2 is exact here "
        "up to rounding (plotted at 1e-16), as is the contact force."
    ),
}


def report_markdown(
    results: list[tuple[SceneSpec, Comparison, list[Point], list[Point]]],
    elapsed: float,
    quick: bool,
) -> str:
    """docs/report/README.md."""
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()
    lines = [
        "# Speed against error: curved-edge-physics and pymunk",
        "",
        f"Written by `make report` (`python -m bench.report`{' --quick' if quick else ''}) "
        f"on {now}, in {elapsed:.0f} s. Machine: {machine()}. Versions: {versions()}. "
        f"1-minute load average at the end: {load[0]:.1f} (other processes share the cores).",
        "",
        "Every point is one run of the whole scene; its wall time is the best of up to 3 "
        "identical runs (ours: `Run.wall_time` of `runtime.simulate`, which includes recording "
        "every step; pymunk: the loop of `space.step` and reading the body's pose and velocity, "
        "with the contact impulses and depths collected in a second, untimed pass). Errors are "
        "measured by the same code for both engines (bench/references.py). "
        f"Ours: euler, midpoint, rk4 over dt; rk45 and dop853 over rtol (atol = rtol/1000) with "
        f"the engine's step (contact classification, recording) at {ADAPTIVE_DT:g} s. "
        f"pymunk: dt from 1/60 s to 1/61440 s, iterations {', '.join(map(str, PEER_ITERATIONS))}, "
        f"friction 0, elasticity 0, collision slop {peers.COLLISION_SLOP:g} m (its default 0.1 "
        "would let the bodies sink 10 cm).",
        "",
        "## Summary",
        "",
        "Ratios ours/pymunk (< 1: ours better), read off the two Pareto fronts (the best run of "
        "each engine at each cost, log-log interpolated) where both engines have measurements; "
        "*worst* is the largest ratio over the whole common range. The project's target: on the "
        "curved-edge scenes, at equal wall time our error is at least 100× smaller.",
        "",
        *summary_table([(s, c) for s, c, _, _ in results]),
        "",
        "- " + box2d_status(),
        "- Our error at the floor (≤ 1e-16, rounding) makes the error ratio an upper bound (≤).",
        "",
    ]
    for spec, cmp, ours, theirs in results:
        lines += [
            f"## {spec.name}",
            "",
            f"![{spec.name}]({spec.name}.png)",
            "",
            SCENE_NOTES.get(spec.name, ""),
            "",
            f"Primary error: {cmp.metric}. Common wall-time range "
            f"{_range(cmp.cost_range)} s: error ours/pymunk {_ratio(cmp.error_ratio_mid, cmp.ours_at_floor)} "
            f"at {_g(cmp.extra.get('cost_mid', math.nan))} s. Common error range "
            f"{_range(cmp.error_range)}: wall time ours/pymunk {_ratio(cmp.cost_ratio_mid)} at "
            f"{_g(cmp.extra.get('error_mid', math.nan))}, "
            f"{_ratio(cmp.cost_ratio_hardest, cmp.cost_hardest_is_bound)} at "
            f"pymunk's best error {_g(cmp.extra.get('error_hardest', math.nan))}. Target "
            f"(error ours/pymunk ≤ 1/100 at equal wall time): {_verdict(cmp)}.",
            "",
            *observations(spec, ours, theirs),
            "",
            "<details><summary>All runs</summary>",
            "",
            *runs_table(spec, ours + theirs),
            "",
            "</details>",
            "",
        ]
    return "\n".join(lines).rstrip("\n") + "\n"


def observations(spec: SceneSpec, ours: list[Point], theirs: list[Point]) -> list[str]:
    """Facts read off the runs, as bullets: the best of each engine, and our runs whose contact
    force vanished while the body was still on the surface (held by impacts instead)."""
    metric = spec.reference.primary
    notes = []
    for engine, points in (("ours", ours), ("pymunk", theirs)):
        best = min(points, key=lambda p: (p.errors[metric], p.wall_time))
        notes.append(
            f"Best {engine}: {metric} {_g(best.errors[metric])} ({best.method}, {best.setting}, "
            f"{_g(best.wall_time)} s)."
        )
    dropped = [p for p in ours if p.errors.get("dropped", 0.0) > 0.0]
    if dropped:
        runs = ", ".join(f"{p.method} {p.setting} ({p.errors['dropped']:.0%})" for p in dropped)
        notes.append(
            "Our runs that report no contact force at some steps although the disc never leaves "
            f"the surface (share of steps): {runs}. In one step the integrator carried the disc "
            "farther off the surface (rk4) or faster into it (midpoint) than the engine treats as "
            "resting, so the contact was opened or met as an impact at the step start (then held "
            "plastically); the force errors count these steps."
        )
    if "dropped" in theirs[0].errors:
        shares = [p.errors["dropped"] for p in theirs]
        notes.append(
            f"pymunk reports no impulse at {min(shares):.0%} – {max(shares):.0%} of its steps "
            "(its contact comes and goes)."
        )
    notes.append(_iterations_note(theirs, metric))
    early = [p for p in ours if p.errors.get("leaving_angle", 0.0) > 0.1]
    if early:
        runs = ", ".join(f"{p.method} {p.setting}" for p in early)
        notes.append(
            f"Our runs whose contact force vanished more than 0.1 rad before the disc leaves: "
            f"{runs}. Their paths stay close (see the position error), but the contact is held "
            "by impacts, not a resting force, so the force does not show where the disc leaves."
        )
    return [f"- {n}" for n in notes]


def _iterations_note(theirs: list[Point], metric: str) -> str:
    """Do pymunk's solver iterations matter here? Each run with more iterations against the
    10-iteration run of the same dt and segments (labels as `peers.PeerConfig.label` writes)."""
    base = {(p.method, p.setting): p.errors[metric] for p in theirs}
    changes = []
    for it in PEER_ITERATIONS:
        for p in theirs:
            if p.method.endswith(f" {it} it"):
                plain = p.method.replace(f", {it} it", "").replace(f" {it} it", "")
                ref = base.get((plain, p.setting))
                if ref:
                    changes.append(p.errors[metric] / ref)
    if not changes:
        return "pymunk: one iteration count only."
    worst = max(max(changes), 1 / min(changes))
    more = max(PEER_ITERATIONS)
    if worst < 1 + 1e-9:
        return (
            f"pymunk: {more} solver iterations give exactly the errors of 10 (one contact: "
            "sequential impulses converge in one sweep), so their lines coincide."
        )
    return f"pymunk: {more} solver iterations change its {metric} by up to {worst:.2g}×."


def _range(r: tuple[float, float] | None) -> str:
    return f"{_g(r[0])} – {_g(r[1])}" if r else "(none)"


def bench_section(results, elapsed: float) -> str:
    """The "## Report" section of bench/README.md: how to run it and the headline table."""
    lines = [
        SECTION,
        "",
        "Written by `python -m bench.report` (`make report`); the diagrams, all runs and the "
        f"details are in [docs/report/README.md](../docs/report/README.md). Last run: {elapsed:.0f} s, "
        f"{machine()}.",
        "",
        *summary_table([(s, c) for s, c, _, _ in results]),
        "",
    ]
    return "\n".join(lines)


# --------------------------------------------------------------------------------------------


def run_scene(spec: SceneSpec, quick: bool):
    """Sweep both engines on one scene and compare them on its primary error."""
    scene = runtime.load_scene(spec.path)
    reference = spec.reference(scene, spec.duration)
    print(f"{spec.name}:", file=sys.stderr)
    ours = sweep_ours(spec, scene, reference, quick)
    theirs = sweep_pymunk(spec, scene, reference, quick)
    return spec, compare(ours, theirs, reference.primary), ours, theirs


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a few runs, into --out")
    parser.add_argument("--out", type=Path, default=None, help="output folder")
    args = parser.parse_args(argv)
    out = args.out or (ROOT / "out" / "report-quick" if args.quick else OUT)
    out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    results = [run_scene(spec, args.quick) for spec in SCENES]
    for spec, _, ours, theirs in results:
        plot_scene(spec, ours, theirs, out / f"{spec.name}.png")
    elapsed = time.perf_counter() - start
    (out / "README.md").write_text(report_markdown(results, elapsed, args.quick))
    if not args.quick and args.out is None:
        replace_section(BENCH_README, SECTION, bench_section(results, elapsed))
    print("\n".join(summary_table([(s, c) for s, c, _, _ in results])))
    print(f"written to {out} in {elapsed:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
