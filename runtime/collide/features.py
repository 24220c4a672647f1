"""Contact features of shapes as flat tables: what the compiled narrow phase reads.

Why tables: the narrow phase runs compiled over many bodies, so a shape's features are rows
of plain float arrays (built once per Shape and cached on it), and a scene's are those rows
concatenated with per-body ranges (:func:`scene_tables`).  All in body coordinates:

- corners: a vertex of ``Shape.vertices`` with its normal cone (the outward normal where the
  cone starts, its width: the turn of the boundary there) and whether the edge before / after
  it is an arc (a smooth feature that may touch instead); a vertex at no join has the full
  cone, the end of an open chain the half-plane of directions beyond it;
- ends: where a convex arc runs smoothly into a straight side; it acts as a vertex against
  straight edges for directions beyond its arc (a rounded box flat on a floor touches at the
  two ends of its flat side).  ``side`` is +1 if the arc comes before the join, -1 after;
- segments: start point, outward normal, unit tangent, length;
- arcs: centre, signed radius (concave < 0), start angle, span (counter-clockwise);
- ellipses: centre, semi-axes, angle.

Every row ends with the index of its vertex (corners) or edge (the others) in the Shape: the
feature index that :class:`~runtime.collide.contact_set.Contacts` reports.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from runtime.model.shapes import TAU, Arc, Ellipse, Segment, Shape
from runtime.settings import JOIN_EPS, TURN_EPS, WIDTH_DIRECTIONS

X, Y = 0, 1  # every table: the feature's point (corner, end, segment start, centre)
C_NX, C_NY, C_WIDTH, C_ARC_BEFORE, C_ARC_AFTER, C_INDEX = 2, 3, 4, 5, 6, 7
E_NX, E_NY, E_SIDE, E_INDEX = 2, 3, 4, 5
S_NX, S_NY, S_TX, S_TY, S_LENGTH, S_INDEX = 2, 3, 4, 5, 6, 7
A_R, A_START, A_SPAN, A_INDEX = 2, 3, 4, 5
L_A, L_B, L_ANGLE, L_INDEX = 2, 3, 4, 5
WIDTH = 8  # columns of every table (unused ones are 0)
CORNERS, ENDS, SEGMENTS, ARCS, ELLIPSES = range(5)  # the kinds: columns of FeatureTables.start
CLOSED, HALF_WIDTH, RADIUS, FIXED = range(4)  # columns of FeatureTables.body


class ShapeFeatures(NamedTuple):
    """One shape's feature tables (see the module docstring)."""

    tables: tuple[np.ndarray, ...]  # corners, ends, segments, arcs, ellipses
    closed: bool
    half_width: float  # half the smallest width (inf for an open chain): the depth limit
    bounding_radius: float

    def kinds(self) -> tuple[bool, bool, bool, bool, bool]:
        """(has corners, smooth ends, straight edges, convex curves, concave arcs)."""
        corners, ends, segments, arcs, ellipses = self.tables
        convex = bool(np.any(arcs[:, A_R] > 0)) or len(ellipses) > 0
        concave = bool(np.any(arcs[:, A_R] < 0))
        return len(corners) > 0, len(ends) > 0, len(segments) > 0, convex, concave


class FeatureTables(NamedTuple):
    """A scene's features: one (F, WIDTH) table ``rows`` holding the corners of every body,
    then their ends, segments, arcs and ellipses; rows ``start[b, kind]`` to
    ``start[b + 1, kind]`` are body b's features of that kind.  ``body`` (n, 4): closed?,
    half width, bounding radius, fixed? (as floats)."""

    rows: np.ndarray
    start: np.ndarray  # (n + 1, 5) int64
    body: np.ndarray


def features(shape: Shape) -> ShapeFeatures:
    """The shape's feature tables, built once and kept on the shape."""
    found = shape._cache.get("features")
    if found is None:
        found = shape._cache["features"] = _build(shape)
    return found


def scene_tables(shapes: Sequence[Shape], fixed: Sequence[bool]) -> FeatureTables:
    """The features of every body, stacked (``fixed``: one flag per shape)."""
    each = [features(s) for s in shapes]
    counts = np.array([[len(t) for t in f.tables] for f in each], dtype=np.int64).reshape(-1, 5)
    start = np.zeros((len(each) + 1, 5), dtype=np.int64)
    start[1:] = np.cumsum(counts, axis=0)
    start += np.concatenate([[0], np.cumsum(counts.sum(axis=0))[:-1]])  # kind blocks in turn
    rows = [f.tables[kind] for kind in range(5) for f in each]
    stacked = np.ascontiguousarray(np.concatenate(rows or [np.zeros((0, WIDTH))]))
    body = np.array(
        [
            (f.closed, f.half_width, f.bounding_radius, bool(x))
            for f, x in zip(each, fixed, strict=True)
        ],
        dtype=float,
    ).reshape(-1, 4)
    return FeatureTables(stacked, start, body)


def _table(rows: list) -> np.ndarray:
    table = np.zeros((len(rows), WIDTH))
    for k, row in enumerate(rows):
        table[k, : len(row)] = row
    return table


def _build(shape: Shape) -> ShapeFeatures:
    edges, n = shape.edges, len(shape.edges)
    cones, ends = [], []  # cones: (point, normal where it starts, width, arc before, arc after)
    for i in range(n if shape.closed else n - 1):
        e_in, e_out = edges[i], edges[(i + 1) % n]
        if isinstance(e_in, Ellipse):
            continue
        (ax, ay), (bx, by) = e_in.normal_last(), e_out.normal_first()
        turn = math.atan2(ax * by - ay * bx, ax * bx + ay * by)
        arc_in, arc_out = isinstance(e_in, Arc), isinstance(e_out, Arc)
        if turn > TURN_EPS:
            cones.append((e_out.first, (ax, ay), turn, arc_in, arc_out))
        elif turn > -TURN_EPS and arc_in != arc_out and (e_in if arc_in else e_out).radius > 0:
            ends.append((*e_out.first, ax, ay, 1.0 if arc_in else -1.0, i))
    if not shape.closed:  # chain ends: the half-plane of directions beyond the end
        (fx, fy), last = edges[0].normal_first(), edges[-1].normal_last()
        cones.append((edges[0].first, (-fx, -fy), math.pi, False, isinstance(edges[0], Arc)))
        cones.append((edges[-1].last, last, math.pi, isinstance(edges[-1], Arc), False))
    near = JOIN_EPS * shape.bounding_radius
    corners = []
    for k, (x, y) in enumerate(shape.vertices):
        at = [c for c in cones if math.hypot(c[0][0] - x, c[0][1] - y) <= near]
        (nx, ny), width, before, after = at[0][1:] if at else ((1.0, 0.0), TAU, False, False)
        corners.append((x, y, nx, ny, width, before, after, k))
    segments, arcs, ellipses = [], [], []
    for j, e in enumerate(edges):
        if isinstance(e, Segment):
            (ax, ay), (nx, ny) = e.start, e.normal
            segments.append((ax, ay, nx, ny, -ny, nx, e.length, j))
        elif isinstance(e, Arc):
            arcs.append((*e.centre, e.radius, e.start_angle, e.span, j))
        else:
            ellipses.append((*e.centre, e.a, e.b, e.angle, j))
    rows = (corners, ends, segments, arcs, ellipses)
    tables = tuple(_table(r) for r in rows)
    half = half_width(shape) if shape.closed else math.inf
    return ShapeFeatures(tables, shape.closed, half, shape.bounding_radius)


def half_width(shape: Shape) -> float:
    """Half the smallest width of the shape: min over directions u of (h(u) + h(-u)) / 2 with
    h the exact support function of its edges (a disc's is its radius)."""
    a = np.linspace(0.0, math.pi, WIDTH_DIRECTIONS, endpoint=False)
    u = np.stack([np.cos(a), np.sin(a)], axis=1)
    reach = np.full((2, len(a)), -math.inf)
    for k, v in enumerate((u, -u)):
        for e in shape.edges:
            reach[k] = np.maximum(reach[k], _support(e, v))
    return 0.5 * float(np.min(reach.sum(axis=0)))


def _support(edge, u: np.ndarray) -> np.ndarray:
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
