"""Whole-step speed: steps per second of piles of discs in a box, and how the cost grows with
the number of contacts (`make bench`, after the kernel benchmark).

The kernels' speed (bench/kernels.py) says little about a simulation: a step also finds the
contacts, resolves impacts, solves the contact LCP at every stage and records. So this times
whole steps of `runtime.simulate` on piles of discs built with `runtime.scene_from_dict`:

- resting piles of 10, 20, 50, 100 and 200 discs (packed hexagonally wall to wall: at rest): the
  contacts are those of the pile from the first step, so the time per step against the number
  of contacts gives the exponent p of time ~ contacts^p (a least-squares fit in log-log);
- falling piles of 10 and 50 discs (the same rows, a few millimetres apart): the discs land on
  each other, and the impacts and the growing contact set show what a step costs then.

Runs are cut into chunks of `simulate` calls, each continuing from the last state, so that a
pile stops after its time budget however slow its steps turn out. The time of each step comes
from `simulate`'s progress callback (the steps of a stretch it coasts in one compiled call share
the stretch's time evenly), its contacts from `Run.contacts` (the resting set that
enters the LCP).

    python -m bench.steps            # rewrites the "## Steps" section of bench/README.md
    python -m bench.steps --quick    # small piles, a few steps, README untouched (smoke test)
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import re
import signal
import sys
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import runtime
from bench.machine import cpu
from bench.markdown import replace_section
from runtime.app.estimate import per_step_times

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Steps"
KERNELS = "## Kernels"

RESTING = (10, 20, 50, 100, 200)  # discs; 10, 50 and 200 are the headline piles
FALLING = (10, 50)  # 200 falling discs take minutes per landing
RADIUS = 0.05  # m
GAP = 0.004  # m between neighbours in a row, and the drop of each row in a falling pile
METHOD = "rk4"  # the scenes' default integrator
DT = 1e-3  # s, the scenes' default step
BUDGET = 30.0  # s of wall time per pile (checked between chunks)
MAX_STEPS = {"resting": 40, "falling": 200}  # a falling pile lands within ~100 steps
WARM_STEPS = 10  # steps of a first, uncounted run of each pile (from the same start as the timed)
CHUNK_TIME = 0.5  # s of wall time per `simulate` call, about (a cut chunk loses contacts)


def pile_scene(n: int, drop: float = 0.0, gap: float = GAP):
    """`n` discs in a triangular pile in a box, via `runtime.scene_from_dict`.

    Rows alternate between k and k - 1 discs; every disc above the floor sits in the notch of
    two below it, touching both, and neighbours in a row are `gap` apart. The box is exactly as
    wide as the long rows, whose end discs lean on the walls. Everything touches at t = 0 (gap
    0 up to rounding) and nothing overlaps. With `drop` > 0 row j is lifted by j * drop: the
    bottom row rests and the others fall onto it.

    With `gap` = 0 the discs are packed hexagonally, wall to wall: the pile is at rest (its
    accelerations ~1e-13 m/s^2) and statically indeterminate (a third of its contacts depend on
    the others; the solver returns the least-norm forces) -- the resting pile the step
    benchmarks time. With `gap` > 0 (the default: bench/lcp.py's and bench/collide.py's
    problems) no disc has more supports than it needs and the forces are determined, but the
    frictionless pile is not in equilibrium: a disc pushed from one side more than the other
    slides into its gap, and the pile spreads (accelerations up to ~1.5 m/s^2 at the first
    step, the rows ~100x slower to step once they collide, from ~80 steps on).
    """
    k = max(2, math.ceil(math.sqrt(2 * n)))  # discs in a long row: the pile is about 2:1
    pitch = 2 * RADIUS + gap
    rise = math.sqrt((2 * RADIUS) ** 2 - (pitch / 2) ** 2)  # row to row, discs touching
    width = 2 * RADIUS + (k - 1) * pitch
    bodies, row = [], 0
    while len(bodies) < n:
        long_row = row % 2 == 0
        x0 = -width / 2 + RADIUS + (0.0 if long_row else pitch / 2)
        for i in range(min(k if long_row else k - 1, n - len(bodies))):
            bodies.append(
                {
                    "name": f"disc{len(bodies):03d}",
                    "shape": {"type": "disc", "radius": RADIUS},
                    "density": 1000.0,
                    "position": [x0 + i * pitch, RADIUS + row * (rise + drop)],
                }
            )
        row += 1
    box = {
        "name": "box",
        "fixed": True,
        "shape": {"type": "box_walls", "width": width, "height": (row + 1) * (rise + drop)},
    }
    data = {
        "scene": {"name": f"pile_{n}", "gravity": [0.0, -9.81]},  # restitution 0: they settle
        "simulation": {"duration": 1.0, "dt": DT, "method": METHOD},
        "body": [box, *bodies],
    }
    return runtime.scene_from_dict(data, source=f"pile_{n}")


@dataclass
class PileTiming:
    """Per-step wall times and resting-contact counts of one pile."""

    discs: int
    kind: str  # "resting" or "falling"
    step_times: np.ndarray  # s, one per step
    contacts: np.ndarray  # resting contacts of each step (-1: unknown, its chunk was cut)
    unfinished: float = 0.0  # s spent in a step the budget cut short (0: none was)

    @property
    def steps_per_second(self) -> float:
        return len(self.step_times) / float(np.sum(self.step_times))


def continued(scene, poses: np.ndarray, velocities: np.ndarray):
    """A copy of `scene` starting from the given state (centres of mass), to run the next chunk."""
    nxt = scene.copy()
    for body, q, v in zip(nxt.bodies, poses, velocities, strict=True):
        if not body.fixed:
            body.position, body.angle = (float(q[0]), float(q[1])), float(q[2])
            body.velocity, body.angular_velocity = (float(v[0]), float(v[1])), float(v[2])
    return nxt


def _chunk(scene, steps: int, marks: list[tuple[float, float]]) -> tuple[list[int], object]:
    """`steps` steps of `simulate`, appending (wall-clock time, fraction done) at each report
    of progress to `marks` (which holds the start; runtime.app.estimate.per_step_times gives
    each step's time); returns the resting contacts of each step and the run."""
    run = runtime.simulate(
        scene, steps * DT, DT, METHOD, progress=lambda f: marks.append((time.perf_counter(), f))
    )
    return [len(c) for c in run.contacts[:steps]], run


class OutOfTime(BaseException):
    """Raised by the alarm when a pile's budget is spent (a BaseException, so that no
    `except Exception` inside the engine swallows it)."""


@contextmanager
def deadline(seconds: float):
    """Interrupt the block after `seconds` of wall time with OutOfTime (SIGALRM, Unix): one
    landing step of a big pile can take minutes, and the budget must hold even then."""

    def ring(_signum, _frame):
        raise OutOfTime

    previous = signal.signal(signal.SIGALRM, ring)
    signal.setitimer(signal.ITIMER_REAL, max(seconds, 1e-3))
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        signal.signal(signal.SIGALRM, previous)


def time_pile(n: int, kind: str, budget: float = BUDGET) -> PileTiming:
    """Step a pile until MAX_STEPS or the budget, in chunks of about CHUNK_TIME seconds.

    A first chunk of WARM_STEPS steps, not counted, pays for the imports, the set-up and the
    loading of compiled code (the coasting loop loads at its first quiet stretch: ~0.2 s that
    had been counted in the 10-disc pile's steps) and gives the first estimate of a step's time; each chunk's first step also pays for `simulate`'s set-up, which
    is small against a step of a pile. When the budget runs out inside a chunk, its finished steps
    keep their times but not their contacts (those were in the lost `Run`), and the time
    already spent in the unfinished step is kept as a lower bound."""
    scene = pile_scene(n, drop=GAP, gap=GAP) if kind == "falling" else pile_scene(n, gap=0.0)
    warm_up = [(time.perf_counter(), 0.0)]
    _chunk(scene, WARM_STEPS, warm_up)
    times: list[float] = []
    contacts: list[int] = []
    marks: list[tuple[float, float]] = []
    steps, unfinished = 1, 0.0
    start = time.perf_counter()
    estimate = (warm_up[-1][0] - warm_up[0][0]) / WARM_STEPS  # an overestimate
    try:
        with deadline(budget):
            while len(times) < MAX_STEPS[kind]:
                left = min(CHUNK_TIME, budget - (time.perf_counter() - start))
                steps = int(np.clip(left / estimate, 1, MAX_STEPS[kind] - len(times)))
                marks = [(time.perf_counter(), 0.0)]
                chunk_contacts, run = _chunk(scene, steps, marks)
                chunk_times = per_step_times(marks, steps)
                times += chunk_times
                contacts += chunk_contacts
                estimate = max(float(np.mean(chunk_times)), 1e-4)  # the mean: impacts are slow
                scene = continued(scene, run.poses[-1], run.velocities[-1])
    except OutOfTime:
        unfinished = time.perf_counter() - marks[-1][0] if marks else 0.0
        cut = per_step_times(marks, steps)  # the cut chunk's finished steps: times known,
        times += cut  # contacts not (they were in its Run)
        contacts += [-1] * len(cut)
    return PileTiming(n, kind, np.array(times), np.array(contacts), unfinished)


def fit_exponent(timings: list[PileTiming]) -> tuple[float, float, int]:
    """p (and its standard error) of time per step ~ contacts^p.

    Steps are grouped by their number of contacts and the median time of each group is taken
    (so that a few slow steps -- impacts, a chunk's set-up -- do not drag the fit); a
    least-squares line through the groups in log-log gives p. Returns (p, standard error,
    number of groups).
    """
    times = np.concatenate([t.step_times for t in timings])
    counts = np.concatenate([t.contacts for t in timings])
    keep = counts > 0
    levels = np.unique(counts[keep])
    if len(levels) < 3:
        return math.nan, math.nan, len(levels)
    med = np.array([np.median(times[keep & (counts == m)]) for m in levels])
    x, y = np.log(levels), np.log(med)
    p, c = np.polyfit(x, y, 1)
    resid = y - (p * x + c)
    se = math.sqrt(float(resid @ resid) / (len(x) - 2) / float(((x - x.mean()) ** 2).sum()))
    return float(p), se, len(levels)


def kernel_summary(readme: Path = README) -> list[str]:
    """The per-call kernel times quoted from the "## Kernels" section, if it is there."""
    text = readme.read_text() if readme.exists() else ""
    section = re.search(rf"^{re.escape(KERNELS)}\n(.*?)(?=^## |\Z)", text, flags=re.M | re.S)
    if not section:
        return ['(No "## Kernels" section in bench/README.md: run `python -m bench.kernels`.)']
    rows = re.findall(r"^\| ([\d,]+) \| ([^|]+) \|.*\| ([^|]+) \|\s*$", section.group(1), re.M)
    quoted = [
        f"N = {n.strip()} ({inputs.strip()}): {median.strip()} µs"
        for n, inputs, median in rows
        if "[" in median
    ]
    if not quoted:
        return ['(The "## Kernels" section has no summary table to quote.)']
    return [
        "Kernel speed, quoted from the Kernels section above (generated kernels, median [max] µs "
        "per call over the 28 functions): " + "; ".join(quoted) + "."
    ]


def _median(values: np.ndarray) -> float:
    return float(np.median(values)) if len(values) else 0.0


def _row(t: PileTiming) -> str:
    """One pile's line of the table."""
    if len(t.step_times) == 0:
        rate = f"< {1 / t.unfinished:.2g}" if t.unfinished else "—"
        return f"| {t.discs} | {t.kind} | 0 | {rate} | — | — | — |"
    with_contacts = t.contacts > 0
    per_contact = t.step_times[with_contacts] / t.contacts[with_contacts]
    known = t.contacts[t.contacts >= 0]  # -1: a step of a chunk the budget cut
    counts = f"{known[0]} → {known[-1]} [{known.max()}]" if known.size else "—"
    if known.size < t.contacts.size:
        counts += f" ({t.contacts.size - known.size} steps unknown)"
    return (
        f"| {t.discs} | {t.kind} | {len(t.step_times)} | {t.steps_per_second:.3g} | "
        f"{1e3 * np.median(t.step_times):.3g} [{1e3 * t.step_times.max():.3g}] | "
        f"{counts} | "
        f"{f'{1e6 * np.median(per_contact):.3g}' if per_contact.size else '—'} |"
    )


def section(timings: list[PileTiming], fit: tuple[float, float, int], elapsed: float) -> str:
    """The "## Steps" section of bench/README.md."""
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    p, se, levels = fit
    load = os.getloadavg()[0]
    lines = [
        SECTION,
        "",
        f"Written by `python -m bench.steps` (`make bench`); run {now} on {cpu()}, Python "
        f"{platform.python_version()}, NumPy {np.__version__}; {elapsed:.0f} s, 1-minute load "
        f"average {load:.1f} at the end (other processes share the cores).",
        "",
        f"Whole steps of `runtime.simulate` ({METHOD}, dt = {DT:g} s; all a step does: contacts, "
        "impacts, the LCP at every stage, recording) on piles of discs "
        f"(r = {RADIUS:g} m, restitution 0) in a box, built with `runtime.scene_from_dict`. "
        "*Resting*: packed hexagonally, wall to wall (every disc touching its neighbours in "
        "its row and the two below it) -- at rest from the first step, and statically "
        "indeterminate (a third of the contacts depend on the others). *Falling*: rows with "
        f"neighbours {GAP * 1e3:g} mm apart, each lifted by {GAP * 1e3:g} mm, so they land on "
        "each other. Contacts = the resting contacts of a step (the LCP's size). Each pile runs "
        f"until {MAX_STEPS['resting']} (resting) or {MAX_STEPS['falling']} (falling) steps or "
        f"{BUDGET:g} s of wall time.",
        "",
        "| discs | pile | steps timed | steps/s | ms per step: median [max] | contacts: first → "
        "last [max] | µs per step and contact (median) |",
        "|---|---|---|---|---|---|---|",
    ]
    for t in timings:
        lines.append(_row(t))
    stopped = [t for t in timings if t.unfinished > 5 * _median(t.step_times)]
    if stopped:
        lines += [
            "",
            "Stopped by the budget in the middle of a long step (the time it had taken so far, "
            "a lower bound; not in the table's times): "
            + "; ".join(f"{t.discs} {t.kind}: {t.unfinished:.1f} s" for t in stopped)
            + ".",
        ]
    lines += [
        "",
        f"Cost growth on the resting piles: time per step ~ contacts^p with **p = {p:.2f} ± "
        f"{se:.2f}** (least squares in log-log through the median step time of each of "
        f"{levels} contact counts).",
        "",
        *kernel_summary(),
        "",
    ]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small piles, no README")
    args = parser.parse_args(argv)
    start = time.perf_counter()
    plan = [(n, "resting") for n in RESTING] + [(n, "falling") for n in FALLING]
    if args.quick:
        plan = [(10, "resting"), (20, "resting"), (50, "resting"), (10, "falling")]
    timings = []
    for n, kind in plan:
        t0 = time.perf_counter()
        timing = time_pile(n, kind, budget=2.0 if args.quick else BUDGET)
        timings.append(timing)
        print(f"{_row(timing)}  ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    fit = fit_exponent([t for t in timings if t.kind == "resting"])
    text = section(timings, fit, time.perf_counter() - start)
    print(text)
    if not args.quick:
        replace_section(README, SECTION, text, before="## Report")


if __name__ == "__main__":
    main()
