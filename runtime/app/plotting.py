"""The energy and contact-force plot of a run, and the geometry both pictures share.

Why this module exists: a number such as "energy drift 1e-9 J" says little about *where* a run
went wrong; a plot of the energy next to the contact forces makes a bad step or a chattering
contact visible at a glance.  The energy panel keeps apart what the impacts took (inelastic by
design) and what the integrator drifted (runtime/app/energy.py).  Drawn from a finished (or
partial) :class:`runtime.Run` and the scene's shapes, without touching the engine; the
animation is runtime/app/animation.py.

Only matplotlib (Agg backend, no display needed) is used.  Bodies are drawn from their exact
edges -- segments, convex and concave arcs and ellipses, sampled densely -- placed at each
recorded pose ``X + R(th) p`` (docs/conventions.md).  Names from the scene are drawn as plain
text (mathtext off: a ``$`` in a name is a dollar sign; control characters escaped, as on the
terminal), and legends sit beside the axes, off the data.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from runtime.app.contact_table import contact_table  # noqa: E402
from runtime.app.energy import energy_budget  # noqa: E402
from runtime.app.text import terminal_safe  # noqa: E402
from runtime.collide.contact_set import KIND_NAMES  # noqa: E402
from runtime.model.shapes import TAU, Arc, Ellipse, Segment  # noqa: E402

__all__ = [
    "FIXED_EDGE",
    "FIXED_FILL",
    "NO_MATHTEXT",
    "edge_points",
    "energy_forces_figure",
    "outline",
    "per_contact_forces",
    "place",
    "plot_energy_forces",
]

FIXED_EDGE, FIXED_FILL = "0.35", "0.85"
NO_MATHTEXT = {"text.parse_math": False, "text.usetex": False}  # names are plain text
_ARC_STEP = TAU / 96  # radians between samples along an arc or ellipse
_LEGEND = {"loc": "upper left", "bbox_to_anchor": (1.01, 1.0), "borderaxespad": 0.0}


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


def place(points: np.ndarray, pose: Sequence[float]) -> np.ndarray:
    """World coordinates ``X + R(th) p`` of body points (rows of ``points``)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    x, y = points[:, 0], points[:, 1]
    return np.column_stack([pose[0] + c * x - s * y, pose[1] + s * x + c * y])


# -- energy and forces --------------------------------------------------------------------------


def per_contact_forces(run: Any) -> dict[tuple, np.ndarray]:
    """Normal force of each contact over the recorded steps, NaN where it is not active; keyed
    by (body 1, body 2, case, features), which follows one contact from step to step."""
    table = contact_table(run)
    series: dict[tuple, np.ndarray] = {}
    keys = zip(
        table["contact_body1"].tolist(),
        table["contact_body2"].tolist(),
        table["contact_case"].tolist(),
        map(tuple, table["contact_feature"].tolist()),
        strict=True,
    )
    for k, key, force in zip(table["contact_step"], keys, table["contact_force"], strict=True):
        series.setdefault(key, np.full(len(run.t), np.nan))[k] = force
    return series


def _feature_text(feature: tuple) -> str:
    """``(0, 2, 1, 0)`` -> ``"vertex 2 / edge 0"``."""
    kind1, index1, kind2, index2 = feature
    return f"{KIND_NAMES[kind1]} {index1} / {KIND_NAMES[kind2]} {index2}"


def _contact_label(key: tuple, names: Sequence[str], several: bool) -> str:
    """``"disc/bowl (circle_circle)"``, with the features when the pair touches more than once."""
    b1, b2, case, feature = key

    def name(i: int) -> str:
        return names[i] if 0 <= i < len(names) else str(i)

    label = terminal_safe(f"{name(b1)}/{name(b2)}")
    if case:
        label += f" ({case})"
    return label + (f" {_feature_text(feature)}" if several else "")


def _legend(ax: Any, **kwargs: Any) -> None:
    """A legend beside the axes (never over the data)."""
    ax.legend(fontsize="small", title_fontsize="small", **_LEGEND, **kwargs)


def _energy_panel(ax: Any, run: Any, t: np.ndarray) -> None:
    """E(t) - E(0); when impacts took energy out, also the energy lost at impacts and the
    numerical drift (the change they do not explain)."""
    budget = energy_budget(run)
    if not budget.impacts:
        ax.plot(t, budget.change, color="C0", lw=1.2, label="E(t) - E(0)")
        ax.set_ylabel("energy drift [J]")
        return
    ax.plot(t, budget.change, color="0.3", lw=1.2, label="E(t) - E(0)")
    ax.plot(t, -budget.lost, color="C3", lw=1.2, ls="--", label="lost at impacts")
    ax.plot(t, budget.drift, color="C0", lw=1.2, label="numerical drift")
    ax.set_ylabel("energy [J]")
    lost, drift = float(budget.lost[-1]), float(budget.drift[-1])
    _legend(ax, title=f"lost at {budget.impacts} impacts: {lost:.3g} J\ndrift: {drift:.3g} J")


def energy_forces_figure(run: Any, names: Sequence[str]) -> Figure:
    """Two stacked panels over time: the energy (change, lost at impacts, drift) and the normal
    contact forces (their total, and each contact)."""
    t = np.asarray(run.t, dtype=float)
    total = np.array([np.sum(f) for f in run.contact_forces], dtype=float)
    with matplotlib.rc_context(NO_MATHTEXT):
        fig = Figure(figsize=(9, 5.5), layout="constrained")
        ax_e, ax_f = fig.subplots(2, 1, sharex=True)
        if len(t):
            _energy_panel(ax_e, run, t)
        ax_e.axhline(0.0, color="0.6", lw=0.6)
        ax_e.set_title(terminal_safe(f"{run.scene_name}: {run.method}, dt = {run.dt:g} s"))
        ax_e.grid(alpha=0.3)
        if len(total):  # underneath: with one contact it is that contact's force
            ax_f.plot(t, total, color="0.3", lw=3.0, alpha=0.35, label="total")
        series = per_contact_forces(run)
        pairs = [key[:2] for key in series]
        for i, (key, force) in enumerate(series.items()):  # in order of first touch
            label = _contact_label(key, names, pairs.count(key[:2]) > 1)
            ax_f.plot(t, force, lw=1.0, color=f"C{(i + 1) % 10}", label=label if i < 8 else None)
        ax_f.set_xlabel("time t [s]")
        ax_f.set_ylabel("normal contact force [N]")
        ax_f.grid(alpha=0.3)
        if len(total):
            more = f"the first 8 of {len(series)} contacts" if len(series) > 8 else None
            _legend(ax_f, title=more)
        else:
            ax_f.text(0.5, 0.5, "nothing recorded", ha="center", transform=ax_f.transAxes)
    return fig


def plot_energy_forces(run: Any, names: Sequence[str], path: str | Path) -> Path:
    """The energy and contact-force figure of the run as a PNG at ``path``."""
    path = Path(path)
    energy_forces_figure(run, names).savefig(path, dpi=100)
    return path
