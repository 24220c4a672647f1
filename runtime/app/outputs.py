"""The files of one ``simulate`` run, written into a folder (the staging folder of OutputDir).

Why: everything needed to judge a run, in files other tools read -- the trajectory and every
contact (``trajectory.npz``: flat arrays, no pickles), the poses as CSV for a spreadsheet
(``--csv``), the energy and force plot, the animation (GIF, and MP4 with ``--mp4``) and the key
numbers (``summary.json``, written last).
"""

from __future__ import annotations

import csv
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from runtime.app.animation import FfmpegError, Look
from runtime.app.contact_table import contact_table
from runtime.app.energy import energy_budget

__all__ = [
    "ANIMATION",
    "CSV",
    "MP4",
    "OUTPUT_FILES",
    "PLOT",
    "SUMMARY",
    "TRAJECTORY",
    "Options",
    "summary",
    "trajectory_arrays",
    "write_csv",
    "write_outputs",
]

TRAJECTORY, PLOT, ANIMATION, SUMMARY = (
    "trajectory.npz",
    "energy_forces.png",
    "animation.gif",
    "summary.json",
)
CSV, MP4 = "poses.csv", "animation.mp4"
OUTPUT_FILES = (TRAJECTORY, PLOT, ANIMATION, SUMMARY, CSV, MP4)


@dataclass(frozen=True)
class Options:
    """Which files to write, and how the animation looks."""

    gif: bool = True
    mp4: bool = False
    csv: bool = False
    look: Look = field(default_factory=Look)


def _finite(x: float) -> float | None:
    """JSON has no NaN or infinity: those become null."""
    x = float(x)
    return x if math.isfinite(x) else None


def trajectory_arrays(scene: Any, run: Any) -> dict[str, np.ndarray]:
    """``run.arrays()`` with shapes kept for an empty (failed at once) run, the body names,
    which bodies are fixed, the time step, the located impacts and every recorded contact
    (runtime/app/contact_table.py)."""
    n = len(scene.bodies)
    arrays = dict(run.arrays())
    if len(run.t) == 0:
        arrays["poses"] = np.zeros((0, n, 3))
        arrays["velocities"] = np.zeros((0, n, 3))
        arrays["momentum"] = np.zeros((0, 2))
    arrays["body_names"] = np.array([b.name for b in scene.bodies], dtype=str)
    arrays["fixed"] = np.array([b.fixed for b in scene.bodies], dtype=bool)
    arrays["dt"] = np.array(run.dt)
    arrays.update(contact_table(run))
    return arrays


def summary(scene: Any, run: Any, wall_time: float, error: str | None = None) -> dict[str, Any]:
    """The run's key numbers (what summary.json holds)."""
    t = np.asarray(run.t, dtype=float)
    budget = energy_budget(run)
    energy = np.asarray(run.energy, dtype=float)
    steps = int(round(t[-1] / run.dt)) if len(t) else 0
    last = lambda a: _finite(a[-1]) if a is not None and len(a) else None  # noqa: E731
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
        "energy_drift": last(budget.change),  # E(end) - E(0), impacts included
        "max_abs_energy_drift": _finite(np.max(np.abs(budget.change))) if len(t) else None,
        "impacts": budget.impacts,
        "impact_energy_loss": last(budget.lost),
        "numerical_drift": last(budget.drift),  # E(end) - E(0) + the loss at impacts
        "max_penetration": _finite(run.max_penetration),
        "status": "failed" if error else "ok",
        "error": error,
    }


def write_csv(scene: Any, run: Any, path: Path) -> None:
    """Poses as CSV: ``t [s]``, then ``<body> x [m]``, ``<body> y [m]``, ``<body> angle [rad]``
    for every body in scene order; numbers with 17 significant digits (exact round trip)."""
    poses = np.asarray(run.poses, dtype=float).reshape(len(run.t), -1, 3)
    header = ["t [s]"] + [
        f"{b.name} {what}" for b in scene.bodies for what in ("x [m]", "y [m]", "angle [rad]")
    ]
    table = np.column_stack([np.asarray(run.t, dtype=float), poses.reshape(len(run.t), -1)])
    with path.open("w", newline="", encoding="utf-8") as stream:
        csv.writer(stream).writerow(header)
        np.savetxt(stream, table.reshape(-1, len(header)), fmt="%.17g", delimiter=",")


def write_outputs(
    scene: Any,
    run: Any,
    folder: Path,
    options: Options,
    *,
    wall_time: float,
    error: str | None = None,
) -> dict[str, Any]:
    """Write the run's files into ``folder`` (summary.json last) and return the summary, with
    ``files`` (what was written) and, if ffmpeg failed, ``mp4_error``."""
    from runtime.app import animation, plotting

    np.savez(folder / TRAJECTORY, **trajectory_arrays(scene, run))
    info = summary(scene, run, wall_time, error)
    if options.csv:
        write_csv(scene, run, folder / CSV)
    if len(run.t):
        plotting.plot_energy_forces(run, [b.name for b in scene.bodies], folder / PLOT)
        if options.gif or options.mp4:
            mp4 = folder / MP4 if options.mp4 else None
            gif = folder / ANIMATION
            try:
                animation.save_animation(scene, run, gif, options.look, mp4)
            except FfmpegError as exc:
                info["mp4_error"] = str(exc)
                (folder / MP4).unlink(missing_ok=True)
            info["animation_frames"] = len(animation.frame_indices(run.t, options.look.fps))
            if not options.gif:
                gif.unlink()
    info["files"] = sorted({p.name for p in folder.iterdir() if p.name in OUTPUT_FILES} | {SUMMARY})
    (folder / SUMMARY).write_text(json.dumps(info, indent=2, allow_nan=False) + "\n")
    return info
