"""What the report writes: the work-precision diagrams, docs/report/README.md and the
"## Report" section of bench/README.md (bench/report.py runs the engines).

Why apart: the sweep is about running engines, this is about presenting what they measured;
every number here is read off the points and comparisons it is given.
"""

from __future__ import annotations

import datetime
import math
import os
import platform
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")  # files only; no display on CI

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import scipy  # noqa: E402

from bench.compare import FLOOR, Comparison, Point  # noqa: E402
from bench.machine import cpu as machine  # noqa: E402

SECTION = "## Report"

LABELS = {
    "position": "max position error [m]",
    "energy": "max energy drift / mg [m]",
    "force": "max contact-force error / mg",
    "force_rms": "rms contact-force error / mg",
    "penetration": "max penetration [m]",
    "leaving_angle": "leaving-angle error [rad]",
    "slip": "max slip speed of the contact point [m/s]",
}
OUR_STYLE = {
    "euler": "tab:red",
    "midpoint": "tab:orange",
    "rk4": "tab:blue",
    "rk45": "tab:green",
    "dop853": "tab:purple",
}
# per peer: line colours, line style, markers
PEER_STYLE = {
    "pymunk": (("0.15", "0.45", "0.65", "0.3"), "--", "s^vD"),
    "Box2D": (("tab:brown", "peru", "sandybrown", "saddlebrown"), ":", "PXhd"),
}


@dataclass(frozen=True)
class PeerInfo:
    """A peer engine as the pages describe it: its name, version, the iteration count its lines
    use unless labelled, and how it was swept (a sentence)."""

    name: str
    version: str
    base_iterations: int
    sweep: str


@dataclass
class SceneResult:
    """One scene: our runs, each peer's runs, and ours against each peer on the primary error."""

    spec: Any  # bench.report.SceneSpec
    ours: list[Point]
    theirs: dict[str, list[Point]]
    comparisons: dict[str, Comparison]
    measured: str = ""  # when, and the machine's load then (a sentence)


def _lines(points: list[Point]) -> dict[str, list[Point]]:
    lines: dict[str, list[Point]] = {}
    for p in points:
        lines.setdefault(p.method, []).append(p)
    return lines


def plot_scene(result: SceneResult, path: Path) -> None:
    """Work-precision diagram: each panel one error measure against wall time, log-log; the
    legend beside the panels, off the data."""
    spec = result.spec
    fig, axes = plt.subplots(1, len(spec.panels), figsize=(5.2 * len(spec.panels) + 2.2, 4.2))
    for ax, metric in zip(np.atleast_1d(axes), spec.panels, strict=True):
        for method, pts in _lines(result.ours).items():
            _plot_line(ax, pts, metric, method, OUR_STYLE.get(method, "k"), "-", "o")
        for peer, points in result.theirs.items():
            colours, style, markers = PEER_STYLE.get(peer, PEER_STYLE["pymunk"])
            for k, (method, pts) in enumerate(_lines(points).items()):
                colour, marker = colours[k % len(colours)], markers[k % len(markers)]
                _plot_line(ax, pts, metric, method, colour, style, marker)
        ax.axhline(FLOOR, color="0.8", lw=0.8, ls=":")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel(LABELS[metric])
        ax.grid(True, which="major", lw=0.4, alpha=0.5)
    np.atleast_1d(axes)[-1].legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0))
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


def _range(r: tuple[float, float] | None) -> str:
    return f"{_g(r[0])} – {_g(r[1])}" if r else "none"


def _verdict(cmp: Comparison) -> str:
    """Whether error ours/peer <= 1/100 over the common wall-time range, and where it does."""
    if cmp.target_met is None:
        return "no common wall-time range"
    if cmp.target_met:
        return "**holds** over the whole range"
    if not math.isfinite(cmp.target_from):
        return "**does not hold** anywhere in the range"
    return f"**does not hold** below {_g(cmp.target_from)} s; holds above"


def summary_table(results: list[SceneResult]) -> list[str]:
    """One row per scene and peer: the headline ratios ours/peer on the scene's primary error."""
    rows = [
        "| scene | peer | error measure | common wall-time range [s] | error ours/peer at equal "
        "time: mid-range [best, worst] | common error range | time ours/peer at equal error: "
        "mid-range | … at the peer's best error | target (curved: ≤ 1/100 over the range) |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for result in results:
        spec = result.spec
        for peer, cmp in result.comparisons.items():
            verdict = _verdict(cmp)
            if not spec.reference.curved:
                verdict = f"({verdict}; straight edge, not a target)"
            bound = cmp.ours_at_floor
            rows.append(
                f"| {spec.name} | {peer} | {cmp.metric} | {_range(cmp.cost_range)} | "
                f"{_ratio(cmp.error_ratio_mid, bound)} [{_ratio(cmp.error_ratio_best, bound)}, "
                f"{_ratio(cmp.error_ratio_worst, bound)}] | {_range(cmp.error_range)} | "
                f"{_ratio(cmp.cost_ratio_mid)} | "
                f"{_ratio(cmp.cost_ratio_hardest, cmp.cost_hardest_is_bound)} | {verdict} |"
            )
    return rows


def runs_table(spec: Any, points: list[Point]) -> list[str]:
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


def versions(peers: list[PeerInfo]) -> str:
    return ", ".join(
        [
            f"Python {platform.python_version()}",
            f"NumPy {np.__version__}",
            f"SciPy {scipy.__version__}",
            f"matplotlib {matplotlib.__version__}",
            *(p.version for p in peers),
        ]
    )


def report_markdown(
    results: list[SceneResult],
    peers: list[PeerInfo],
    *,
    ours: str,
    missing: list[str],
    elapsed: float,
    quick: bool,
    rerun: list[str],
) -> str:
    """docs/report/README.md. ``ours``: how our engine was swept; ``missing``: a sentence per
    peer or scene that could not be run; ``rerun``: the scenes this run measured (the others
    are as stored, each section says when)."""
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    load = os.getloadavg()
    names = " and ".join(p.name for p in peers)
    lines = [
        f"# Speed against error: curved-edge-physics, {names}",
        "",
        f"Written by `make report` (`python -m bench.report`{' --quick' if quick else ''}) "
        f"on {now}, measuring {', '.join(rerun)} in {elapsed:.0f} s"
        f"{'' if len(rerun) == len(results) else ' (the other scenes as last measured)'}. "
        f"Machine: {machine()}. Versions: {versions(peers)}. "
        f"1-minute load average at the end: {load[0]:.1f} (other processes share the cores).",
        "",
        "Every point is one run of the whole scene; its wall time is the best of up to 3 "
        "identical runs (ours: `Run.wall_time` of `runtime.simulate`, which includes recording "
        "every step; a peer: its loop of steps and reading the body's pose and velocity, with "
        "the contact impulses and depths collected in a second, untimed pass). Errors are "
        "measured by the same code for every engine (bench/references.py). " + ours,
        "",
        *(f"{p.name}: {p.sweep}" for p in peers),
        "",
        "## Summary",
        "",
        "Ratios ours/peer (< 1: ours better), read off the two Pareto fronts (the best run of "
        "each engine at each cost, log-log interpolated) where both engines have measurements; "
        "*worst* is the largest ratio over the whole common range. The project's target: on the "
        "curved-edge scenes, at equal wall time our error is at least 100× smaller.",
        "",
        *summary_table(results),
        "",
        *(f"- {m}" for m in missing),
        "- Our error at the floor (≤ 1e-16, rounding) makes the error ratio an upper bound (≤).",
        "",
    ]
    for result in results:
        spec = result.spec
        lines += [f"## {spec.name}", "", f"![{spec.name}]({spec.name}.png)", "", spec.note, ""]
        if result.measured:
            lines += [f"Measured {result.measured}.", ""]
        for peer, cmp in result.comparisons.items():
            lines += [
                f"Against {peer}, primary error {cmp.metric}: common wall-time range "
                f"{_range(cmp.cost_range)} s, error ours/{peer} "
                f"{_ratio(cmp.error_ratio_mid, cmp.ours_at_floor)} at "
                f"{_g(cmp.extra.get('cost_mid', math.nan))} s; common error range "
                f"{_range(cmp.error_range)}, wall time ours/{peer} {_ratio(cmp.cost_ratio_mid)} "
                f"at {_g(cmp.extra.get('error_mid', math.nan))}, "
                f"{_ratio(cmp.cost_ratio_hardest, cmp.cost_hardest_is_bound)} at {peer}'s best "
                f"error {_g(cmp.extra.get('error_hardest', math.nan))}. Target (error ours/"
                f"{peer} ≤ 1/100 at equal wall time): {_verdict(cmp)}.",
                "",
            ]
        every = result.ours + [p for points in result.theirs.values() for p in points]
        lines += [
            *observations(result, peers),
            "",
            "<details><summary>All runs</summary>",
            "",
            *runs_table(spec, every),
            "",
            "</details>",
            "",
        ]
    return "\n".join(lines).rstrip("\n") + "\n"


def observations(result: SceneResult, peers: list[PeerInfo]) -> list[str]:
    """Facts read off the runs, as bullets: the best of each engine, and our runs whose contact
    force vanished while the body was still on the surface (held by impacts instead)."""
    metric = result.spec.reference.primary
    ours = result.ours
    notes = []
    for engine, points in (("ours", ours), *result.theirs.items()):
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
    for info in peers:
        theirs = result.theirs.get(info.name, [])
        if theirs and "dropped" in theirs[0].errors:
            shares = [p.errors["dropped"] for p in theirs]
            notes.append(
                f"{info.name} reports no impulse at {min(shares):.0%} – {max(shares):.0%} of its "
                "steps (its contact comes and goes)."
            )
        if theirs:
            notes.append(_iterations_note(info, theirs, metric))
    early = [p for p in ours if p.errors.get("leaving_angle", 0.0) > 0.1]
    if early:
        runs = ", ".join(f"{p.method} {p.setting}" for p in early)
        notes.append(
            f"Our runs whose contact force vanished more than 0.1 rad before the disc leaves: "
            f"{runs}. Their paths stay close (see the position error), but the contact is held "
            "by impacts, not a resting force, so the force does not show where the disc leaves."
        )
    return [f"- {n}" for n in notes]


def _iterations_note(info: PeerInfo, theirs: list[Point], metric: str) -> str:
    """Do the peer's solver iterations matter here? Each run labelled with more iterations
    (``... 50 it``, as the peers' configs label them) against the default run of the same dt and
    segments."""
    base = {(p.method, p.setting): p.errors[metric] for p in theirs}
    changes, more = [], 0
    for p in theirs:
        head, _, tail = p.method.rpartition(" ")
        if tail != "it":
            continue
        count = int(head.rsplit(" ", 1)[-1])
        plain = head.rsplit(" ", 1)[0].rstrip(",")
        ref = base.get((plain, p.setting))
        if ref:
            changes.append(p.errors[metric] / ref)
            more = max(more, count)
    if not changes:
        return f"{info.name}: one iteration count only."
    worst = max(max(changes), 1 / min(changes))
    if worst < 1 + 1e-9:
        return (
            f"{info.name}: {more} solver iterations give exactly the errors of "
            f"{info.base_iterations} (one contact: sequential impulses converge in one sweep), "
            "so their lines coincide."
        )
    if worst < 1.01:
        return f"{info.name}: {more} solver iterations change its {metric} by less than 1 %."
    return f"{info.name}: {more} solver iterations change its {metric} by up to {worst:.2g}×."


def bench_section(results: list[SceneResult], elapsed: float, rerun: list[str]) -> str:
    """The "## Report" section of bench/README.md: how to run it and the headline table."""
    lines = [
        SECTION,
        "",
        "Written by `python -m bench.report` (`make report`); the diagrams, all runs and the "
        f"details are in [docs/report/README.md](../docs/report/README.md). Last run: "
        f"{', '.join(rerun)} in {elapsed:.0f} s, {machine()}"
        f"{'' if len(rerun) == len(results) else ' (the other scenes as measured before)'}.",
        "",
        *summary_table(results),
        "",
    ]
    return "\n".join(lines)
