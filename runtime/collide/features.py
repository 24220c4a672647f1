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
- segments: start point, outward normal, unit tangent, length, and the free angle of a reflex
  join at its start and at its end (0: none; runtime.collide.junctions);
- arcs: centre, signed radius (concave < 0), start angle, span (counter-clockwise);
- ellipses: centre, semi-axes, angle.

Every row ends with the index of its vertex (corners) or edge (the others) in the Shape: the
feature index that :class:`~runtime.collide.contact_set.Contacts` reports.

A compound body (``Shape.parts``) has one set of tables per part, its *units*: each part is
convex, so the narrow phase's per-body reasoning (a closed body's inside, its depth limit)
holds per unit, and a contact is between a part of one body and a part of another.  Feature
indices are the compound's (its edges and vertices are the parts' in order).  A part's corner
on another part's boundary is hidden or narrowed: its cone is intersected with that part's
there (a vertex's cone, or an edge's normal), so a flat join of two parts (the side of a
frame) or a reflex one (its inner corner) has no corner.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import NamedTuple

import numpy as np

from runtime.model.ellipse_distance import nearest_on_ellipse
from runtime.model.regions import edge_distance, edge_support, winding
from runtime.model.shapes import TAU, Arc, Ellipse, Segment, Shape
from runtime.settings import JOIN_EPS, THICKNESS_RAYS, TURN_EPS, WIDTH_DIRECTIONS

X, Y = 0, 1  # every table: the feature's point (corner, end, segment start, centre)
C_NX, C_NY, C_WIDTH, C_ARC_BEFORE, C_ARC_AFTER, C_INDEX = 2, 3, 4, 5, 6, 7
E_NX, E_NY, E_SIDE, E_INDEX = 2, 3, 4, 5
S_NX, S_NY, S_TX, S_TY, S_LENGTH, S_INDEX, S_JOIN_START, S_JOIN_END = 2, 3, 4, 5, 6, 7, 8, 9
A_R, A_START, A_SPAN, A_INDEX = 2, 3, 4, 5
L_A, L_B, L_ANGLE, L_INDEX = 2, 3, 4, 5
# a corner's cone width (C_WIDTH) where it touches nothing (runtime.collide.junctions)
HIDDEN = -1.0
WIDTH = 10  # columns of every table (unused ones are 0)
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
    """A scene's features by unit (a body, or one part of a compound body): one (F, WIDTH)
    table ``rows`` holding the corners of every unit, then their ends, segments, arcs and
    ellipses; rows ``start[u, kind]`` to ``start[u + 1, kind]`` are unit u's features of that
    kind.  ``body`` (U, 4): closed?, half width, bounding radius, fixed? (as floats);
    ``owner`` (U,): the body of each unit (units of a body are consecutive); ``body_start``
    (n + 1, 5): the same ranges per body (all its units)."""

    rows: np.ndarray
    start: np.ndarray  # (U + 1, 5) int64
    body: np.ndarray
    owner: np.ndarray  # (U,) int64
    body_start: np.ndarray  # (n + 1, 5) int64


def features(shape: Shape) -> ShapeFeatures:
    """The shape's feature tables, built once and kept on the shape; a compound's are its
    units' stacked (for what is asked of the whole body: its kinds and its depth limit, the
    thinnest part's)."""
    found = shape._cache.get("features")
    if found is None:
        if shape.parts:
            each = units(shape)
            tables = tuple(np.concatenate([u.tables[k] for u in each]) for k in range(5))
            half = min(u.half_width for u in each)
            found = ShapeFeatures(tables, True, half, shape.bounding_radius)
        else:
            found = _build(shape)
        shape._cache["features"] = found
    return found


def units(shape: Shape) -> tuple[ShapeFeatures, ...]:
    """The feature tables of each unit of the shape: itself, or each part of a compound with
    the compound's feature indices and its hidden corners left out."""
    if not shape.parts:
        return (features(shape),)
    found = shape._cache.get("units")
    if found is None:
        found = shape._cache["units"] = _part_tables(shape)
    return found


def scene_tables(shapes: Sequence[Shape], fixed: Sequence[bool]) -> FeatureTables:
    """The features of every unit of every body, stacked (``fixed``: one flag per shape)."""
    each, owner = [], []
    for b, s in enumerate(shapes):
        for u in units(s):
            each.append(u)
            owner.append(b)
    counts = np.array([[len(t) for t in f.tables] for f in each], dtype=np.int64).reshape(-1, 5)
    start = np.zeros((len(each) + 1, 5), dtype=np.int64)
    start[1:] = np.cumsum(counts, axis=0)
    start += np.concatenate([[0], np.cumsum(counts.sum(axis=0))[:-1]])  # kind blocks in turn
    rows = [f.tables[kind] for kind in range(5) for f in each]
    stacked = np.ascontiguousarray(np.concatenate(rows or [np.zeros((0, WIDTH))]))
    flags = [bool(x) for x in fixed]
    body = np.array(
        [
            (f.closed, f.half_width, f.bounding_radius, flags[b])
            for f, b in zip(each, owner, strict=True)
        ],
        dtype=float,
    ).reshape(-1, 4)
    owners = np.array(owner, dtype=np.int64)
    first = np.searchsorted(owners, np.arange(len(shapes) + 1))
    return FeatureTables(stacked, start, body, owners, np.ascontiguousarray(start[first]))


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
        if math.dist(e_in.last, e_out.first) > JOIN_EPS * shape.bounding_radius:
            continue  # the end of one loop (a ring's outer circle), not a join
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
    joins = _reflex_joins(shape)
    for j, e in enumerate(edges):
        if isinstance(e, Segment):
            (ax, ay), (nx, ny) = e.start, e.normal
            segments.append((ax, ay, nx, ny, -ny, nx, e.length, j, *joins.get(j, (0.0, 0.0))))
        elif isinstance(e, Arc):
            arcs.append((*e.centre, e.radius, e.start_angle, e.span, j))
        else:
            ellipses.append((*e.centre, e.a, e.b, e.angle, j))
    rows = (corners, ends, segments, arcs, ellipses)
    tables = tuple(_table(r) for r in rows)
    half = half_width(shape) if shape.closed else math.inf
    return ShapeFeatures(tables, shape.closed, half, shape.bounding_radius)


def _reflex_joins(shape: Shape) -> dict[int, tuple[float, float]]:
    """{edge index: (free angle at its start, at its end)} of the shape's straight edges that
    meet another straight edge at a reflex join in an open chain (runtime.collide.junctions)."""
    from runtime.collide.junctions import free_angle  # (it reads this module's columns)

    edges, out = shape.edges, {}
    if shape.closed:  # (a closed unit is convex)
        return out
    for i in range(len(edges) - 1):
        k = i + 1
        e_in, e_out = edges[i], edges[k]
        if not (isinstance(e_in, Segment) and isinstance(e_out, Segment)):
            continue
        if math.dist(e_in.end, e_out.start) > JOIN_EPS * shape.bounding_radius:
            continue
        (ax, ay), (bx, by) = e_in.normal, e_out.normal  # (tangents: the normals turned left)
        angle = free_angle((ay, -ax), (ax, ay), (-by, bx), (bx, by))
        if angle > 0.0:
            out[i] = (out.get(i, (0.0, 0.0))[0], angle)
            out[k] = (angle, out.get(k, (0.0, 0.0))[1])
    return out


def half_width(shape: Shape) -> float:
    """Half the smallest width of the shape: min over directions u of (h(u) + h(-u)) / 2 with
    h the exact support function of its edges (a disc's is its radius); for a shape with a
    concave arc (a cup), at most half the material's thickness behind that arc."""
    a = np.linspace(0.0, math.pi, WIDTH_DIRECTIONS, endpoint=False)
    u = np.stack([np.cos(a), np.sin(a)], axis=1)
    reach = np.full((2, len(a)), -math.inf)
    for k, v in enumerate((u, -u)):
        for e in shape.edges:
            reach[k] = np.maximum(reach[k], edge_support(e, v))
    half = 0.5 * float(np.min(reach.sum(axis=0)))
    for e in shape.edges:
        if isinstance(e, Arc) and not e.convex:
            half = min(half, 0.5 * _thickness_behind(shape, e))
    return half


def _thickness_behind(shape: Shape, arc: Arc) -> float:
    """The material's thickness behind a concave arc: the shortest ray from a point of the arc
    (THICKNESS_RAYS, inside its span), away from its centre, to another edge."""
    best = math.inf
    for k in range(THICKNESS_RAYS):
        angle = arc.start_angle + arc.span * (k + 0.5) / THICKNESS_RAYS
        p, d = np.array(arc.point(angle)), np.array([math.cos(angle), math.sin(angle)])
        for e in shape.edges:
            if e is not arc:
                best = min(best, _ray_hit(p, d, e))
    return best


def _ray_hit(p: np.ndarray, d: np.ndarray, e) -> float:
    """Distance along the unit ray p + s d (s > 0) to the edge (a segment or an arc), inf if
    it misses."""
    if isinstance(e, Segment):
        a, b = np.asarray(e.start), np.asarray(e.end)
        m = np.column_stack([d, a - b])
        if abs(np.linalg.det(m)) < 1e-300:
            return math.inf
        s, t = np.linalg.solve(m, a - p)
        return float(s) if s > 0 and 0.0 <= t <= 1.0 else math.inf
    if not isinstance(e, Arc):
        return math.inf
    w = p - np.asarray(e.centre)
    half_b, c = float(w @ d), float(w @ w) - e.radius**2
    disc = half_b * half_b - c
    if disc < 0:
        return math.inf
    for s in sorted((-half_b - math.sqrt(disc), -half_b + math.sqrt(disc))):
        hit = w + s * d
        if s > 0 and e.contains_angle(math.atan2(hit[1], hit[0])):
            return s
    return math.inf


# -- compound bodies -------------------------------------------------------------------------


def _part_tables(shape: Shape) -> tuple[ShapeFeatures, ...]:
    """Each part's tables with the compound's feature indices (vertex and edge offsets of the
    parts before it) and its corners on other parts hidden or narrowed."""
    near = JOIN_EPS * shape.bounding_radius
    found, vertex0, edge0 = [], 0, 0
    for k, part in enumerate(shape.parts):
        own = features(part)
        corners, ends, segments, arcs, ellipses = (t.copy() for t in own.tables)
        keep = []
        for row in corners:
            cone = (
                math.atan2(row[C_NY], row[C_NX]),
                row[C_WIDTH],
                row[C_ARC_BEFORE],
                row[C_ARC_AFTER],
            )
            for m, other in enumerate(shape.parts):
                if m != k and cone is not None:
                    cone = _narrowed(cone, _cone_of(other, (row[X], row[Y]), near))
            if cone is not None:
                start, width, before, after = cone
                row[C_NX], row[C_NY], row[C_WIDTH] = math.cos(start), math.sin(start), width
                row[C_ARC_BEFORE], row[C_ARC_AFTER] = before, after
                keep.append(row)
        corners = np.array(keep).reshape(-1, WIDTH)
        corners[:, C_INDEX] += vertex0
        ends[:, E_INDEX] += edge0
        segments[:, S_INDEX] += edge0
        arcs[:, A_INDEX] += edge0
        ellipses[:, L_INDEX] += edge0
        tables = (corners, ends, segments, arcs, ellipses)
        found.append(ShapeFeatures(tables, True, own.half_width, own.bounding_radius))
        vertex0, edge0 = vertex0 + len(part.vertices), edge0 + len(part.edges)
    return tuple(found)


def _cone_of(part: Shape, point: tuple[float, float], near: float):
    """The directions in which ``point`` is extreme for the part (start angle, width, arc
    before, arc after): "all" if the point is outside it, None if inside, a corner's cone
    or an edge's normal (width 0) on its boundary."""
    p = np.array([point])
    distance = [float(edge_distance(e, p)[0]) for e in part.edges]
    if min(distance) > near:
        return None if winding(part, p)[0] != 0 else "all"
    for row in features(part).tables[CORNERS]:
        if math.hypot(row[X] - point[0], row[Y] - point[1]) <= near:
            return (
                math.atan2(row[C_NY], row[C_NX]),
                row[C_WIDTH],
                row[C_ARC_BEFORE],
                row[C_ARC_AFTER],
            )
    e = part.edges[int(np.argmin(distance))]
    if isinstance(e, Segment):
        n, curved = e.normal, 0.0
    elif isinstance(e, Arc):
        n, curved = e.normal_at(math.atan2(point[1] - e.centre[1], point[0] - e.centre[0])), 1.0
    else:
        c, s = math.cos(e.angle), math.sin(e.angle)
        local = np.array(
            [
                [
                    c * (point[0] - e.centre[0]) + s * (point[1] - e.centre[1]),
                    c * (point[1] - e.centre[1]) - s * (point[0] - e.centre[0]),
                ]
            ]
        )
        (qx, qy), curved = nearest_on_ellipse(e.a, e.b, local)[0], 1.0
        gx, gy = qx / e.a**2, qy / e.b**2
        n = (c * gx - s * gy, s * gx + c * gy)
    return (math.atan2(n[1], n[0]), 0.0, curved, curved)


def _narrowed(cone, other):
    """The intersection of a corner's cone (start angle, width, arc flags of its sides) with
    ``other`` ("all", None: empty, or a cone); None if nothing of width > TURN_EPS is left."""
    if other is None or other == "all":
        return cone if other == "all" else None
    a1, w1, before1, after1 = cone
    a2, w2, before2, after2 = other
    shift = (a2 - a1) % TAU
    best = None
    for b in (shift, shift - TAU):
        lo, hi = max(0.0, b), min(w1, b + w2)
        if hi - lo > TURN_EPS and (best is None or hi - lo > best[1] - best[0]):
            best = (lo, hi, before1 if lo == 0.0 else before2, after1 if hi == w1 else after2)
    if best is None:
        return None
    lo, hi, before, after = best
    return (a1 + lo, hi - lo, before, after)
