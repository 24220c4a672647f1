"""Soak test: random valid scenes for minutes, counting every way a run can go wrong.

The fuzz tests (tests/runtime/test_fuzz.py) run a fixed set of a few hundred small scenes in
CI; this runs the same generator and the same checks (tests/strategies.py) unseeded, with more
bodies and longer runs, for as long as asked, and counts what happens by kind:

- ``generator``: a SceneError for a drawn scene: a bug of the generator or a false alarm of
  the loader (the scenes are valid by construction);
- ``simulation``: a SimulationError (documented), counted by its cause (the message with the
  numbers taken out);
- ``exception``: any other exception, with a short traceback summary;
- ``timeout``: one scene took longer than ``--scene-timeout`` (stopped with SIGALRM);
- ``nan``, ``warning``, ``energy``, ``penetration``, ``escaped``, ``bad-error``: the property
  checks of tests/strategies.check_run (non-finite numbers, NumPy RuntimeWarnings, energy
  growth beyond 1e-6 of the energy scale with RK4/midpoint, penetration deeper than 1e-3
  half-widths, a centre of mass below the floor or outside the box, a SimulationError
  without step and time or with a bad state).

Each scene's time step is drawn so that no body moves more than ``travel`` half-widths of the
thinnest body per step; ``--travel`` gives the values to cycle through (default 0.1, what CI
uses, and 1 and 3: steps too coarse for the geometry, where the engine must either cope or
say so). The table has one count column per travel. Every failing scene is written, as the
dict for ``runtime.scene_from_dict``, to ``out/soak/failures.jsonl`` (one JSON object a line,
with its kinds and details) so it can be replayed:

    python -m bench.soak                   # 10 minutes; prints the table and writes the
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
import platform
import signal
import sys
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

README = ROOT / "bench" / "README.md"
SECTION = "## Soak"
OUT = ROOT / "out" / "soak"
BATCH = 25  # examples per Hypothesis run (each run draws afresh; travels alternate by run)


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
        self.scenes = collections.Counter()
        self.steps = 0
        self.bodies = collections.Counter()
        self.slowest = (0.0, "")
        self.scene_time = 0.0

    def record(self, drawn: S.Drawn, travel: float) -> None:
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
        self.bodies[len(drawn.bodies) - 1] += 1
        if report.run is not None:
            self.steps += max(len(report.run.t) - 1, 0)
        for kind, details in report.problems.items():
            key = (kind, _key(kind, details[0]))
            self.counts[key][travel] += 1
            self.example.setdefault(key, details[0])
        if report.problems and self.failures is not None:
            with self.failures.open("a") as out:
                entry = {"travel": travel, "problems": report.problems, "data": drawn.data}
                out.write(json.dumps(entry, default=_jsonable) + "\n")

    def run(self, seconds: float) -> None:
        deadline = time.monotonic() + seconds
        batch = 0
        while time.monotonic() < deadline:
            self.batch(self.travels[batch % len(self.travels)], deadline)
            batch += 1

    def batch(self, travel: float, deadline: float) -> None:
        """One Hypothesis run of up to BATCH scenes (generation only: nothing is shrunk; the
        checks never raise, they count)."""

        @settings(
            max_examples=BATCH,
            deadline=None,
            database=None,
            phases=[Phase.generate],
            suppress_health_check=list(HealthCheck),
        )
        @given(S.drawn_scenes(max_bodies=6, steps=(20, 200), travel=travel))
        def one(drawn):
            if time.monotonic() < deadline:
                self.record(drawn, travel)

        one()

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


def _md(text: str) -> str:
    return "`" + text.replace("|", "\\|").replace("`", "'")[:160] + "`"


def _jsonable(value: Any) -> Any:
    if isinstance(value, np.generic):
        return value.item()
    return str(value)


def section(soak: Soak, minutes: float, wall: float) -> str:
    when = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    total = sum(soak.scenes.values())
    failing = sum(sum(c.values()) for c in soak.counts.values())
    bodies = ", ".join(f"{n}: {soak.bodies[n]}" for n in sorted(soak.bodies))
    lines = [
        SECTION,
        "",
        "Written by `python -m bench.soak` (`make soak`, not in CI); rerun it to refresh this "
        "section.",
        "",
        f"Run {when} on {cpu()}; Python {platform.python_version()}, NumPy "
        f"{np.__version__}. {minutes:g} minutes asked, {wall:.0f} s taken: {total} random "
        f"scenes ({bodies} moving bodies; sizes 1e-3 .. 1e3 m; a floor or a box; 20-200 "
        f"steps each, {soak.steps} steps in all, {soak.scene_time / max(total, 1):.2f} s a "
        f"scene on average, slowest {soak.slowest[0]:.1f} s), generated and checked as in "
        "tests/runtime/test_fuzz.py (tests/strategies.py). *travel*: the most a body may move "
        "in one step, in half-widths of the thinnest body (0.1 is what the fuzz tests use; "
        "1 and 3 are time steps too coarse for the geometry). A scene can count under "
        f"several kinds; {failing} failures in all. Failing scenes: `out/soak/failures.jsonl`.",
        "",
        *soak.table(),
        "",
        "Kinds: " + "; ".join(f"*{k}*: {v}" for k, v in S.KINDS.items()) + "; *timeout*: one "
        "scene ran longer than the per-scene limit.",
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
    soak.run(60.0 * args.minutes)
    wall = time.perf_counter() - start
    text = section(soak, args.minutes, wall)
    print(text)
    if not args.no_readme:
        replace_section(README, SECTION, text)
        print(f"\nwrote the {SECTION!r} section of {README.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
