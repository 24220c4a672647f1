"""Mutation testing (`make mutate`): do the tests catch the bugs they are there for?

Each mutant of bench/mutants.py is applied, one at a time, to a fresh scratch copy of the
repository (the working tree is never touched; uncommitted files are included), and the tests it
names run there: `python -m pytest -x -q` with a timeout. A failing test kills the mutant; a
mutant that passes its tests survives; one whose tests outlast --timeout is a timeout (not
killed: its own line). First the named tests run once on the unmutated copy (the baseline must
pass, or every mutant would look killed); that run also builds the warm numba cache. A mutant
starts from a copy of the warm cache without the entries of every compiled function the mutated
file can reach (bench/mutate_cache.py: its own, and those of the modules that import it,
directly or through others), so that code is rebuilt from the mutated sources and the rest loads.

Prints killed/survived/timeout per mutant (with the test that killed it), the survivors and the
score, and writes the "## Mutation testing" section of bench/README.md. Exit status 1 when the
score is below --min-score or a mutant no longer applies (its text is gone: update
bench/mutants.py).

    python -m bench.mutate                        # every mutant (~35 minutes on 2 busy cores)
    python -m bench.mutate --only circle_circle   # mutants whose name contains the text
    python -m bench.mutate --list
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

from bench.machine import cpu
from bench.markdown import replace_section
from bench.mutants import MUTANTS, NOTES, SURVIVOR_NOTES, Mutant
from bench.mutate_cache import cache_folder, stale_files, warm_copy

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "bench" / "README.md"
SECTION = "## Mutation testing"


class MutantError(ValueError):
    """A mutant that cannot be applied (its text is not where it says)."""


def mutated(mutant: Mutant, text: str) -> str:
    """`text` with the mutant's replacement: the only occurrence of `old`, or the first one
    after the (unique) `within` anchor."""
    start = 0
    if mutant.within:
        if text.count(mutant.within) != 1:
            found = text.count(mutant.within)
            raise MutantError(f"{mutant.name}: anchor {mutant.within!r} occurs {found} times")
        start = text.index(mutant.within)
    elif text.count(mutant.old) != 1:
        found = text.count(mutant.old)
        raise MutantError(f"{mutant.name}: {mutant.old!r} occurs {found} times (give `within`)")
    where = text.find(mutant.old, start)
    if where < 0:
        raise MutantError(f"{mutant.name}: {mutant.old!r} not found in {mutant.path}")
    return text[:where] + mutant.new + text[where + len(mutant.old) :]


@dataclass
class Outcome:
    mutant: Mutant
    status: str  # killed, survived, timeout (not killed), error
    detail: str
    seconds: float
    cache: str = ""  # cold (compiled afresh), warm (the baseline's cache), warm -N (without
    # the entries of N files whose compiled code the mutant can change)

    @property
    def killed(self) -> bool:
        return self.status == "killed"


def _repository_files() -> list[str]:
    """Tracked and untracked (not ignored) files of the working tree, as it is now."""
    listed = subprocess.run(
        ["git", "ls-files", "-co", "--exclude-standard", "-z"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return [f for f in listed.split("\0") if f and (ROOT / f).is_file()]


def _copy_tree(files: list[str], source: Path, target: Path) -> None:
    shutil.rmtree(target, ignore_errors=True)
    for name in files:
        (target / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(source / name, target / name)


def _environment(work: Path, cache: Path) -> dict[str, str]:
    env = dict(os.environ)
    env.update(
        PYTHONPATH=str(work),
        CURVED_EDGE_CACHE=str(cache),
        PYTHONDONTWRITEBYTECODE="1",
        MPLBACKEND="Agg",
    )
    return env


def _run(command: list[str], work: Path, env: dict, timeout: float):
    """(return code or None on timeout, combined output). On a timeout the whole process group
    is killed: a test's own subprocesses too, which would otherwise hold the pipes open."""
    process = subprocess.Popen(
        command,
        cwd=work,
        env=env,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        start_new_session=True,
    )
    try:
        out, _ = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        process.communicate()
        return None, ""
    except BaseException:  # interrupted (Ctrl-C, SIGTERM): no test left running
        os.killpg(process.pid, signal.SIGKILL)
        raise
    return process.returncode, out


def _pytest(targets: list[str], work: Path, env: dict, timeout: float):
    command = [sys.executable, "-m", "pytest", "-x", "-q", "-p", "no:cacheprovider"]
    return _run(command + targets, work, env, timeout)


def last_killers(readme: Path = README) -> dict[str, str]:
    """Mutant -> the test that killed it in the last run (bench/README.md's table)."""
    found = re.search(rf"^{SECTION}\n(.*?)(?=^## |\Z)", readme.read_text(), flags=re.M | re.S)
    killers = {}
    for row in (found[1] if found else "").splitlines():
        cells = [c.strip().replace("\\|", "|") for c in re.split(r"(?<!\\)\|", row)[1:-1]]
        if len(cells) >= 4 and cells[2] == "killed" and "::" in cells[-1]:
            killers[cells[0].strip("`")] = cells[-1]
    return killers


def _first_failure(output: str) -> str:
    """The first failing test's id (which may hold spaces), or the output's last line."""
    found = re.search(r"^(?:FAILED|ERROR) (.+?)(?: - |$)", output, flags=re.M)
    return found[1] if found else output.strip().splitlines()[-1] if output.strip() else "?"


def _check_imports(work: Path, env: dict) -> None:
    """The scratch copy's packages, not the installed ones, must be the ones imported."""
    code = "import derive, generated, runtime; print(derive.__file__, generated.__file__, runtime.__file__)"
    rc, out = _run([sys.executable, "-c", code], work, env, 120)
    if rc != 0 or any(not p.startswith(str(work)) for p in out.split()):
        raise SystemExit(f"mutate: the scratch copy is not what Python imports: {out.strip()}")


def run_mutant(
    mutant: Mutant, files, pristine: Path, work: Path, env, timeout, warm, first=""
) -> Outcome:
    """Apply `mutant` to a fresh copy of `pristine` in `work` and run its tests there, with a
    copy of the `warm` cache folder less what the mutant can change (cold without one). The
    test `first` (the last run's killer) runs alone first: the fastest way to the first failure
    when it still kills; the named tests run when it passes (or is gone)."""
    start = time.perf_counter()
    _copy_tree(files, pristine, work)
    target = work / mutant.path
    target.write_text(mutated(mutant, target.read_text()))
    cache = Path(env["CURVED_EDGE_CACHE"])
    shutil.rmtree(cache, ignore_errors=True)
    state = "cold"

    def outcome(status: str, detail: str) -> Outcome:
        return Outcome(mutant, status, detail, time.perf_counter() - start, state)

    if mutant.regenerate:
        rc, out = _run([sys.executable, "-m", "derive", "--no-pdf"], work, env, timeout)
        if rc is None:
            return outcome("timeout", "regenerate-equations timed out")
        if rc != 0:
            if "proofs fail" in out:
                return outcome("killed", "the proofs (regenerate-equations refused)")
            return outcome("error", "regenerate-equations: " + out.strip().splitlines()[-1])
    if warm is not None:
        dropped = warm_copy(warm, cache_folder(work, env), work, stale_files(pristine, work))
        state = f"warm -{dropped}" if dropped else "warm"
    rc = 0
    if first:
        rc, out = _pytest([first], work, env, timeout - (time.perf_counter() - start))
    if rc not in (1, None):
        rc, out = _pytest(mutant.tests.split(), work, env, timeout - (time.perf_counter() - start))
    if rc is None:
        return outcome("timeout", f"tests still running after {timeout:.0f} s")
    if rc == 0:
        return outcome("survived", "")
    if rc == 1:
        return outcome("killed", _first_failure(out))
    return outcome("error", f"pytest exit {rc}: {_first_failure(out)}")


def _baseline_targets(chosen: list[Mutant]) -> list[str]:
    """Every named test once: a test id (file::name) is dropped when its file is named too."""
    named = dict.fromkeys(t for m in chosen for t in m.tests.split())
    return [t for t in named if "::" not in t or t.split("::")[0] not in named]


def section(outcomes: list[Outcome], wall: float, load: tuple[float, float]) -> str:
    killed = sum(o.killed for o in outcomes)
    lines = [
        SECTION,
        "",
        "Written by `python -m bench.mutate` (`make mutate`, not part of `make test`); the"
        " mutants are listed in bench/mutants.py (one line each: file, exact text, replacement,"
        " the tests that should catch it). Each runs against its tests in a scratch copy of the"
        " repository (pytest -x). Tests that only compare files (the stale check) are never"
        " named: a mutant must be caught by a test of the physics or the mathematics."
        " Each starts from a copy of the numba cache the unmutated baseline run built, less"
        " the entries of the compiled functions the mutated file can reach (warm -N: those of"
        " N files dropped; bench/mutate_cache.py). A timeout is not a kill.",
        "",
        f"Run {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} on {cpu()}; "
        f"{len(outcomes)} mutants in {wall / 60:.1f} min (load average {load[0]:.1f} before, "
        f"{load[1]:.1f} after). **Score: {killed}/{len(outcomes)} killed "
        f"({100 * killed / max(len(outcomes), 1):.1f} %).**",
        "",
        "| mutant | the bug it models | result | seconds (cache) | caught by |",
        "|---|---|---|---|---|",
    ]
    for o in outcomes:
        caught = o.detail if o.killed else ""
        cells = (
            f"`{o.mutant.name}`",
            o.mutant.what,
            o.status,
            f"{o.seconds:.0f} ({o.cache})",
            caught,
        )
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    survivors = [o for o in outcomes if not o.killed]
    lines += ["", "Survivors:" if survivors else "No survivors."]
    for o in survivors:
        note = SURVIVOR_NOTES.get(o.mutant.name, "not explained yet: a missing test")
        lines.append(f"- `{o.mutant.name}` ({o.status}): {note}")
    return "\n".join([*lines, "", NOTES]) + "\n"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.mutate", description=__doc__)
    parser.add_argument("--only", help="run the mutants whose name contains this text")
    parser.add_argument("--list", action="store_true", help="list the mutants and exit")
    parser.add_argument("--timeout", type=float, default=900.0, help="seconds per test run")
    parser.add_argument("--min-score", type=float, default=95.0, help="percent killed to pass")
    parser.add_argument("--no-baseline", action="store_true", help="skip the unmutated run")
    parser.add_argument("--no-readme", action="store_true", help="do not write bench/README.md")
    args = parser.parse_args(argv)
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # the scratch copy is removed
    chosen = [m for m in MUTANTS if not args.only or args.only in m.name]
    if args.list or not chosen:
        for m in chosen:
            print(f"{m.name:40s} {m.path:36s} {m.what}")
        return 0 if chosen else 1
    files = _repository_files()
    stale = []
    for m in chosen:
        try:
            mutated(m, (ROOT / m.path).read_text())
        except (MutantError, FileNotFoundError) as exc:
            stale.append(str(exc))
    if stale:
        print("mutants that no longer apply (update bench/mutants.py):", *stale, sep="\n  ")
        return 1
    load_before = os.getloadavg()[0]
    start = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="mutate-") as scratch:
        pristine, work = Path(scratch) / "pristine", Path(scratch) / "work"
        _copy_tree(files, ROOT, pristine)
        env = _environment(work, Path(scratch) / "numba-cache")
        _copy_tree(files, pristine, work)
        _check_imports(work, env)
        warm = None
        if not args.no_baseline:
            warm_env = _environment(work, Path(scratch) / "warm-cache")
            rc, out = _pytest(_baseline_targets(chosen), work, warm_env, 4 * args.timeout)
            if rc != 0:
                print(f"baseline: the named tests fail without a mutant: {_first_failure(out)}")
                return 1
            warm = cache_folder(work, warm_env)
            print(f"baseline: the named tests pass ({time.perf_counter() - start:.0f} s)")
        outcomes = []
        killers = last_killers()
        for m in chosen:
            o = run_mutant(
                m, files, pristine, work, env, args.timeout, warm, killers.get(m.name, "")
            )
            outcomes.append(o)
            print(
                f"{o.status:8s} {m.name:42s} {o.seconds:6.1f} s {o.cache:4s}  {o.detail}",
                flush=True,
            )
    wall = time.perf_counter() - start
    text = section(outcomes, wall, (load_before, os.getloadavg()[0]))
    killed = sum(o.killed for o in outcomes)
    score = 100 * killed / len(outcomes)
    print(f"\nscore: {killed}/{len(outcomes)} killed ({score:.1f} %)")
    for status in ("survived", "timeout", "error"):
        for o in outcomes:
            if o.status == status:
                print(f"  {status}: {o.mutant.name}: {SURVIVOR_NOTES.get(o.mutant.name, '')}")
    if not args.no_readme and not args.only:
        replace_section(README, SECTION, text)
        print(f"wrote the {SECTION!r} section of {README.relative_to(ROOT)}")
    errors = any(o.status == "error" for o in outcomes)
    return 1 if errors or score < args.min_score else 0


if __name__ == "__main__":
    sys.exit(main())
