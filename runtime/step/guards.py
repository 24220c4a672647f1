"""Checks after each step that stop a run which has gone wrong, instead of letting it go on.

Why: a time step that is too large does not fail loudly by itself. Bodies sink into each other
(an impact missed between two steps) and may fall through; an explicit method pumps energy into
a scene with no energy source. Both produce finite numbers that look like a simulation. These
guards turn them into a :class:`runtime.step.simulation.SimulationError` naming the step, the time,
the bodies and the size of the problem. Both limits are relative, so they hold for scenes of
any size:

* ``penetration``: the deepest overlap of two bodies, in units of the smaller body's bounding
  radius (a located impact leaves ~1e-12 m; 1e-2 of a body's size is a missed impact); and,
  with the same switch, a centre of mass whose path over a step crosses an edge of a fixed body
  (:class:`FixedEdges`): a body that passed through a wall within one step leaves no overlap
  behind to measure;
* ``energy_growth``: the rise of the mechanical energy above its value at t = 0, in units of the
  scene's energy scale (kinetic energy + m |g| x the scene's height, summed over the moving
  bodies). Frictionless contacts do no work and restitution <= 1, so physics only takes energy
  out; a rise is integration error, and a rise of half the scale is a blow-up.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from runtime import settings
from runtime.collide.broadphase import sweep
from runtime.compiled import njit
from runtime.model.regions import winding
from runtime.model.shapes import TAU, Arc, Segment


@dataclass(frozen=True)
class Guards:
    """Limits past which a run stops (None: not checked)."""

    penetration: float | None = settings.PENETRATION_LIMIT
    energy_growth: float | None = settings.ENERGY_GROWTH_LIMIT

    def __post_init__(self) -> None:
        for name in ("penetration", "energy_growth"):
            value = getattr(self, name)
            if value is not None and not (np.isfinite(value) and value > 0):
                raise ValueError(f"Guards: {name} must be a finite number > 0 or None, got {value}")


def contact_names(scene, contacts) -> str:
    """'a/b, c/d': the body pairs of ``contacts`` (runtime.collide.contact_set.Contacts),
    sorted, each once ('none' if there are none)."""
    bodies = scene.bodies
    pairs = zip(contacts.body1.tolist(), contacts.body2.tolist(), strict=True)
    names = sorted({f"{bodies[i].name}/{bodies[j].name}" for i, j in pairs})
    return ", ".join(names) or "none"


def energy_scale(scene, radii: np.ndarray, kinetic: float) -> float:
    """The kinetic energy at t = 0 (``kinetic``) plus, over the moving bodies, m |g| (H + 2 r),
    where H is the height the scene spans (every body's centre +- its bounding radius r)."""
    y, g = scene.poses()[:, 1], float(np.hypot(*scene.gravity))
    height = float(np.max(y + radii) - np.min(y - radii))
    return kinetic + sum(
        body.mass * g * (height + 2.0 * r)
        for body, r in zip(scene.bodies, radii, strict=True)
        if not body.fixed
    )


def deepest_overlap(frame, radii: np.ndarray) -> tuple[float, float, int] | None:
    """(depth, depth / the smaller bounding radius, contact index) of the frame's deepest
    overlap relative to body size, or None if nothing overlaps."""
    if not frame.min_gap < 0.0:  # (the frame's, asked once: this runs at every step)
        return None
    gap = np.ascontiguousarray(frame.rows.gap, dtype=float)
    k, relative = deepest_relative(gap, frame.rows.body1, frame.rows.body2, radii)
    return float(-gap[k]), float(relative), int(k)


@njit
def deepest_relative(gap, body1, body2, radii):
    """(index, overlap / the smaller bounding radius) of the contact that overlaps most
    relative to body size (the first such; (-1, 0.0) if none overlaps): the penetration guard,
    from World.step and from the coast's loop (runtime.step.coast)."""
    worst, at = 0.0, -1
    for k in range(gap.size):
        if gap[k] < 0.0:
            relative = -gap[k] / min(radii[body1[k]], radii[body2[k]])
            if relative > worst:
                worst, at = relative, k
    return at, worst


@njit
def _first_passing(start, end, inner, first, second):
    """Index of the first pair (first[p], second[p]) whose centres of mass came closer than the
    larger of their inner radii during the step (straight paths), or -1."""
    for p in range(first.size):
        i, j = first[p], second[p]
        px, py = start[i, 0] - start[j, 0], start[i, 1] - start[j, 1]
        dx = (end[i, 0] - end[j, 0]) - px
        dy = (end[i, 1] - end[j, 1]) - py
        dd = dx * dx + dy * dy
        s = 0.0 if dd == 0.0 else min(max(-(px * dx + py * dy) / dd, 0.0), 1.0)
        cx, cy = px + s * dx, py + s * dy
        limit = max(inner[i], inner[j])
        if cx * cx + cy * cy < limit * limit:
            return p
    return -1


@njit
def _passed_through(start, end, inner, hollow):
    """First pair (i, j) of bodies that are not ``hollow`` (fixed, or open chains) whose
    centres of mass came closer than the larger inner radius during the step, or (-1, -1)."""
    mid_x = 0.5 * (start[:, 0] + end[:, 0])
    mid_y = 0.5 * (start[:, 1] + end[:, 1])
    reach = np.empty(inner.size)
    for b in range(inner.size):
        dx, dy = end[b, 0] - start[b, 0], end[b, 1] - start[b, 1]
        reach[b] = 0.5 * np.sqrt(dx * dx + dy * dy) + inner[b]
    pairs = sweep(mid_x, mid_y, reach, hollow)
    keep = np.empty(pairs.shape[0], np.bool_)
    for p in range(pairs.shape[0]):
        keep[p] = not (hollow[pairs[p, 0]] or hollow[pairs[p, 1]])
    first, second = pairs[keep, 0].copy(), pairs[keep, 1].copy()
    p = _first_passing(start, end, inner, first, second)
    return (-1, -1) if p < 0 else (first[p], second[p])


def passed_through(
    start: np.ndarray, end: np.ndarray, inner: np.ndarray, hollow: np.ndarray
) -> tuple[int, int] | None:
    """The first pair of bodies (not ``hollow``: fixed bodies, open chains) whose centres of
    mass came closer than the larger of their inner radii during the step (straight paths
    between the step's poses ``start`` and ``end``), or None. ``inner``: each body's distance
    from its centre of mass to its boundary (a disc's radius): one centre that far inside the
    other body means they overlap by at least the smaller body's inner radius: they passed
    through each other."""
    i, j = _passed_through(start, end, inner, hollow)
    return None if i < 0 else (int(i), int(j))


def pair_passed_through(
    start: np.ndarray, end: np.ndarray, inner: np.ndarray, first: np.ndarray, second: np.ndarray
) -> int | None:
    """:func:`passed_through` over given pairs (first[p], second[p]) of bodies (an ensemble's
    pairs within one copy): the index p of the first pair that passed through, or None."""
    first = np.ascontiguousarray(first, dtype=np.int64)
    second = np.ascontiguousarray(second, dtype=np.int64)
    p = _first_passing(start, end, inner, first, second)
    return None if p < 0 else p


class FixedEdges:
    """The fixed bodies' segments and arcs in world coordinates, to find a centre of mass that
    went through one of them in a step (the straight path from its start to its end crosses
    the edge). A centre never crosses another body's boundary in a valid motion: it would have
    to overlap that body by more than its own distance to its boundary. Elliptic edges are not
    checked (no fixed body has one in the shipped shapes)."""

    def __init__(self, scene):
        poses = scene.poses()
        segments, arcs = [], []
        for j, (body, shape) in enumerate(zip(scene.bodies, scene.shapes, strict=True)):
            if not body.fixed:
                continue
            x, y, th = poses[j]
            c, s = np.cos(th), np.sin(th)

            def world(p, x=x, y=y, c=c, s=s):
                return (x + c * p[0] - s * p[1], y + s * p[0] + c * p[1])

            for edge in shape.edges:
                if isinstance(edge, Segment):
                    segments.append((*world(edge.start), *world(edge.end), j))
                elif isinstance(edge, Arc):
                    arcs.append((*world(edge.centre), abs(edge.radius), edge.start_angle + th,
                                 edge.span, j))  # fmt: skip
        self.segments = np.array(segments, dtype=float).reshape(-1, 5)
        self.arcs = np.array(arcs, dtype=float).reshape(-1, 6)

    def crossing(
        self, p0: np.ndarray, p1: np.ndarray, rows: np.ndarray | None = None
    ) -> tuple[int, int] | None:
        """(row of p0, fixed body) of the first path p0[i] -> p1[i] ((n, 2) or (n, 3) arrays:
        x, y first) that crosses a fixed edge, or None; ``rows``: the paths to look at (default
        all), so a caller need not copy the moving bodies' rows out of its poses."""
        p0, p1 = np.ascontiguousarray(p0), np.ascontiguousarray(p1)
        rows = np.arange(len(p0)) if rows is None else rows
        row, owner = _crossing(p0, p1, rows, self.segments, self.arcs)
        return None if row < 0 else (int(row), int(owner))


@njit
def _crossing(p0, p1, rows, segments, arcs):
    for i in rows:
        dx, dy = p1[i, 0] - p0[i, 0], p1[i, 1] - p0[i, 1]
        if dx == 0.0 and dy == 0.0:
            continue
        for k in range(segments.shape[0]):
            sx, sy, ex, ey, owner = segments[k]
            ux, uy = ex - sx, ey - sy
            wx, wy = sx - p0[i, 0], sy - p0[i, 1]
            denom = dx * uy - dy * ux
            if denom == 0.0:
                continue
            t = (wx * uy - wy * ux) / denom
            u = (wx * dy - wy * dx) / denom
            if 0.0 <= t <= 1.0 and 0.0 <= u <= 1.0:
                return i, int(owner)
        for k in range(arcs.shape[0]):
            cx, cy, radius, start, span, owner = arcs[k]
            fx, fy = p0[i, 0] - cx, p0[i, 1] - cy
            a = dx * dx + dy * dy
            b = 2.0 * (dx * fx + dy * fy)
            disc = b * b - 4.0 * a * (fx * fx + fy * fy - radius * radius)
            if disc < 0.0:
                continue
            root = np.sqrt(disc)
            for sign in (-1.0, 1.0):
                t = (-b + sign * root) / (2.0 * a)
                if 0.0 <= t <= 1.0:
                    angle = np.arctan2(fy + t * dy, fx + t * dx)
                    if (angle - start) % TAU <= span:
                        return i, int(owner)
    return -1, -1


def inner_radius(shape) -> float:
    """Distance from the body's origin (its centre of mass) to the nearest point of its
    boundary: the radius of the largest circle about the centre of mass inside a closed body
    (0 for an open chain, which encloses nothing, and for a body whose centre of mass lies
    outside its material: a cup's or a frame's, in its hollow). Kept on the shape, as its
    feature tables are: every World of a scene asks (a quarter of a short run's set-up)."""
    found = shape._cache.get("inner_radius")
    if found is None:
        found = shape._cache["inner_radius"] = _inner_radius(shape)
    return found


def _inner_radius(shape) -> float:
    if not shape.closed:
        return 0.0
    origin = np.zeros((1, 2))
    if not any(winding(part, origin)[0] != 0 for part in shape.parts or (shape,)):
        return 0.0
    best = np.inf
    for edge in shape.edges:
        if isinstance(edge, Segment):
            a, b = np.asarray(edge.start), np.asarray(edge.end)
            u = b - a
            t = float(np.clip(-(a @ u) / (u @ u), 0.0, 1.0))
            best = min(best, float(np.hypot(*(a + t * u))))
        elif isinstance(edge, Arc):
            c, r = np.asarray(edge.centre), abs(edge.radius)
            direction = np.arctan2(-c[1], -c[0]) if np.any(c) else edge.start_angle
            if edge.contains_angle(float(direction)):
                best = min(best, abs(float(np.hypot(*c)) - r))
            best = min(best, *(float(np.hypot(*p)) for p in edge.end_points))
        else:  # an ellipse: the only edge of its shape, centred at the centre of mass
            best = min(best, min(edge.a, edge.b))
    return best
