"""Pictures of a run: the energy / contact-force plot and an animated GIF of the bodies.

Why this module exists: a number such as "energy drift 1e-9 J" says little about *where* a run
went wrong; a plot of the drift next to the contact forces and a small animation showing the
bodies, the contact points and their normals make a bad step, a chattering contact or a body
sinking into a bowl visible at a glance.  Both are drawn from a finished (or partial)
:class:`runtime.step.simulation.Run` and the scene's shapes, without touching the engine.

Only matplotlib (Agg backend, no display needed) and Pillow (its GIF writer) are used.  Bodies
are drawn from their exact edges -- segments, convex and concave arcs and ellipses, sampled
densely -- placed at each recorded pose ``X + R(th) p`` (docs/conventions.md); fixed bodies are
grey, moving bodies coloured, with a spoke from the centre of mass so rotation shows.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from PIL import Image  # noqa: E402

from runtime.model.shapes import TAU, Arc, Ellipse, Segment  # noqa: E402

__all__ = ["MAX_FRAMES", "edge_points", "frame_indices", "plot_energy_forces", "save_animation"]

MAX_FRAMES = 150  # keeps a GIF to a few hundred kB
_FIXED_EDGE, _FIXED_FILL = "0.35", "0.85"
_ARC_STEP = TAU / 96  # radians between samples along an arc or ellipse


# -- geometry ---------------------------------------------------------------------------------


def edge_points(edge: Segment | Arc | Ellipse) -> np.ndarray:
    """(k, 2) points along an edge in body coordinates, in traversal order (material on the
    left): a concave arc runs from ``end_angle`` back to ``start_angle``."""
    if isinstance(edge, Segment):
        return np.array([edge.start, edge.end], dtype=float)
    if isinstance(edge, Arc):
        count = max(2, math.ceil(edge.span / _ARC_STEP) + 1)
        angles = np.linspace(edge.start_angle, edge.end_angle, count)
        if not edge.convex:
            angles = angles[::-1]
        r = abs(edge.radius)
        return np.column_stack(
            [edge.centre[0] + r * np.cos(angles), edge.centre[1] + r * np.sin(angles)]
        )
    if isinstance(edge, Ellipse):
        return np.array([edge.point(t) for t in np.linspace(0.0, TAU, 97)], dtype=float)
    raise TypeError(f"cannot draw an edge of type {type(edge).__name__}")


def outline(shape: Any) -> np.ndarray:
    """The shape's boundary as one (k, 2) polyline in body coordinates (edges joined in order;
    a NaN row separates edges that do not meet)."""
    pieces: list[np.ndarray] = []
    for edge in shape.edges:
        pts = edge_points(edge)
        if pieces and not np.allclose(pieces[-1][-1], pts[0], atol=1e-9, rtol=0):
            pieces.append(np.full((1, 2), np.nan))
        pieces.append(pts if not pieces or np.isnan(pieces[-1][-1, 0]) else pts[1:])
    return np.concatenate(pieces) if pieces else np.zeros((0, 2))


def _place(points: np.ndarray, pose: Sequence[float]) -> np.ndarray:
    """World coordinates ``X + R(th) p`` of body points (rows of ``points``)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    x, y = points[:, 0], points[:, 1]
    return np.column_stack([pose[0] + c * x - s * y, pose[1] + s * x + c * y])


# -- energy and forces --------------------------------------------------------------------------


def _contact_keys(contacts: Any) -> list[tuple]:
    """Keys that follow each contact from step to step: the body pair, the kernel case and the
    features touching (stable between steps)."""
    return [
        (int(b1), int(b2), contacts.case_name(k), tuple(int(x) for x in contacts.feature[k]))
        for k, (b1, b2) in enumerate(zip(contacts.body1, contacts.body2, strict=True))
    ]


def per_contact_forces(run: Any) -> dict[tuple, np.ndarray]:
    """Normal force of each contact over the recorded steps, NaN where it is not active."""
    count = len(run.t)
    series: dict[tuple, np.ndarray] = {}
    for k, (contacts, forces) in enumerate(zip(run.contacts, run.contact_forces, strict=False)):
        forces = np.atleast_1d(np.asarray(forces, dtype=float))
        for key, force in zip(_contact_keys(contacts), forces, strict=False):
            series.setdefault(key, np.full(count, np.nan))[k] = force
    return series


def _feature_text(feature: Any) -> str:
    """``(0, 2, 1, 0)`` (kind, index, kind, index) -> ``"vertex 2 / edge 0"``."""
    kinds = ("vertex", "edge", "end")
    try:
        return f"{kinds[feature[0]]} {feature[1]} / {kinds[feature[2]]} {feature[3]}"
    except (TypeError, ValueError, IndexError):
        return f"#{feature}"


def _contact_label(key: tuple, names: Sequence[str], several: bool) -> str:
    """``"disc/bowl (circle_circle)"``, with the features when the pair touches more than once."""
    b1, b2, case, feature = key

    def name(i: Any) -> str:
        return names[i] if isinstance(i, int | np.integer) and 0 <= i < len(names) else str(i)

    label = f"{name(b1)}/{name(b2)}"
    if case:
        label += f" ({case})"
    return label + (f" {_feature_text(feature)}" if several else "")


def plot_energy_forces(run: Any, names: Sequence[str], path: str | Path) -> Path:
    """Two stacked panels over time: the energy drift ``E(t) - E(0)`` and the normal contact
    forces (their total, and each contact).  Writes a PNG to ``path``."""
    path = Path(path)
    t = np.asarray(run.t, dtype=float)
    energy = np.asarray(run.energy, dtype=float)
    total = np.array([np.sum(f) for f in run.contact_forces], dtype=float)
    fig, (ax_e, ax_f) = plt.subplots(2, 1, figsize=(7, 5.5), sharex=True, layout="constrained")
    try:
        if len(energy):
            ax_e.plot(t, energy - energy[0], color="C0", lw=1.2)
        ax_e.axhline(0.0, color="0.6", lw=0.6)
        ax_e.set_ylabel("energy drift E(t) - E(0) [J]")
        ax_e.set_title(f"{run.scene_name}: {run.method}, dt = {run.dt:g} s")
        ax_e.grid(alpha=0.3)
        if len(total):  # underneath: with one contact it is that contact's force
            ax_f.plot(t, total, color="0.3", lw=3.0, alpha=0.35, label="total")
        series = per_contact_forces(run)
        pairs = [key[:2] for key in series]
        for i, (key, force) in enumerate(series.items()):  # in order of first touch
            label = _contact_label(key, names, pairs.count(key[:2]) > 1)
            ax_f.plot(
                t, force, lw=1.0, color=f"C{(i + 1) % 10}",
                label=label if i < 8 else None,
            )  # fmt: skip
        ax_f.set_xlabel("time t [s]")
        ax_f.set_ylabel("normal contact force [N]")
        ax_f.grid(alpha=0.3)
        if len(total):
            more = f"the first 8 of {len(series)} contacts" if len(series) > 8 else None
            ax_f.legend(fontsize="small", loc="best", title=more, title_fontsize="small")
        else:
            ax_f.text(0.5, 0.5, "nothing recorded", ha="center", transform=ax_f.transAxes)
        fig.savefig(path, dpi=100)
    finally:
        plt.close(fig)
    return path


# -- animation ---------------------------------------------------------------------------------


def frame_indices(t: Sequence[float], fps: float, max_frames: int = MAX_FRAMES) -> np.ndarray:
    """Indices of the recorded steps to show: about ``fps`` per second of simulated time, the
    first and the last always, never more than ``max_frames`` (then evenly spread)."""
    t = np.asarray(t, dtype=float)
    if len(t) == 0:
        return np.zeros(0, dtype=int)
    span = float(t[-1] - t[0])
    wanted = min(max_frames, max(2, int(math.floor(span * fps + 1e-9)) + 1), len(t))
    targets = np.linspace(t[0], t[-1], wanted)
    indices = np.clip(np.searchsorted(t, targets), 0, len(t) - 1)
    return np.unique(indices)


def _arrows(points: np.ndarray, normals: np.ndarray, length: float) -> np.ndarray:
    """Polyline (NaN-separated) drawing an arrow of ``length`` from each point along its normal."""
    if len(points) == 0:
        return np.zeros((0, 2))
    tips = points + length * normals
    head = 0.3 * length
    rows = []
    for p, q, n in zip(points, tips, normals, strict=True):
        side = np.array([-n[1], n[0]])
        rows += [p, q, [np.nan, np.nan]]
        rows += [q - head * n + 0.5 * head * side, q, q - head * n - 0.5 * head * side]
        rows += [[np.nan, np.nan]]
    return np.array(rows, dtype=float)


def _bounds(points: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray] | None:
    """Lower-left and upper-right corners of the finite points, or None."""
    stacked = np.concatenate(points) if points else np.zeros((0, 2))
    stacked = stacked[np.all(np.isfinite(stacked), axis=1)]
    return (stacked.min(axis=0), stacked.max(axis=0)) if len(stacked) else None


def _view(
    scene: Any, shapes: list[np.ndarray], poses: list[np.ndarray]
) -> tuple[np.ndarray, float]:
    """Centre and half-width of a square view: everything the frames show, unless the fixed
    bodies reach much farther than the moving ones go (a long floor under a small body); then
    about three times the moving bodies' range, kept inside the scene where possible."""
    moving = [i for i, b in enumerate(scene.bodies) if not b.fixed]
    everything = _bounds([_place(shapes[i], p[i]) for p in poses for i in range(len(shapes))])
    if everything is None:
        return np.zeros(2), 1.0
    lo, hi = everything
    width = float(max(hi - lo))
    movers = _bounds([_place(shapes[i], p[i]) for p in poses for i in moving])
    if movers is not None:
        m_lo, m_hi = movers
        window = 3.0 * float(max(m_hi - m_lo))
        if 0 < window < width:
            centre = (m_lo + m_hi) / 2
            for axis in range(2):
                if hi[axis] - lo[axis] > window:
                    centre[axis] = np.clip(
                        centre[axis], lo[axis] + window / 2, hi[axis] - window / 2
                    )
                else:
                    centre[axis] = (lo[axis] + hi[axis]) / 2
            return centre, 0.53 * window
    return (lo + hi) / 2, 0.53 * width or 0.5


def save_animation(
    scene: Any,
    run: Any,
    path: str | Path,
    *,
    fps: float = 30.0,
    max_frames: int = MAX_FRAMES,
    size: float = 4.0,
    dpi: int = 72,
) -> int:
    """Write an animated GIF of the run to ``path``: each body's edges at its recorded pose
    (fixed bodies grey), the contact points and short arrows along their normals.  Frames are
    sub-sampled to about ``fps`` per simulated second (at most ``max_frames``) and played at
    ``fps``.  Returns the number of frames written."""
    path = Path(path)
    frames = frame_indices(run.t, fps, max_frames)
    if len(frames) == 0:
        raise ValueError("the run recorded no steps: nothing to animate")
    poses = [np.asarray(run.poses[k], dtype=float).reshape(-1, 3) for k in frames]
    shapes = [outline(body.shape) for body in scene.bodies]
    spokes = [
        np.array([[0.0, 0.0], [0.7 * float(body.shape.bounding_radius), 0.0]])
        for body in scene.bodies
    ]

    centre, half = _view(scene, shapes, poses)
    arrow = 0.15 * half

    # A square view in a square axes gives equal aspect with fixed limits.  The axes, title and
    # fixed bodies are drawn once as a background; each frame restores it and draws only the
    # moving artists (blitting), then Pillow writes the frames as one GIF.
    fig = Figure(figsize=(size, size), dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes((0.13, 0.08, 0.84, 0.84))
    ax.set_xlim(centre[0] - half, centre[0] + half)
    ax.set_ylim(centre[1] - half, centre[1] + half)
    ax.set_aspect("equal", adjustable="box")
    ax.tick_params(labelsize=7)
    ax.set_title(f"{run.scene_name} ({run.method}, dt = {run.dt:g} s)", fontsize=8)
    moving: list[tuple[int, Any, Any, Any]] = []  # (body index, edge line, fill, spoke)
    colour = 0
    for i, body in enumerate(scene.bodies):
        world = _place(shapes[i], poses[0][i])
        closed = bool(getattr(body.shape, "closed", True))
        if body.fixed:  # fixed bodies never move: background
            if closed:
                ax.fill(*world[np.all(np.isfinite(world), axis=1)].T, color=_FIXED_FILL, lw=0)
            ax.plot(world[:, 0], world[:, 1], color=_FIXED_EDGE, lw=1.8)
            continue
        c = f"C{colour % 10}"
        colour += 1
        fill = ax.fill([], [], color=c, alpha=0.3, lw=0, animated=True)[0] if closed else None
        (line,) = ax.plot([], [], color=c, lw=1.3, animated=True)
        (spoke,) = ax.plot([], [], color=c, lw=0.8, animated=True)
        moving.append((i, line, fill, spoke))
    (points_line,) = ax.plot([], [], "o", color="crimson", ms=3, zorder=5, animated=True)
    (normals_line,) = ax.plot([], [], color="crimson", lw=0.9, zorder=5, animated=True)
    clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=8, animated=True)
    canvas.draw()
    background = canvas.copy_from_bbox(fig.bbox)

    images: list[Image.Image] = []
    for pose, k in zip(poses, frames, strict=True):
        canvas.restore_region(background)
        for i, line, fill, spoke in moving:
            world = _place(shapes[i], pose[i])
            if fill is not None:
                fill.set_xy(world[np.all(np.isfinite(world), axis=1)])
                ax.draw_artist(fill)
            line.set_data(world[:, 0], world[:, 1])
            ax.draw_artist(line)
            spoke.set_data(*_place(spokes[i], pose[i]).T)
            ax.draw_artist(spoke)
        contacts = run.contacts[k] if k < len(run.contacts) else None
        pts = np.zeros((0, 2)) if contacts is None else contacts.point
        nrm = np.zeros((0, 2)) if contacts is None else contacts.normal
        points_line.set_data(pts[:, 0], pts[:, 1])
        normals_line.set_data(*_arrows(pts, nrm, arrow).T)
        clock.set_text(f"t = {run.t[k]:.3f} s   contacts: {len(pts)}")
        for artist in (normals_line, points_line, clock):
            ax.draw_artist(artist)
        rgba = Image.frombuffer("RGBA", canvas.get_width_height(), canvas.buffer_rgba())
        images.append(rgba.convert("RGB").convert("P", palette=Image.Palette.ADAPTIVE, colors=64))
    images[0].save(
        path, save_all=True, append_images=images[1:], duration=round(1000 / fps), loop=0
    )
    return len(frames)
