"""Soak test: random valid scenes for minutes, counting every way a run can go wrong.

The fuzz tests (tests/runtime/test_fuzz.py) run a fixed set of a few hundred small scenes in
CI; this runs the same generators and the same checks (tests/strategies.py) unseeded, with more
bodies and longer runs, for as long as asked. Three families of scenes take turns: ``scenes``
(1-6 bodies of every shape, ovals included, some at angles up to 1e11 turns, on a floor or in a
box, sizes 1e-3 .. 1e3 m), ``masses`` (the same with densities over nine decades: mass ratios
beyond 1e9) and ``pairs`` (2-3 bodies flying at each other in empty space, sizes 1e-4 .. 1e4 m,
where momentum must be conserved too). Each scene's time step is drawn so that no body moves
more than ``travel`` half-widths of the thinnest body per step; ``--travel`` gives the values to
cycle through (default 0.1, what CI uses, and 1 and 3: 10x and 30x coarser, steps too coarse
for the geometry, where the engine must either cope or say so).

Each scene ends in one outcome:

- ``ok``: no problem;
- ``caught``: a SimulationError naming the step, the time and the cause (a guard, a solver
  failure): the engine said so;
- ``silent``: the run ended "successfully" but a property check of tests/strategies.check_run
  failed beyond what the engine's guards promise to catch (penetration deeper than
  settings.PENETRATION_LIMIT of the smaller body's bounding radius, energy growth beyond
  settings.ENERGY_GROWTH_LIMIT of the guard's energy scale, a centre of mass through a wall,
  momentum not conserved in empty space): a silent wrong result;
- ``inaccurate``: it failed a property check only by the CI bounds (1e-3 half-widths of
  penetration, 1e-6 of the energy scale), within the guards' limits: at CI step sizes that is a
  silent failure too, at coarse steps it is the price of the step;
- ``crash``: any other exception, a SimulationError without step and time, a NaN, a NumPy
  RuntimeWarning, a scene the loader refused (a generator bug), or one that took longer than
  ``--scene-timeout``.

Meanwhile interrupted writes (bench/soak_writes.py) run in the background: a `simulate --force`
rerun killed at a random instant, and the output folder checked. Every failing scene is written,
as the dict for ``runtime.scene_from_dict``, to ``out/soak/failures.jsonl`` (one JSON object a
line, with its kinds and details) so it can be replayed:

    python -m bench.soak                   # 10 minutes; prints the tables and writes the
                                           # "## Soak" section of bench/README.md
    python -m bench.soak --minutes 1 --no-readme
    python -m bench.soak --replay out/soak/failures.jsonl

Not run in CI (`make soak` runs it).
"""

from __future__ import annotations

import argparse
import collections
import datetime
import json
import math
import os
import platform
import random
import signal
import sys
import threading
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))  # tests/strategies.py: the generator and the checks

import numpy as np  # noqa: E402
import strategies as S  # noqa: E402
from hypothesis import HealthCheck, Phase, given, settings  # noqa: E402

from bench.machine import cpu  # noqa: E402
from bench.markdown import replace_section  # noqa: E402
from bench.soak_writes import OUTCOMES, interrupted_write  # noqa: E402

README = ROOT / "bench" / "README.md"
SECTION = "## Soak"
OUT = ROOT / "out" / "soak"
BATCH = 10  # examples per Hypothesis run (each draws afresh; families, then travels, alternate)
FAMILIES = {
    "scenes": lambda travel: S.drawn_scenes(max_bodies=6, steps=(20, 200), travel=travel),
    "masses": lambda travel: S.drawn_scenes(
        max_bodies=4, steps=(20, 200), travel=travel, densities=9.0
    ),
    "pairs": lambda travel: S.moving_pairs(travel=travel, max_steps=200),
}
OUTCOME_ROWS = {
    "ok": "ok",
    "caught": "caught: a SimulationError naming step, time and cause",
    "silent": "silent: wrong beyond the guards' limits, no error",
    "inaccurate": "inaccurate: past the CI bounds, within the guards' limits",
    "crash": "crash: other exception, NaN, warning, timeout, refused scene",
}
CRASHES = ("generator", "exception", "bad-error", "nan", "warning", "timeout")


def outcome(report: S.Report) -> str:
    """The scene's outcome (a key of OUTCOME_ROWS; see the module docstring)."""
    kinds = set(report.problems)
    if kinds & set(CRASHES):
        return "crash"
    if "simulation" in kinds:
        return "caught"
    if report.beyond:
        return "silent"
    return "inaccurate" if kinds else "ok"


class SceneTimeout(BaseException):  # not caught by the checks' `except Exception`
    """One scene ran longer than --scene-timeout."""


def _alarm(_signum, _frame):
    raise SceneTimeout


class Soak:
    """Counts by (kind, detail key) and travel; keeps the first example of each."""

    def __init__(self, travels: list[float], timeout: float, failures: Path | None) -> None:
        self.travels = travels
        self.timeout = timeout
        self.failures = failures
        self.counts: dict[tuple[str, str], collections.Counter] = collections.defaultdict(
            collections.Counter
        )
        self.example: dict[tuple[str, str], str] = {}
        self.outcomes: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
        self.families = collections.Counter()
        self.writes = collections.Counter()
        self.write_examples: dict[str, str] = {}
        self.scenes = collections.Counter()
        self.steps = 0
        self.bodies = collections.Counter()
        self.slowest = (0.0, "")
        self.scene_time = 0.0

    def record(self, drawn: S.Drawn, travel: float, family: str = "scenes") -> None:
        start = time.perf_counter()
        signal.setitimer(signal.ITIMER_REAL, self.timeout)
        try:
            report = S.check_scene(drawn, source="soak")
        except SceneTimeout:
            report = S.Report(drawn)
            report.add("timeout", f"longer than {self.timeout:g} s")
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        took = time.perf_counter() - start
        self.scene_time += took
        if took > self.slowest[0]:
            self.slowest = (took, drawn.data["scene"]["name"])
        self.scenes[travel] += 1
        self.families[family] += 1
        self.outcomes[outcome(report)][travel] += 1
        self.bodies[sum(1 for b in drawn.bodies if not b.get("fixed"))] += 1
        if report.run is not None:
            self.steps += max(len(report.run.t) - 1, 0)
        for kind, details in report.problems.items():
            key = (kind, _key(kind, details[0]))
            self.counts[key][travel] += 1
            self.example.setdefault(key, details[0])
        if report.problems and self.failures is not None:
            with self.failures.open("a") as out:
                entry = {"travel": travel, "family": family, "outcome": outcome(report),
                         "problems": report.problems, "data": drawn.data}  # fmt: skip
                out.write(json.dumps(entry, default=_jsonable) + "\n")

    def run(self, seconds: float, writes: bool = True) -> None:
        deadline = time.monotonic() + seconds
        writer = threading.Thread(target=self.write_cases, args=(deadline,), daemon=True)
        if writes:
            writer.start()
        batch = 0
        families = list(FAMILIES)
        while time.monotonic() < deadline:
            family = families[batch % len(families)]
            travel = self.travels[(batch // len(families)) % len(self.travels)]
            self.batch(travel, deadline, family)
            batch += 1
        if writes:
            writer.join()

    def write_cases(self, deadline: float) -> None:
        """Interrupted writes (bench/soak_writes.py) until the deadline, in this thread (the
        command runs in its own process)."""
        rng = random.Random()
        while time.monotonic() < deadline - 40.0:  # a case takes ~30 s
            try:
                kind, detail = interrupted_write(rng)
            except Exception as exc:  # noqa: BLE001 -- counted
                kind, detail = "corrupt", f"the case failed: {type(exc).__name__}: {exc}"
            self.writes[kind] += 1
            self.write_examples.setdefault(kind, detail)

    def batch(self, travel: float, deadline: float, family: str = "scenes") -> None:
        """One Hypothesis run of up to BATCH scenes (generation only: nothing is shrunk; the
        checks never raise, they count)."""

        @settings(
            max_examples=BATCH,
            deadline=None,
            database=None,
            phases=[Phase.generate],
            suppress_health_check=list(HealthCheck),
        )
        @given(FAMILIES[family](travel))
        def one(drawn):
            if time.monotonic() < deadline:
                self.record(drawn, travel, family)

        one()

    def outcome_table(self) -> list[str]:
        heads = " | ".join(f"travel {t:g}" for t in self.travels)
        lines = [
            f"| outcome | {heads} |",
            "|---|" + "---|" * len(self.travels),
            f"| scenes run | {' | '.join(str(self.scenes[t]) for t in self.travels)} |",
        ]
        for key, label in OUTCOME_ROWS.items():
            cells = " | ".join(str(self.outcomes[key][t]) for t in self.travels)
            lines.append(f"| {label} | {cells} |")
        return lines

    def write_table(self) -> list[str]:
        total = sum(self.writes.values())
        lines = [
            f"| interrupted `simulate --force` reruns | {total} | first example |",
            "|---|---|---|",
        ]
        for key, label in OUTCOMES.items():
            example = self.write_examples.get(key, "")
            lines.append(
                f"| {key}: {label} | {self.writes[key]} | {_md(example) if example else ''} |"
            )
        return lines

    def table(self) -> list[str]:
        heads = " | ".join(f"travel {t:g}" for t in self.travels)
        lines = [
            f"| kind | cause or first detail | {heads} |",
            "|---|---|" + "---|" * len(self.travels),
            f"| scenes run | | {' | '.join(str(self.scenes[t]) for t in self.travels)} |",
        ]
        for (kind, key), counter in sorted(self.counts.items(), key=lambda kv: kv[0]):
            cells = " | ".join(str(counter[t]) for t in self.travels)
            detail = key if kind in ("simulation", "exception") else self.example[(kind, key)]
            lines.append(f"| {kind} | {_md(detail)} | {cells} |")
        if not self.counts:
            lines.append(f"| (no failure) | | {' | '.join('0' for _ in self.travels)} |")
        return lines


def _key(kind: str, detail: str) -> str:
    """What failures of a kind are grouped by: the cause for simulation errors, type and
    place for other exceptions, nothing (one row) for the property checks."""
    if kind in ("simulation", "exception"):
        return detail
    return ""


def _load() -> str:
    """The 1-, 5- and 15-minute load averages (the machine is shared)."""
    return ", ".join(f"{x:.1f}" for x in os.getloadavg())


def _md(text: str) -> str:
    return "`" + text.replace("|", "\\|").replace("`", "'")[:160] + "`"


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return str(value)


def section(soak: Soak, minutes: float, wall: float, load: str) -> str:
    when = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    total = sum(soak.scenes.values())
    bodies = ", ".join(f"{n}: {soak.bodies[n]}" for n in sorted(soak.bodies))
    families = ", ".join(f"{k}: {soak.families[k]}" for k in FAMILIES)
    lines = [
        SECTION,
        "",
        "Written by `python -m bench.soak` (`make soak`, not in CI); rerun it to refresh this "
        "section.",
        "",
        f"Run {when} on {cpu()}, shared (load average {load}); Python "
        f"{platform.python_version()}, NumPy {np.__version__}. {minutes:g} minutes asked, "
        f"{wall:.0f} s taken: {total} random scenes by family ({families}; see the docstring "
        f"of bench/soak.py), by moving bodies ({bodies}); 20-200 steps each, {soak.steps} "
        f"steps in all, {soak.scene_time / max(total, 1):.2f} s a scene on average, slowest "
        f"{soak.slowest[0]:.1f} s; generated and checked as in tests/runtime/test_fuzz.py "
        "(tests/strategies.py). *travel*: the most a body may move in one step, in "
        "half-widths of the thinnest body: 0.1 is what the fuzz tests use (CI step sizes), 1 "
        "and 3 are 10x and 30x coarser. Failing scenes: `out/soak/failures.jsonl` "
        "(`--replay` reruns them).",
        "",
        "Outcome of each scene (the targets: *silent* and *inaccurate* 0 at travel 0.1; at "
        "coarser steps every failure *caught*, i.e. *silent* 0):",
        "",
        *soak.outcome_table(),
        "",
        "What failed, by kind (a scene can count under several):",
        "",
        *soak.table(),
        "",
        "Kinds: " + "; ".join(f"*{k}*: {v}" for k, v in S.KINDS.items()) + "; *timeout*: one "
        "scene ran longer than the per-scene limit.",
        "",
        "Interrupted writes, in the background meanwhile (bench/soak_writes.py: a shipped "
        "scene's `simulate --force` rerun sent SIGINT, SIGTERM or SIGKILL at a random "
        "instant, then the folder checked, then one more run that must take over a dead "
        "run's lock and leave nothing beside the folder):",
        "",
        *soak.write_table(),
    ]
    return "\n".join(lines)


def replay(path: Path) -> int:
    """Run the scenes of a failures file again and print what each gives now."""
    import runtime

    for number, line in enumerate(path.read_text().splitlines(), 1):
        entry = json.loads(line)
        scene = runtime.scene_from_dict(entry["data"], source=f"{path}:{number}")
        try:
            run = runtime.simulate(scene)
            outcome = f"ok, {len(run.t) - 1} steps"
        except Exception as exc:  # noqa: BLE001 -- shown, not handled
            outcome = f"{type(exc).__name__}: {exc}"
        print(f"{path}:{number}: was {sorted(entry['problems'])}; now {outcome[:200]}")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m bench.soak", description=__doc__.split("\n")[0]
    )
    parser.add_argument("--minutes", type=float, default=10.0, help="how long (default 10)")
    parser.add_argument(
        "--travel",
        default="0.1,1,3",
        help="comma-separated travels per step to cycle through (default 0.1,1,3)",
    )
    parser.add_argument(
        "--scene-timeout", type=float, default=60.0, help="s per scene before giving up"
    )
    parser.add_argument("--no-readme", action="store_true", help="leave bench/README.md alone")
    parser.add_argument("--no-writes", action="store_true", help="no interrupted-write cases")
    parser.add_argument("--replay", type=Path, help="rerun the scenes of a failures.jsonl")
    args = parser.parse_args(argv)
    if args.replay:
        return replay(args.replay)
    if not (math.isfinite(args.minutes) and args.minutes > 0):
        parser.error(f"--minutes must be > 0, got {args.minutes}")
    travels = [float(t) for t in args.travel.split(",") if t.strip()]
    OUT.mkdir(parents=True, exist_ok=True)
    failures = OUT / "failures.jsonl"
    failures.unlink(missing_ok=True)
    signal.signal(signal.SIGALRM, _alarm)
    soak = Soak(travels, args.scene_timeout, failures)
    start = time.perf_counter()
    soak.run(60.0 * args.minutes, writes=not args.no_writes)
    wall = time.perf_counter() - start
    text = section(soak, args.minutes, wall, _load())
    print(text)
    if not args.no_readme:
        replace_section(README, SECTION, text)
        print(f"\nwrote the {SECTION!r} section of {README.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
