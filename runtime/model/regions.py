"""Questions about the region a shape bounds: its support function, whether points lie inside
(winding number), their distance to its edges, and how deeply two convex regions overlap.

Why a module: the compound constructor (parts must not overlap), the centre-of-mass check (a
centre of mass must lie in the shape's convex hull), the contact finder's depth limit (a
shape's smallest width) and the scene loader's overlap test ask the same few questions, and
each answer is exact for straight and circular edges:

- support function ``h(u) = max over the boundary of u . p`` (that of the convex hull);
- ``overlap_depth(a, b) = min over unit u of h_a(u) + h_b(-u)``: for convex a and b, the
  depth of their overlap (the shortest translation that separates them) if positive, minus
  their distance if negative.  The minimum is taken over the directions where it can lie
  for segments and arcs (edge normals, lines between arc centres and corners), a fine ring
  of directions, and a bounded 1-D search about the best one (ellipses).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from scipy.optimize import minimize_scalar

from runtime.model.ellipse_distance import ellipse_distance
from runtime.model.shapes import TAU, Arc, Ellipse, Point, Segment, Shape, _turn
from runtime.settings import CONVEX_EPS, OVERLAP_DIRECTIONS

__all__ = [
    "edge_distance",
    "edge_support",
    "is_convex",
    "overlap_depth",
    "support",
    "winding",
]


def edge_support(edge: Any, u: np.ndarray) -> np.ndarray:
    """max over the edge's points p of u . p, for each row u of ``u``."""
    if isinstance(edge, Segment):
        return np.maximum(u @ np.asarray(edge.start), u @ np.asarray(edge.end))
    if isinstance(edge, Ellipse):
        c, s = math.cos(edge.angle), math.sin(edge.angle)
        along, across = c * u[:, 0] + s * u[:, 1], c * u[:, 1] - s * u[:, 0]
        return u @ np.asarray(edge.centre) + np.hypot(edge.a * along, edge.b * across)
    ends = np.maximum(*(u @ np.asarray(p) for p in edge.end_points))
    facing = (np.arctan2(u[:, 1], u[:, 0]) - edge.start_angle) % TAU <= edge.span
    return np.where(facing, u @ np.asarray(edge.centre) + abs(edge.radius), ends)


def support(shape: Shape | Point, u: np.ndarray) -> np.ndarray:
    """The support function of a shape (its convex hull's) or of a point, at the unit rows of
    ``u``."""
    u = np.asarray(u, dtype=float).reshape(-1, 2)
    if not isinstance(shape, Shape):
        return u @ np.asarray(shape, dtype=float)
    return np.max([edge_support(e, u) for e in shape.edges], axis=0)


def _anchors(shape: Shape | Point) -> list[Point]:
    """Points whose connecting lines may hold the deepest direction: corners, arc centres,
    ellipse centres (a point: itself)."""
    if not isinstance(shape, Shape):
        return [(float(shape[0]), float(shape[1]))]
    found = list(shape.vertices)
    for e in shape.edges:
        if isinstance(e, Segment):
            found += [e.start, e.end]
        else:
            found.append(e.centre)
    return found


def _normals(shape: Shape | Point) -> list[Point]:
    if not isinstance(shape, Shape):
        return []
    return [e.normal for e in shape.edges if isinstance(e, Segment)]


def overlap_depth(a: Shape, b: Shape | Point) -> float:
    """``min over unit u of h_a(u) + h_b(-u)`` (see the module docstring): for convex ``a``
    and ``b`` (a shape or a point), how deep they overlap (> 0) or minus how far apart they
    are (< 0); 0 when they touch.  For a point, minus its distance from the convex hull of
    ``a`` when outside it."""
    angles = list(np.linspace(0.0, TAU, OVERLAP_DIRECTIONS, endpoint=False))
    for nx, ny in _normals(a) + _normals(b):
        angles += [math.atan2(ny, nx), math.atan2(-ny, -nx)]
    for p in _anchors(a):
        for q in _anchors(b):
            if p != q:
                angles += [
                    math.atan2(q[1] - p[1], q[0] - p[0]),
                    math.atan2(p[1] - q[1], p[0] - q[0]),
                ]

    def f(phi: np.ndarray) -> np.ndarray:
        u = np.column_stack([np.cos(phi), np.sin(phi)])
        return support(a, u) + support(b, -u)

    phi = np.asarray(angles)
    values = f(phi)
    best = int(np.argmin(values))
    step = TAU / OVERLAP_DIRECTIONS
    found = minimize_scalar(
        lambda x: float(f(np.array([x]))[0]),
        bounds=(phi[best] - step, phi[best] + step),
        method="bounded",
        options={"xatol": 1e-12},
    )
    return float(min(values[best], found.fun))


def is_convex(shape: Shape) -> bool:
    """Whether a closed shape is one convex loop: no concave arc, no reflex join, consecutive
    edges meeting, the boundary turning once."""
    if not shape.closed or shape.parts:
        return False
    edges = shape.edges
    if len(edges) == 1:
        return isinstance(edges[0], Ellipse) or (isinstance(edges[0], Arc) and edges[0].full)
    if any(isinstance(e, Ellipse) or (isinstance(e, Arc) and not e.convex) for e in edges):
        return False
    scale = shape.bounding_radius
    turning = sum(e.span for e in edges if isinstance(e, Arc))
    for k, e_out in enumerate(edges):
        e_in = edges[k - 1]
        if math.dist(e_in.last, e_out.first) > CONVEX_EPS * scale:
            return False
        turn = _turn(e_in.normal_last(), e_out.normal_first())
        if turn < -CONVEX_EPS:
            return False
        turning += turn
    return abs(turning - TAU) <= CONVEX_EPS * TAU


def _local(points: np.ndarray, centre: Point, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return (points - np.asarray(centre)) @ np.array([[c, -s], [s, c]])


def winding(shape: Shape, p: np.ndarray) -> np.ndarray:
    """Winding number of a closed boundary (every loop) around the points ``p`` ((k, 2)),
    exact for arcs and ellipses."""
    p = np.asarray(p, dtype=float).reshape(-1, 2)
    total = np.zeros(len(p))
    for e in shape.edges:
        if isinstance(e, Ellipse):
            q = _local(p, e.centre, e.angle)
            total += TAU * ((q[:, 0] / e.a) ** 2 + (q[:, 1] / e.b) ** 2 < 1.0)
            continue
        if isinstance(e, Segment):
            a, b = np.asarray(e.start) - p, np.asarray(e.end) - p
            total += np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], np.einsum("ij,ij->i", a, b))
            continue
        a, b = np.asarray(e.first) - p, np.asarray(e.last) - p
        swept = np.arctan2(b[:, 1], b[:, 0]) - np.arctan2(a[:, 1], a[:, 0])
        inside_circle = np.hypot(*(p - np.asarray(e.centre)).T) < abs(e.radius)
        if e.convex:  # counter-clockwise: from inside the circle the angle only increases
            turn = np.where(inside_circle, np.mod(swept, TAU), _wrap(swept))
            total += np.where(inside_circle & e.full, TAU, turn)
        else:  # clockwise; a full concave circle (a ring's inner loop) turns -2 pi inside it
            turn = np.where(inside_circle, -np.mod(-swept, TAU), _wrap(swept))
            total += np.where(inside_circle & e.full, -TAU, turn)
    return np.rint(total / TAU)


def _wrap(angle: np.ndarray) -> np.ndarray:
    return (angle + math.pi) % TAU - math.pi


def edge_distance(e: Any, p: np.ndarray) -> np.ndarray:
    """Exact distance of the points ``p`` ((k, 2)) to the edge."""
    if isinstance(e, Segment):
        a, b = np.asarray(e.start), np.asarray(e.end)
        t = np.clip((p - a) @ (b - a) / float((b - a) @ (b - a)), 0.0, 1.0)
        return np.hypot(*(p - a - np.outer(t, b - a)).T)
    if isinstance(e, Ellipse):
        return ellipse_distance(e.a, e.b, _local(p, e.centre, e.angle))
    v = p - np.asarray(e.centre)
    on_span = np.array([e.contains_angle(a) for a in np.arctan2(v[:, 1], v[:, 0])], dtype=bool)
    ends = [np.hypot(*(p - np.asarray(q)).T) for q in e.end_points]
    return np.where(on_span, np.abs(np.hypot(*v.T) - abs(e.radius)), np.minimum(*ends))
