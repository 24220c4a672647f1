"""Soak case: a `simulate --force` rerun killed at a random instant, and what its folder holds.

Why: results are what the user keeps (issue #13, "Data that is lost"). The CLI writes into a
staging folder beside ``--out`` and moves the files into place only when all are complete, under
a lock (runtime/app/output_dir.py); tests/app/test_output_dir.py checks each situation once.
Here a shipped scene is run once into a folder (the previous results), then rerun with
``--force`` in a fresh interpreter and sent SIGINT, SIGTERM or SIGKILL at a random instant
(mostly 0-3 s after its staging folder appeared: during its run or its writing; else during
start-up). The folder must then hold either the previous
results, byte for byte, or the new ones complete (each file readable, the summary's step count
that of the trajectory); never a mix or a truncated file. A run killed by SIGKILL cannot clean
up: its staging folder and lock file stay, and the next run must take them over and leave
nothing behind.
"""

from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
SCENES = sorted((ROOT / "scenes").glob("*.toml"))
SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGKILL)
OUTCOMES = {
    "previous": "killed before its files were moved into place: the previous results, intact",
    "new": "finished (or killed after the move): the new results, complete",
    "corrupt": "anything else: a mix, a truncated or unreadable file (target 0)",
    "leftovers": "staging folders or lock files beside the output after the next run (target 0)",
    "bad exit": "an exit status other than 0, 130 (SIGINT), 143 (SIGTERM) or -9 (SIGKILL)",
}


def _snapshot(folder: Path) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def _command(scene: Path, out: Path, duration: float) -> list[str]:
    return [sys.executable, "-m", "runtime", str(scene), "--out", str(out), "--force", "--no-gif",
            "--quiet", "--duration", f"{duration:g}"]  # fmt: skip


def _run(args: list[str], cwd: Path) -> subprocess.Popen:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.Popen(
        args, cwd=cwd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True
    )


def complete(folder: Path) -> bool:
    """Whether ``folder`` holds one whole set of results: a readable summary and trajectory
    that agree on the number of steps."""
    try:
        summary = json.loads((folder / "summary.json").read_text())
        with np.load(folder / "trajectory.npz") as data:
            steps = len(data["t"]) - 1
            data["poses"].sum()  # every array readable
        return summary.get("steps") == steps
    except (OSError, ValueError, KeyError, json.JSONDecodeError):
        return False


def leftovers(out: Path) -> list[str]:
    return sorted(p.name for p in out.parent.iterdir() if p.name.startswith(f".{out.name}."))


def interrupted_write(rng: random.Random) -> tuple[str, str]:
    """One case: (outcome, detail), outcome a key of OUTCOMES; a case can also count
    'leftovers' or 'bad exit' (then the detail says which)."""
    scene = rng.choice(SCENES)
    sig = rng.choice(SIGNALS)
    delay = rng.uniform(0.0, 3.0)
    duration = rng.choice([0.05, 0.2, 1.0, 5.0])
    with tempfile.TemporaryDirectory(prefix="soak-writes-") as tmp:
        where = Path(tmp)
        out = where / "out"
        first = _run(_command(scene, out, 0.01), where)
        if first.wait(timeout=300) != 0:
            return "bad exit", f"first run of {scene.name}: {first.stderr.read()[-200:]}"
        before = _snapshot(out)
        rerun = _run(_command(scene, out, duration), where)
        started = time.monotonic()
        if rng.random() < 0.8:  # most signals once the run has its staging folder: mid-run
            while not any(where.glob(".out.partial-*")) and rerun.poll() is None:
                if time.monotonic() - started > 120:
                    break
                time.sleep(0.02)
        time.sleep(delay)
        if rerun.poll() is None:
            rerun.send_signal(sig)
        status = rerun.wait(timeout=300)
        waited = time.monotonic() - started
        detail = f"{scene.name}, {duration:g} s, {sig.name} after {waited:.1f} s: exit {status}"
        if status not in (0, 130, 143, -9):
            return "bad exit", detail
        after = _snapshot(out)
        if after == before:
            outcome = "previous"
        elif complete(out) and set(after) >= set(before):
            outcome = "new"
        else:
            return "corrupt", f"{detail}; files {sorted(after)}"
        cleanup = _run(_command(scene, out, 0.01), where)  # takes over a dead run's lock
        if cleanup.wait(timeout=300) != 0 or leftovers(out) or not complete(out):
            return "leftovers", f"{detail}; then {leftovers(out)}"
        return outcome, detail


if __name__ == "__main__":
    generator = random.Random(int(sys.argv[1]) if len(sys.argv) > 1 else None)
    print(interrupted_write(generator))
