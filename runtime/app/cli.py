"""The ``simulate`` command: run a scene file and write its trajectory, plots and animation.

Why this module exists: running a scene should not need a Python session.  ``simulate`` reads a
scene (docs/scene-format.md), runs :func:`runtime.simulate`, and leaves everything needed to
judge the run in one directory -- the trajectory (``trajectory.npz``), the energy drift and
contact forces (``energy_forces.png``), an animation (``animation.gif``) and the key numbers
(``summary.json``) -- plus a one-line summary on stdout.

Bad input (a missing or invalid scene file, a bad ``--dt``, an unknown ``--method``, an output
directory that would be overwritten) is reported in one line on stderr with exit status 2,
never a traceback.  A run that fails part-way (:class:`runtime.SimulationError`) still writes
what it recorded, so the failure can be inspected, and exits with status 1.

    simulate scenes/disc_in_bowl.toml --duration 2 --method rk4 --out out/disc_in_bowl
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NoReturn, TextIO

import numpy as np

from runtime.step.integrators import METHODS

__all__ = ["OUTPUT_FILES", "ProgressBar", "main", "write_outputs"]

TRAJECTORY, PLOT, ANIMATION, SUMMARY = (
    "trajectory.npz",
    "energy_forces.png",
    "animation.gif",
    "summary.json",
)
OUTPUT_FILES = (TRAJECTORY, PLOT, ANIMATION, SUMMARY)
PROG = "simulate"


class UsageError(Exception):
    """Bad input from the user: reported in one line, exit status 2."""


class _Parser(argparse.ArgumentParser):
    """argparse, but its errors are one line (with a pointer to --help) and exit status 2."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{message} (see {self.prog} --help)")


def _parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog=PROG,
        description="Run a 2-D rigid-body scene and write trajectory.npz, energy_forces.png, "
        "animation.gif and summary.json into --out DIR.",
    )
    parser.add_argument("scene", metavar="SCENE.toml", help="scene file (docs/scene-format.md)")
    parser.add_argument(
        "--duration", type=float, metavar="S", help="simulated time in s (default: the scene's)"
    )
    parser.add_argument(
        "--dt", type=float, metavar="S", help="time step in s (default: the scene's)"
    )
    parser.add_argument(
        "--method", metavar="|".join(METHODS), help="integrator (default: the scene's)"
    )
    parser.add_argument("--out", required=True, metavar="DIR", help="output directory")
    parser.add_argument(
        "--force", action="store_true", help="write into DIR even if it is not empty"
    )
    parser.add_argument(
        "--fps", type=float, default=30.0, help="animation frames per simulated second (default 30)"
    )
    parser.add_argument(
        "--max-penetration",
        metavar="X|off",
        default="0.01",
        help="stop when two bodies overlap by more than X times the smaller one's size "
        "(default 0.01; runtime.Guards)",
    )
    parser.add_argument(
        "--max-energy-growth",
        metavar="X|off",
        default="0.5",
        help="stop when the energy rises by more than X times the scene's energy scale "
        "(default 0.5; runtime.Guards)",
    )
    parser.add_argument("--no-gif", action="store_true", help="do not write animation.gif")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
    return parser


# -- progress -------------------------------------------------------------------------------------


class ProgressBar:
    """A one-line text bar on ``stream`` fed by the ``progress`` callback of ``simulate``.

    It stays silent for the first ``delay`` seconds of wall time, so short runs print nothing,
    and redraws at most every ``interval`` seconds."""

    def __init__(
        self, stream: TextIO, *, delay: float = 2.0, interval: float = 0.2, width: int = 30
    ) -> None:
        self.stream = stream
        self.delay, self.interval, self.width = delay, interval, width
        self.start = time.perf_counter()
        self.last_draw = -math.inf
        self.drawn = False

    def __call__(self, fraction: float) -> None:
        now = time.perf_counter()
        elapsed = now - self.start
        if elapsed < self.delay or now - self.last_draw < self.interval:
            return
        self.last_draw = now
        fraction = min(max(float(fraction), 0.0), 1.0)
        filled = int(round(self.width * fraction))
        left = elapsed * (1.0 - fraction) / fraction if fraction > 0 else math.inf
        eta = f"~{left:.0f} s left" if math.isfinite(left) else ""
        bar = "#" * filled + "." * (self.width - filled)
        self.stream.write(f"\r[{bar}] {100 * fraction:5.1f}%  {elapsed:.0f} s  {eta}   ")
        self.stream.flush()
        self.drawn = True

    def close(self) -> None:
        """Erase the bar (if one was drawn): the summary line that follows replaces it."""
        if self.drawn:
            self.stream.write("\r" + " " * (self.width + 40) + "\r")
            self.stream.flush()
            self.drawn = False


# -- checks ---------------------------------------------------------------------------------------


def _check_arguments(args: argparse.Namespace) -> None:
    if args.dt is not None and not (math.isfinite(args.dt) and args.dt > 0):
        raise UsageError(f"--dt must be a finite number > 0, got {args.dt!r}")
    if args.duration is not None and not (math.isfinite(args.duration) and args.duration > 0):
        raise UsageError(f"--duration must be a finite number > 0, got {args.duration!r}")
    if args.method is not None:
        args.method = args.method.lower()
        if args.method not in METHODS:
            raise UsageError(
                f"--method: unknown method {args.method!r}; choose one of {', '.join(METHODS)}"
            )
    if not (math.isfinite(args.fps) and args.fps > 0):
        raise UsageError(f"--fps must be a finite number > 0, got {args.fps!r}")
    for option in ("max_penetration", "max_energy_growth"):
        setattr(args, option, _guard_limit(option, getattr(args, option)))


def _guard_limit(option: str, text: str) -> float | None:
    """A guard's limit from the command line: a number > 0, or 'off' (None)."""
    if text.strip().lower() == "off":
        return None
    flag = "--" + option.replace("_", "-")
    try:
        value = float(text)
    except ValueError:
        raise UsageError(f"{flag} must be a number > 0 or 'off', got {text!r}") from None
    if not (math.isfinite(value) and value > 0):
        raise UsageError(f"{flag} must be a number > 0 or 'off', got {text!r}")
    return value


def _check_output(out: Path, force: bool) -> None:
    if out.exists() and not out.is_dir():
        raise UsageError(f"output {str(out)!r} exists and is not a directory")
    if out.is_dir() and any(out.iterdir()) and not force:
        raise UsageError(
            f"output directory {str(out)!r} is not empty; use --force to overwrite its files"
        )
    try:  # now, not after a long run
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise UsageError(f"cannot create output directory {str(out)!r}: {exc.strerror}") from None


def _load(path: str) -> Any:
    import runtime

    if not Path(path).exists():
        raise UsageError(f"scene file {path!r} not found")
    if Path(path).is_dir():
        raise UsageError(f"scene file {path!r} is a directory")
    try:
        return runtime.load_scene(path)
    except runtime.SceneError as exc:
        raise UsageError(str(exc)) from None


# -- outputs --------------------------------------------------------------------------------------


def _finite(x: float) -> float | None:
    """JSON has no NaN or infinity: those become null."""
    x = float(x)
    return x if math.isfinite(x) else None


def trajectory_arrays(scene: Any, run: Any) -> dict[str, np.ndarray]:
    """``run.arrays()`` with shapes kept for an empty (failed at once) run, plus the body names,
    which bodies are fixed, and the time step."""
    n = len(scene.bodies)
    arrays = dict(run.arrays())
    if len(run.t) == 0:
        arrays["poses"] = np.zeros((0, n, 3))
        arrays["velocities"] = np.zeros((0, n, 3))
        arrays["momentum"] = np.zeros((0, 2))
    arrays["body_names"] = np.array([b.name for b in scene.bodies], dtype=str)
    arrays["fixed"] = np.array([b.fixed for b in scene.bodies], dtype=bool)
    arrays["dt"] = np.array(run.dt)
    return arrays


def summary(scene: Any, run: Any, wall_time: float, error: str | None = None) -> dict[str, Any]:
    """The run's key numbers (what summary.json holds)."""
    t = np.asarray(run.t, dtype=float)
    energy = np.asarray(run.energy, dtype=float)
    steps = int(round(t[-1] / run.dt)) if len(t) else 0
    drift = energy - energy[0] if len(energy) else np.zeros(0)
    return {
        "scene": scene.name,
        "scene_file": str(scene.source),
        "method": run.method,
        "dt": run.dt,
        "duration": float(t[-1]) if len(t) else 0.0,
        "steps": steps,
        "recorded_steps": len(t),
        "bodies": [b.name for b in scene.bodies],
        "wall_time": wall_time,
        "steps_per_second": _finite(steps / wall_time) if wall_time > 0 else None,
        "rhs_evaluations": int(run.rhs_evaluations),
        "initial_energy": _finite(energy[0]) if len(energy) else None,
        "energy_drift": _finite(drift[-1]) if len(drift) else None,
        "max_abs_energy_drift": _finite(np.max(np.abs(drift))) if len(drift) else None,
        "max_penetration": _finite(run.max_penetration),
        "status": "failed" if error else "ok",
        "error": error,
    }


def write_outputs(
    scene: Any,
    run: Any,
    out: Path,
    *,
    wall_time: float,
    fps: float,
    gif: bool,
    error: str | None = None,
) -> dict[str, Any]:
    """Write trajectory.npz, summary.json, energy_forces.png and (``gif``) animation.gif into
    ``out``; files of an earlier run there are replaced or, if not produced now, removed."""
    from runtime.app import plotting

    out.mkdir(parents=True, exist_ok=True)
    for name in OUTPUT_FILES:
        (out / name).unlink(missing_ok=True)
    np.savez(out / TRAJECTORY, **trajectory_arrays(scene, run))
    info = summary(scene, run, wall_time, error)
    names = [b.name for b in scene.bodies]
    if len(run.t):
        plotting.plot_energy_forces(run, names, out / PLOT)
        if gif:
            info["gif_frames"] = plotting.save_animation(scene, run, out / ANIMATION, fps=fps)
    info["files"] = sorted(p.name for p in out.iterdir() if p.name in OUTPUT_FILES)
    info["files"] = sorted({*info["files"], SUMMARY})
    (out / SUMMARY).write_text(json.dumps(info, indent=2, allow_nan=False) + "\n")
    return info


def _one_line(info: dict[str, Any], out: Path) -> str:
    def num(x: Any, unit: str) -> str:
        return "n/a" if x is None else f"{x:.3g} {unit}"

    rate = info["steps_per_second"]
    return (
        f"{info['scene']}: {info['method']}, dt = {info['dt']:g} s, {info['steps']} steps "
        f"({info['duration']:g} s simulated) in {info['wall_time']:.2f} s"
        f"{f' ({rate:.0f} steps/s)' if rate else ''}; energy drift {num(info['energy_drift'], 'J')}, "
        f"max penetration {num(info['max_penetration'], 'm')} -> {out}"
    )


# -- main -----------------------------------------------------------------------------------------


def _error(message: str, stream: TextIO) -> None:
    print(f"{PROG}: error: {message}", file=stream)


def run_command(args: argparse.Namespace) -> int:
    import runtime

    _check_arguments(args)
    scene = _load(args.scene)
    duration = scene.simulation.duration if args.duration is None else args.duration
    dt = scene.simulation.dt if args.dt is None else args.dt
    if dt > duration:
        raise UsageError(f"--dt {dt:g} s is longer than the duration {duration:g} s")
    out = Path(args.out)
    _check_output(out, args.force)

    show = not args.quiet and sys.stderr.isatty()
    bar = ProgressBar(sys.stderr) if show else None
    start = time.perf_counter()
    error = None
    try:
        guards = runtime.Guards(args.max_penetration, args.max_energy_growth)
        run = runtime.simulate(scene, duration, dt, args.method, progress=bar, guards=guards)
    except runtime.SimulationError as exc:
        run, error = exc.run, str(exc)
    except ValueError as exc:  # the engine's own argument checks
        raise UsageError(str(exc)) from None
    finally:
        if bar is not None:
            bar.close()
    wall = run.wall_time if error is None and run.wall_time > 0 else time.perf_counter() - start
    info = write_outputs(
        scene, run, out, wall_time=wall, fps=args.fps, gif=not args.no_gif, error=error
    )
    if error is not None:
        _error(f"simulation failed: {error}", sys.stderr)
        print(
            f"{PROG}: wrote the {len(run.t)} recorded steps before the failure to {out}",
            file=sys.stderr,
        )
        print(_one_line(info, out))
        return 1
    print(_one_line(info, out))
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``simulate`` console script; returns the exit status."""
    try:
        args = _parser().parse_args(argv)
        return run_command(args)
    except UsageError as exc:
        _error(str(exc), sys.stderr)
        return 2
    except KeyboardInterrupt:
        _error("interrupted", sys.stderr)
        return 130


if __name__ == "__main__":
    sys.exit(main())
