"""The ``simulate`` command: run a scene file and write its trajectory, plots and animation.

Why this module exists: running a scene should not need a Python session.  ``simulate`` reads a
scene (docs/scene-format.md), runs :func:`runtime.simulate`, and leaves everything needed to
judge the run in one folder (runtime/app/outputs.py), plus a one-line summary on stdout.

    simulate scenes/disc_in_bowl.toml --duration 2 --method rk4 --out out/disc_in_bowl
    python -m runtime scenes/disc_in_bowl.toml          # the same; --out defaults to out/<scene>

What it promises (docs/bad-input.md lists each case and its message):

- bad input (a missing or invalid scene file, a number out of range, an unknown method, an
  output folder that would be overwritten, cannot be written or is in use by another run) is
  one line on stderr naming the flag or path, exit status 2, checked *before* the run;
- a run that fails part-way (:class:`runtime.SimulationError`) still writes what it recorded,
  exit status 1;
- Ctrl-C (exit 130) or SIGTERM (143) at any point prints one line, never a traceback, and leaves
  the output folder as it was (runtime/app/output_dir.py);
- names from the scene file are printed with control characters escaped (runtime/app/text.py).

Only the standard library is imported at the top, so Ctrl-C during start-up is caught too.
"""

from __future__ import annotations

import argparse
import functools
import math
import re
import signal
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any, NoReturn, TextIO

from runtime.app.interrupts import Terminated, redeliver
from runtime.app.text import folder_name, terminal_safe

__all__ = ["main"]

PROG = "simulate"
TIME_RANGE = (1e-50, 1e50)  # s: the scene format's range for times (docs/scene-format.md)
FPS_RANGE = (0.01, 1000.0)  # frames per simulated second (a GIF delay is at most 655 s)
SIZE_RANGE = (64, 4096)  # pixels per side of the animation
DPI_RANGE = (10.0, 600.0)


class UsageError(Exception):
    """Bad input from the user: reported in one line, exit status 2."""


class _Parser(argparse.ArgumentParser):
    """argparse, but its errors are one line (with a pointer to --help) and exit status 2."""

    def error(self, message: str) -> NoReturn:
        raise UsageError(f"{message} (see {self.prog} --help)")


def _parser(prog: str) -> argparse.ArgumentParser:
    from runtime.step.integrators import METHODS

    parser = _Parser(
        prog=prog,
        description="Run a 2-D rigid-body scene and write trajectory.npz, energy_forces.png, "
        "animation.gif and summary.json into --out DIR.",
    )
    add = parser.add_argument
    add("scene", metavar="SCENE.toml", help="scene file (docs/scene-format.md)")
    add("--duration", metavar="S", help="simulated time in s (default: the scene's)")
    add("--dt", metavar="S", help="time step in s (default: the scene's)")
    add("--method", metavar="|".join(METHODS), help="integrator (default: the scene's)")
    add("--out", metavar="DIR", help="output directory (default: out/<scene name>)")
    add("--force", action="store_true", help="write into DIR even if it is not empty")
    add("--max-penetration", metavar="X|off", default="0.01",
        help="stop when two bodies overlap by more than X times the smaller one's size "
        "(default 0.01; runtime.Guards)")  # fmt: skip
    add("--max-energy-growth", metavar="X|off", default="0.5",
        help="stop when the energy rises by more than X times the scene's energy scale "
        "(default 0.5; runtime.Guards)")  # fmt: skip
    add("--csv", action="store_true", help="also write poses.csv (t and every body's pose)")
    add("--no-gif", action="store_true", help="do not write animation.gif")
    add("--mp4", action="store_true", help="also write animation.mp4 (needs ffmpeg on PATH)")
    add("--fps", metavar="F", default="30",
        help="animation frames per simulated second (default 30; played at F, at most 50 per "
        "second: above, in slow motion)")  # fmt: skip
    add(
        "--size",
        metavar="WxH",
        default="288x288",
        help="animation size in pixels (default 288x288)",
    )
    add(
        "--dpi",
        metavar="D",
        default="72",
        help="animation dots per inch: text and line scale (default 72)",
    )
    add("--no-arrows", action="store_true", help="animation: no contact-normal arrows")
    add("--quiet", action="store_true", help="no progress output")
    return parser


# -- checks ---------------------------------------------------------------------------------------


def _number(flag: str, text: str, low: float, high: float, unit: str = "") -> float:
    """A number in [low, high] from the command line, or a UsageError naming the flag."""
    what = f"{flag} must be a number from {low:g} to {high:g}{unit}"
    try:
        value = float(text)
    except ValueError:
        raise UsageError(f"{what}, got {text!r}") from None
    if not (low <= value <= high):  # also NaN and inf
        raise UsageError(f"{what}, got {text}")
    return value


def _guard_limit(flag: str, text: str) -> float | None:
    """A guard's limit from the command line: a number > 0, or 'off' (None)."""
    if text.strip().lower() == "off":
        return None
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise UsageError(f"{flag} must be a number > 0 or 'off', got {text!r}")
    return value


def _size(text: str) -> tuple[int, int]:
    match = re.fullmatch(r"\s*(\d{1,6})\s*[xX]\s*(\d{1,6})\s*", text)
    low, high = SIZE_RANGE
    if not match or not all(low <= int(v) <= high for v in match.groups()):
        raise UsageError(
            f"--size must be WIDTHxHEIGHT in pixels, each from {low} to {high}, got {text!r}"
        )
    return int(match[1]), int(match[2])


def _check_arguments(args: argparse.Namespace) -> None:
    """Numbers in range, a known method, valid guard limits: before anything is loaded."""
    for flag in ("duration", "dt"):
        text = getattr(args, flag)
        if text is not None:
            setattr(args, flag, _number(f"--{flag}", text, *TIME_RANGE, " s"))
    from runtime.step.integrators import METHODS

    if args.method is not None:
        args.method = args.method.lower()
        if args.method not in METHODS:
            raise UsageError(
                f"--method: unknown method {args.method!r}; choose one of {', '.join(METHODS)}"
            )
    args.fps = _number("--fps", args.fps, *FPS_RANGE)
    args.dpi = _number("--dpi", args.dpi, *DPI_RANGE)
    args.size = _size(args.size)
    for flag in ("--max-penetration", "--max-energy-growth"):
        name = flag[2:].replace("-", "_")
        setattr(args, name, _guard_limit(flag, getattr(args, name)))


def _load(path: str) -> Any:
    import runtime

    file = Path(path)
    if not file.exists():
        raise UsageError(f"scene file {path!r} not found")
    if file.is_dir():
        raise UsageError(f"scene file {path!r} is a directory")
    if not file.is_file():
        raise UsageError(f"scene file {path!r} is not a regular file")
    try:
        return runtime.load_scene(path)
    except runtime.SceneError as exc:
        raise UsageError(str(exc)) from None


# -- the run --------------------------------------------------------------------------------------


def _say(stream: TextIO, prog: str, text: str) -> None:
    print(terminal_safe(f"{prog}: {text}"), file=stream)


def _one_line(info: dict[str, Any], out: Path) -> str:
    def num(x: Any, unit: str) -> str:
        return "n/a" if x is None else f"{x:.3g} {unit}"

    rate = info["steps_per_second"]
    if info["impacts"]:
        energy = (
            f"energy lost at {info['impacts']} impacts {num(info['impact_energy_loss'], 'J')}, "
            f"numerical drift {num(info['numerical_drift'], 'J')}"
        )
    else:
        energy = f"energy drift {num(info['energy_drift'], 'J')}"
    return terminal_safe(
        f"{info['scene']}: {info['method']}, dt = {info['dt']:g} s, {info['steps']} steps "
        f"({info['duration']:g} s simulated) in {info['wall_time']:.2f} s"
        f"{f' ({rate:.0f} steps/s)' if rate else ''}; {energy}, "
        f"max penetration {num(info['max_penetration'], 'm')} -> {out}"
    )


def _simulate(scene: Any, duration: float, dt: float, method: str, args: argparse.Namespace,
              prog: str) -> tuple[Any, str | None, float]:  # fmt: skip
    """Run the scene with progress on stderr: (run, the SimulationError's message or None, wall
    time). A run that fails part-way returns what it recorded."""
    import runtime
    from runtime.app.progress import ProgressBar, ProgressLines

    bar = None
    if not args.quiet:
        from runtime.compiled import CACHE_FOLDER, cache_is_cold

        if cache_is_cold():
            _say(sys.stderr, prog, "first run of this version: compiling the engine (a minute or "
                 f"more; later runs load it from {CACHE_FOLDER})")  # fmt: skip
        tty = sys.stderr.isatty()
        bar = ProgressBar(sys.stderr) if tty else ProgressLines(sys.stderr, duration, prog=prog)
    start = time.perf_counter()
    try:
        guards = runtime.Guards(args.max_penetration, args.max_energy_growth)
        run = runtime.simulate(scene, duration, dt, method, progress=bar, guards=guards)
        return run, None, run.wall_time if run.wall_time > 0 else time.perf_counter() - start
    except runtime.SimulationError as exc:
        return exc.run, str(exc), time.perf_counter() - start
    except ValueError as exc:  # the engine's own argument checks
        raise UsageError(str(exc)) from None
    finally:
        if bar is not None:
            bar.close()


def run_command(args: argparse.Namespace, prog: str = PROG) -> int:
    """Check everything, run, write the files; the exit status (bad input raises UsageError)."""
    _check_arguments(args)
    if args.mp4:
        from runtime.app.animation import FfmpegError, ffmpeg

        try:
            ffmpeg()
        except FfmpegError as exc:
            raise UsageError(str(exc)) from None
    scene = _load(args.scene)
    duration = scene.simulation.duration if args.duration is None else args.duration
    dt = scene.simulation.dt if args.dt is None else args.dt
    method = scene.simulation.method if args.method is None else args.method
    if dt > duration:
        raise UsageError(f"--dt {dt:g} s is longer than the duration {duration:g} s")
    steps = int(round(duration / dt))
    out = Path(args.out or Path("out") / folder_name(scene.name, Path(args.scene).stem))

    from runtime.app import estimate
    from runtime.app.animation import Look
    from runtime.app.output_dir import OutputDir, OutputError
    from runtime.app.outputs import OUTPUT_FILES, Options, write_outputs

    look = Look(*args.size, dpi=args.dpi, fps=args.fps, arrows=not args.no_arrows)
    options = Options(gif=not args.no_gif, mp4=args.mp4, csv=args.csv, look=look)
    try:
        with OutputDir(out, force=args.force, owned=OUTPUT_FILES) as output:
            if output.stale_lock:
                _say(
                    sys.stderr,
                    prog,
                    f"note: took over the lock of a run that ended ({output.stale_lock})",
                )
            warning = estimate.warning(estimate.probe(scene, steps, dt, method), len(scene.bodies))
            if warning:
                _say(sys.stderr, prog, f"warning: {warning}")
            run, error, wall = _simulate(scene, duration, dt, method, args, prog)
            info = write_outputs(scene, run, output.staging, options, wall_time=wall, error=error)
            output.commit(info["files"])
    except OutputError as exc:
        raise UsageError(str(exc)) from None
    except INTERRUPTIBLE as exc:
        interrupt = _interrupt_behind(exc)
        if interrupt is None:
            raise
        what = "terminated" if isinstance(interrupt, Terminated) else "interrupted"
        raise type(interrupt)(f"{what}; {str(out)!r} keeps its previous contents") from None
    status = 0
    if "mp4_error" in info:
        _say(sys.stderr, prog, f"error: animation.mp4 not written: {info['mp4_error']}")
        status = 1
    if error is not None:
        _say(sys.stderr, prog, f"error: simulation failed: {error}")
        _say(sys.stderr, prog, f"wrote the {len(run.t)} recorded steps before the failure to {out}")
        status = 1
    print(_one_line(info, out))
    return status


# -- main -----------------------------------------------------------------------------------------


def _terminate(_signum: int, _frame: Any) -> None:
    raise Terminated("terminated")


def main(argv: Sequence[str] | None = None, prog: str = PROG) -> int:
    """Entry point of the ``simulate`` console script; returns the exit status."""
    try:
        previous = signal.signal(signal.SIGTERM, _terminate)
    except ValueError:  # not the main thread: leave SIGTERM alone
        previous = None
    hook = sys.unraisablehook
    sys.unraisablehook = functools.partial(redeliver, default=hook)
    try:
        args = _parser(prog).parse_args(argv)
        return run_command(args, prog)
    except UsageError as exc:
        _say(sys.stderr, prog, f"error: {exc}")
        return 2
    except INTERRUPTIBLE as exc:
        return interrupted(exc, prog)
    finally:
        sys.unraisablehook = hook
        if previous is not None:
            signal.signal(signal.SIGTERM, previous)


# what a Ctrl-C or SIGTERM can surface as (see _interrupt_behind)
INTERRUPTIBLE = (KeyboardInterrupt, ImportError, SystemError)


def interrupted(exc: BaseException, prog: str) -> int:
    """Exit status 130 (Ctrl-C) or 143 (SIGTERM) for an exception that stems from one, after
    one line on stderr; any other exception is raised again."""
    interrupt = _interrupt_behind(exc)
    if interrupt is None:
        raise exc
    _say(sys.stderr, prog, str(interrupt) or "interrupted")
    return 143 if isinstance(interrupt, Terminated) else 130


def _interrupt_behind(exc: BaseException) -> KeyboardInterrupt | None:
    """The Ctrl-C or SIGTERM an exception stems from: one that arrives while a C extension
    initialises (scipy's HiGHS, on the first scene load) surfaces as "ImportError:
    initialization failed", and a later import of the half-loaded package fails again; one
    that arrives while numba's dispatcher is in a compiled call (it runs Python to unpickle
    the result) surfaces as "SystemError: ... returned a result with an exception set"."""
    seen: set[int] = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return exc
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return None


if __name__ == "__main__":
    sys.exit(main())
