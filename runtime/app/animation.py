"""The animation of a run: frames of the bodies, contact points and normals, as GIF and MP4.

Why: a small animation shows at a glance what numbers hide -- a body sinking into a bowl, a
chattering contact, a box tipping the wrong way.  Frames are rendered once (matplotlib's Agg
canvas, blitting the moving parts over a background of the fixed bodies) and handed to each
writer: Pillow's GIF and, when asked and ffmpeg is on PATH, an MP4 through ffmpeg's stdin.

The view is fixed for the whole animation and frames the scene: the fixed bodies and every
moving body over its *whole* recorded path (not only the frames shown), so a body falling from
high up stays in view and nothing shrinks or jumps.  When the fixed bodies reach much farther
than the moving ones go (a long floor under a small body), the view is about three times the
moving bodies' range, kept inside the scene.
"""

from __future__ import annotations

import math
import shutil
import subprocess
from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from PIL import Image  # noqa: E402

from runtime.app.plotting import FIXED_EDGE, FIXED_FILL, NO_MATHTEXT, outline, place  # noqa: E402
from runtime.app.text import terminal_safe  # noqa: E402
from runtime.model.links import link_segments  # noqa: E402

__all__ = [
    "FfmpegError",
    "MAX_FRAMES",
    "MAX_PLAYBACK_FPS",
    "Look",
    "Mp4Writer",
    "View",
    "ffmpeg",
    "frame_indices",
    "render_frames",
    "save_animation",
    "scene_view",
    "write_gif",
]

MAX_FRAMES = 150  # keeps a GIF to a few hundred kB
MAX_PLAYBACK_FPS = 50.0  # GIF delays are in 1/100 s and players slow delays under 2/100 s down
MARGIN = 0.06  # share of the view left empty around the scene on each side


@dataclass(frozen=True)
class Look:
    """How the animation looks: pixel size, dots per inch (text and line scale), frames per
    simulated second, and whether contact normals are drawn as arrows."""

    width: int = 288
    height: int = 288
    dpi: float = 72.0
    fps: float = 30.0
    arrows: bool = True

    @property
    def playback_fps(self) -> float:
        """Frames per second of playback: ``fps`` (real time) up to MAX_PLAYBACK_FPS; above, the
        animation plays in slow motion."""
        return min(self.fps, MAX_PLAYBACK_FPS)


@dataclass(frozen=True)
class View:
    """The world rectangle shown: centre and half-sizes (m)."""

    centre: np.ndarray
    half_x: float
    half_y: float


def frame_indices(t: Sequence[float], fps: float, max_frames: int = MAX_FRAMES) -> np.ndarray:
    """Indices of the recorded steps to show: about ``fps`` per second of simulated time, the
    first and the last always, never more than ``max_frames`` (then evenly spread)."""
    t = np.asarray(t, dtype=float)
    if len(t) == 0:
        return np.zeros(0, dtype=int)
    span = float(t[-1] - t[0])
    wanted = min(float(max_frames), max(2.0, math.floor(span * fps + 1e-9) + 1.0), len(t))
    targets = np.linspace(t[0], t[-1], int(wanted))
    indices = np.clip(np.searchsorted(t, targets), 0, len(t) - 1)
    return np.unique(indices)


def _bounds(points: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """Lower-left and upper-right corners of the finite rows of ``points``, or None."""
    points = points[np.all(np.isfinite(points), axis=1)]
    return (points.min(axis=0), points.max(axis=0)) if len(points) else None


def scene_view(scene: Any, poses: np.ndarray, aspect: float = 1.0) -> View:
    """The view of a run with ``poses`` (K, n, 3) in an image of width/height ``aspect``."""
    fixed = [i for i, b in enumerate(scene.bodies) if b.fixed]
    moving = [i for i, b in enumerate(scene.bodies) if not b.fixed]
    parts = [place(outline(scene.bodies[i].shape), poses[0, i]) for i in fixed]
    movers = None
    if moving and len(poses):
        centres = poses[:, moving, :2]
        reach = np.array([scene.bodies[i].shape.bounding_radius for i in moving])[:, None]
        corners = np.concatenate(
            [(centres - reach).reshape(-1, 2), (centres + reach).reshape(-1, 2)]
        )
        links = [*getattr(scene, "joints", []), *getattr(scene, "springs", [])]
        if links:  # their world ends too (a pendulum's pivot): part of what moves
            corners = np.concatenate([corners, link_segments(links, poses[0])])
        movers = _bounds(corners)
        parts.append(corners)
    everything = _bounds(np.concatenate(parts)) if parts else None
    if everything is None:
        return View(np.zeros(2), 1.0 * aspect, 1.0)
    lo, hi = everything
    if movers is not None:
        m_lo, m_hi = movers
        window = 3.0 * float(max(m_hi - m_lo))
        if 0 < window < float(max(hi - lo)):  # a long floor under a small body: follow it
            size = np.array([window * max(aspect, 1.0), window / min(aspect, 1.0)])
            centre = (m_lo + m_hi) / 2
            for axis in range(2):
                if hi[axis] - lo[axis] > size[axis]:
                    low, high = lo[axis] + size[axis] / 2, hi[axis] - size[axis] / 2
                    centre[axis] = np.clip(centre[axis], low, high)
                else:
                    centre[axis] = (lo[axis] + hi[axis]) / 2
            lo, hi = centre - window / 2, centre + window / 2
    centre = (lo + hi) / 2
    half_x, half_y = float(hi[0] - lo[0]) / 2, float(hi[1] - lo[1]) / 2
    half_x, half_y = max(half_x, half_y * aspect), max(half_y, half_x / aspect)
    if not half_x > 0:
        half_x, half_y = 0.5 * aspect, 0.5
    scale = 1.0 / (1.0 - 2.0 * MARGIN)
    return View(centre, half_x * scale, half_y * scale)


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


def _contact_points(contacts: Any) -> tuple[np.ndarray, np.ndarray]:
    """(points, normals) of one recorded step's contacts (a Contacts set)."""
    return np.asarray(contacts.point, float), np.asarray(contacts.normal, float)


def render_frames(scene: Any, run: Any, look: Look = Look()) -> Iterator[np.ndarray]:
    """(height, width, 3) uint8 RGB frames of the run: each body's edges at its recorded pose
    (fixed bodies grey), its joints and springs as lines between their anchors, the contact
    points and (``look.arrows``) short arrows along their
    normals; about ``look.fps`` frames per simulated second, at most MAX_FRAMES."""
    frames = frame_indices(run.t, look.fps)
    if len(frames) == 0:
        raise ValueError("the run recorded no steps: nothing to animate")
    all_poses = np.asarray(run.poses, dtype=float).reshape(len(run.t), -1, 3)
    shapes = [outline(body.shape) for body in scene.bodies]
    spokes = [
        np.array([[0.0, 0.0], [0.7 * float(body.shape.bounding_radius), 0.0]])
        for body in scene.bodies
    ]
    view = scene_view(scene, all_poses, look.width / look.height)
    arrow = 0.15 * min(view.half_x, view.half_y)

    with matplotlib.rc_context(NO_MATHTEXT):
        fig = Figure(figsize=(look.width / look.dpi, look.height / look.dpi), dpi=look.dpi)
        canvas = FigureCanvasAgg(fig)
        ax = fig.add_axes((0.13, 0.08, 0.84, 0.84))
        ax.set_xlim(view.centre[0] - view.half_x, view.centre[0] + view.half_x)
        ax.set_ylim(view.centre[1] - view.half_y, view.centre[1] + view.half_y)
        ax.set_aspect("equal", adjustable="box")
        ax.tick_params(labelsize=7)
        title = terminal_safe(f"{run.scene_name} ({run.method}, dt = {run.dt:g} s)")
        ax.set_title(title, fontsize=8)
        moving: list[tuple[int, Any, Any, Any]] = []  # (body index, edge line, fill, spoke)
        colour = 0
        for i, body in enumerate(scene.bodies):
            closed = bool(getattr(body.shape, "closed", True))
            if body.fixed:  # fixed bodies never move: background
                world = place(shapes[i], all_poses[0, i])
                if closed:
                    ax.fill(*world[np.all(np.isfinite(world), axis=1)].T, color=FIXED_FILL, lw=0)
                ax.plot(world[:, 0], world[:, 1], color=FIXED_EDGE, lw=1.8)
                continue
            c = f"C{colour % 10}"
            colour += 1
            fill = ax.fill([], [], color=c, alpha=0.3, lw=0, animated=True)[0] if closed else None
            (line,) = ax.plot([], [], color=c, lw=1.3, animated=True)
            (spoke,) = ax.plot([], [], color=c, lw=0.8, animated=True)
            moving.append((i, line, fill, spoke))
        links = [*getattr(scene, "joints", []), *getattr(scene, "springs", [])]
        (links_line,) = ax.plot([], [], color="0.35", lw=0.9, zorder=4, animated=True)
        (points_line,) = ax.plot([], [], "o", color="crimson", ms=3, zorder=5, animated=True)
        (normals_line,) = ax.plot([], [], color="crimson", lw=0.9, zorder=5, animated=True)
        clock = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=8, animated=True)
        canvas.draw()
        background = canvas.copy_from_bbox(fig.bbox)

        for k in frames:
            pose = all_poses[k]
            canvas.restore_region(background)
            for i, line, fill, spoke in moving:
                world = place(shapes[i], pose[i])
                if fill is not None:
                    fill.set_xy(world[np.all(np.isfinite(world), axis=1)])
                    ax.draw_artist(fill)
                line.set_data(world[:, 0], world[:, 1])
                ax.draw_artist(line)
                spoke.set_data(*place(spokes[i], pose[i]).T)
                ax.draw_artist(spoke)
            if links:  # joints and springs: a line between their anchors
                links_line.set_data(*link_segments(links, pose).T)
                ax.draw_artist(links_line)
            contacts = run.contacts[k] if k < len(run.contacts) else []
            pts, nrm = _contact_points(contacts)
            points_line.set_data(pts[:, 0], pts[:, 1])
            ax.draw_artist(points_line)
            if look.arrows:
                normals_line.set_data(*_arrows(pts, nrm, arrow).T)
                ax.draw_artist(normals_line)
            clock.set_text(f"t = {run.t[k]:.3f} s   contacts: {len(contacts)}")
            ax.draw_artist(clock)
            rgba = np.asarray(canvas.buffer_rgba())
            yield _sized(rgba[..., :3], look.width, look.height)


def _sized(rgb: np.ndarray, width: int, height: int) -> np.ndarray:
    """The frame at exactly width x height (Agg may round the canvas by a pixel): pad or crop."""
    if rgb.shape[:2] == (height, width):
        return np.ascontiguousarray(rgb)
    out = np.full((height, width, 3), 255, dtype=np.uint8)
    h, w = min(height, rgb.shape[0]), min(width, rgb.shape[1])
    out[:h, :w] = rgb[:h, :w]
    return out


def _palette(frame: np.ndarray) -> Image.Image:
    """A GIF frame: 64 colours chosen for this frame."""
    return Image.fromarray(frame).convert("P", palette=Image.Palette.ADAPTIVE, colors=64)


def write_gif(images: Sequence[Image.Image], path: Path, playback_fps: float) -> None:
    """An animated, looping GIF of palette ``images``."""
    delay = int(round(1000.0 / playback_fps))
    images[0].save(path, save_all=True, append_images=list(images[1:]), duration=delay, loop=0)


class FfmpegError(RuntimeError):
    """ffmpeg is missing or failed (one line)."""


def ffmpeg() -> str:
    """The ffmpeg on PATH, or FfmpegError saying how to get it."""
    found = shutil.which("ffmpeg")
    if found is None:
        raise FfmpegError(
            "--mp4 needs ffmpeg on PATH and there is none; install it (Debian: apt-get install "
            "ffmpeg) or leave out --mp4 (animation.gif is written either way)"
        )
    return found


class Mp4Writer:
    """Frames streamed to ffmpeg's stdin as raw RGB, encoded as MP4 (H.264 where ffmpeg has it,
    else its default codec for .mp4), yuv420p so every player shows it."""

    def __init__(self, path: Path, width: int, height: int, playback_fps: float) -> None:
        command = [
            ffmpeg(), "-loglevel", "error", "-y",
            "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{width}x{height}",
            "-r", f"{playback_fps:g}", "-i", "-",
            "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2",  # yuv420p needs even sizes
            "-pix_fmt", "yuv420p", "-movflags", "+faststart", str(path),
        ]  # fmt: skip
        try:
            self.process = subprocess.Popen(
                command, stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
            )
        except OSError as exc:
            raise FfmpegError(f"cannot run ffmpeg: {exc.strerror or exc}") from None

    def write(self, frame: np.ndarray) -> None:
        """One frame; if ffmpeg has stopped, nothing (``finish`` reports why)."""
        try:
            self.process.stdin.write(frame.tobytes())
        except BrokenPipeError:
            pass

    def finish(self) -> None:
        """Wait for ffmpeg; FfmpegError with its last message line if it failed."""
        if self.process.stdin and not self.process.stdin.closed:
            try:
                self.process.stdin.close()
            except BrokenPipeError:
                pass
        err = self.process.stderr.read() if self.process.stderr else b""
        status = self.process.wait()
        if status != 0:
            lines = err.decode("utf-8", "replace").strip().splitlines() or ["no message"]
            raise FfmpegError(f"ffmpeg failed (exit status {status}): {lines[-1]}")

    def abort(self) -> None:
        """Stop ffmpeg (the run was interrupted): no half-written video is kept by the caller."""
        self.process.kill()
        self.process.wait()


def save_animation(
    scene: Any, run: Any, path: str | Path, look: Look = Look(), mp4: Path | None = None
) -> int:
    """Write the run's animation as a GIF to ``path`` (and an MP4 to ``mp4``), rendering each
    frame once; returns the number of frames.  If ffmpeg fails, the GIF is written and then
    FfmpegError raised."""
    video = Mp4Writer(mp4, look.width, look.height, look.playback_fps) if mp4 else None
    images = []
    try:
        for frame in render_frames(scene, run, look):
            images.append(_palette(frame))
            if video is not None:
                video.write(frame)
        write_gif(images, Path(path), look.playback_fps)
    except BaseException:
        if video is not None:
            video.abort()
        raise
    if video is not None:
        video.finish()
    return len(images)
