"""The named shapes a scene file can ask for: polygon, disc, rounded_rect, half_disc, d_shape,
ellipse, walls, bowls and boxes, and bodies of several convex parts (compound, frame).

Each constructor builds a :class:`runtime.model.shapes.Shape` in the shape's own coordinates
(docs/scene-format.md) and refuses bad parameters with a ValueError naming the parameter first
(``"polygon: points must be ..."``), which runtime.io turns into ``field 'shape.points'``.
They are re-exported by runtime.model.shapes, so ``shapes.disc(0.1)`` keeps working.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

from runtime.model.shapes import (
    _JOIN,
    TAU,
    Arc,
    Edge,
    Ellipse,
    Point,
    Segment,
    Shape,
    _number,
    _point,
    shape_from_edges,
)
from runtime.settings import MAX_AXIS_RATIO

__all__ = [
    "box_walls",
    "bowl",
    "compound",
    "d_shape",
    "disc",
    "ellipse",
    "frame",
    "half_disc",
    "polygon",
    "rounded_rect",
    "segment_chain",
    "wall",
]


def _chain(points: list[Point], closed: bool) -> list[Segment]:
    m = len(points)
    return [Segment(points[i], points[(i + 1) % m]) for i in range(m if closed else m - 1)]


def polygon(points: Sequence[Sequence[float]]) -> Shape:
    """Convex polygon from its corners (counter-clockwise or clockwise; normalised to
    counter-clockwise).  Rejects repeated, collinear and reflex corners and self-intersection,
    naming the offending vertex (index into ``points``)."""
    try:
        pts = [_point(f"points[{i}]", p, "polygon: ") for i, p in enumerate(points)]
    except TypeError:
        raise ValueError(f"polygon: points must be a sequence of (x, y), got {points!r}") from None
    m = len(pts)
    if m < 3:
        raise ValueError(f"polygon: points needs at least 3 vertices, got {m}")
    # The tests run in coordinates relative to the first corner: a unit square placed at 1e12 m
    # has products of coordinates near 1e24, whose rounding (1e8) would swamp its area (1).
    x0, y0 = pts[0]
    rel = [(x - x0, y - y0) for x, y in pts]
    index = list(range(m))
    twice_area = math.fsum(rel[i - 1][0] * rel[i][1] - rel[i][0] * rel[i - 1][1] for i in range(m))
    if twice_area < 0:  # reverse, keeping the first point first
        pts, rel, index = pts[:1] + pts[:0:-1], rel[:1] + rel[:0:-1], index[:1] + index[:0:-1]
    scale = max(math.hypot(x, y) for x, y in rel)
    for i in range(m):
        if math.hypot(rel[i][0] - rel[i - 1][0], rel[i][1] - rel[i - 1][1]) <= _JOIN * scale:
            raise ValueError(f"polygon: points repeat at vertex {index[i]} {pts[i]}")
    turning = 0.0
    for i in range(m):
        (ax, ay), (bx, by), (cx, cy) = rel[i - 1], rel[i], rel[(i + 1) % m]
        where = f"vertex {index[i]} {pts[i]}"
        cross = (bx - ax) * (cy - by) - (by - ay) * (cx - bx)
        if cross <= _JOIN * scale * scale:
            kind = "collinear" if abs(cross) <= _JOIN * scale * scale else "reflex (not convex)"
            raise ValueError(f"polygon: points must be strictly convex; {where} is {kind}")
        turning += math.atan2(cross, (bx - ax) * (cx - bx) + (by - ay) * (cy - by))
        if turning > TAU * (1 + 1e-9):
            raise ValueError(f"polygon: points are self-intersecting (winding again at {where})")
    return shape_from_edges(_chain(pts, True))


def disc(radius: float) -> Shape:
    """Disc centred at the origin: one full convex arc, no vertices."""
    r = _number("radius", radius, positive=True, where="disc: ")
    return Shape((Arc((0.0, 0.0), r, 0.0, TAU),))


def rounded_rect(width: float, height: float, corner_radius: float) -> Shape:
    """Rectangle centred at the origin with quarter-circle corners (no vertices);
    ``corner_radius = 0`` gives the plain rectangle (4 vertices)."""
    w = _number("width", width, positive=True, where="rounded_rect: ")
    h = _number("height", height, positive=True, where="rounded_rect: ")
    r = _number("corner_radius", corner_radius, where="rounded_rect: ")
    if not 0 <= r <= min(w, h) / 2:
        raise ValueError(
            f"rounded_rect: corner_radius must be in [0, min(width, height)/2 = {min(w, h) / 2!r}]"
            f", got {r!r}"
        )
    hx, hy = w / 2, h / 2
    if r == 0:
        return polygon([(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)])
    ax, ay, q = hx - r, hy - r, math.pi / 2
    edges: list[Edge] = []
    for k, ((sx, sy), (ex, ey)) in enumerate(
        [
            ((-ax, -hy), (ax, -hy)),
            ((hx, -ay), (hx, ay)),
            ((ax, hy), (-ax, hy)),
            ((-hx, ay), (-hx, -ay)),
        ]
    ):
        if (sx, sy) != (ex, ey):
            edges.append(Segment((sx, sy), (ex, ey)))
        centre = ((ax, -ay), (ax, ay), (-ax, ay), (-ax, -ay))[k]
        edges.append(Arc(centre, r, (k - 1) * q, k * q))
    return shape_from_edges(edges)


def half_disc(radius: float) -> Shape:
    """Upper half disc; the arc's centre is the origin, the flat side lies on y = 0; two
    vertices at (+-radius, 0).  (Centroid at (0, 4 radius / (3 pi)).)"""
    r = _number("radius", radius, positive=True, where="half_disc: ")
    return shape_from_edges([Segment((-r, 0.0), (r, 0.0)), Arc((0.0, 0.0), r, 0.0, math.pi)])


def d_shape(width: float, height: float) -> Shape:
    """A "D": flat back on x = -(width - height/2) with straight top and bottom running into a
    semicircular front of radius height/2 centred at the origin.  Vertices: the two back corners
    (the straight sides join the arc tangentially).  ``width = height/2`` is a half disc."""
    w = _number("width", width, positive=True, where="d_shape: ")
    h = _number("height", height, positive=True, where="d_shape: ")
    r = h / 2
    if w < r:
        raise ValueError(f"d_shape: width must be >= {r!r} (the front's radius), got {w!r}")
    back = -(w - r)
    edges: list[Edge] = [Arc((0.0, 0.0), r, -math.pi / 2, math.pi / 2)]
    if back < 0:
        edges.append(Segment((0.0, r), (back, r)))
    edges.append(Segment((back, r), (back, -r)))
    if back < 0:
        edges.append(Segment((back, -r), (0.0, -r)))
    return shape_from_edges(edges)


def ellipse(a: float, b: float) -> Shape:
    """Ellipse centred at the origin with semi-axes ``a`` (along x) and ``b`` (along y), at most
    MAX_AXIS_RATIO (runtime/settings.py) times longer than wide."""
    a = _number("a", a, positive=True, where="ellipse: ")
    b = _number("b", b, positive=True, where="ellipse: ")
    (long, big), (short, small) = sorted((("a", a), ("b", b)), key=lambda p: -p[1])
    if big > MAX_AXIS_RATIO * small:
        raise ValueError(
            f"ellipse: {long} / {short} must be at most {MAX_AXIS_RATIO:g}, got {big / small:.3g}: "
            f"the radius of curvature at the ends, {short}^2/{long} = {small * small / big:.3g} m, "
            f"would be lost in the rounding of positions there (~{2.2e-16 * big:.2g} m)"
        )
    return Shape((Ellipse((0.0, 0.0), a, b),))


def segment_chain(
    points: Sequence[Sequence[float]], *, closed: bool = False, end_vertices: bool = False
) -> Shape:
    """Straight-edged chain through ``points`` with the material on the RIGHT when walking
    from the first point to the last (a floor drawn left to right has material below)."""
    pts = [_point(f"points[{i}]", p, "segment_chain: ") for i, p in enumerate(points)]
    if len(pts) < 2:
        raise ValueError(f"segment_chain: points needs at least 2 points, got {len(pts)}")
    for i in range(1, len(pts)):
        if pts[i] == pts[i - 1]:
            raise ValueError(f"segment_chain: points[{i}] repeats points[{i - 1}] = {pts[i]}")
    pts.reverse()
    return shape_from_edges(_chain(pts, closed), closed=closed, end_vertices=end_vertices)


def wall(start: Sequence[float], end: Sequence[float], *, end_vertices: bool = False) -> Shape:
    """Fixed straight wall, material on the right of ``start -> end`` (a half-plane locally).
    Its ends are vertices only with ``end_vertices`` (then bodies can tip over them)."""
    s, e = _point("start", start, "wall: "), _point("end", end, "wall: ")
    if s == e:
        raise ValueError(f"wall: start and end must differ, both are {s}")
    return segment_chain([s, e], end_vertices=end_vertices)


def bowl(
    radius: float,
    start_angle: float,
    end_angle: float,
    *,
    end_vertices: bool = False,
    thickness: float | None = None,
) -> Shape:
    """Concave arc (radius stored negative) centred at the origin covering the angles
    ``start_angle -> end_angle`` counter-clockwise; bodies rest inside.

    Without ``thickness``: one open arc for a fixed body; a full turn is a closed circular
    container; otherwise the rim points are vertices only with ``end_vertices``.  With
    ``thickness``: a cup that can move, the ring sector between ``radius`` (the concave inner
    surface) and ``radius + thickness`` (a convex outer one) with flat rims and four rim
    corners, or a ring for a full turn.  Its span is at most pi or a full turn: a deeper cup's
    rims face inwards, over material of the cup itself, which the contact finder's test of a
    penetrating corner (the distance to each edge's line) cannot tell from outside."""
    r = _number("radius", radius, positive=True, where="bowl: ")
    a0 = _number("start_angle", start_angle, where="bowl: ")
    a1 = _number("end_angle", end_angle, where="bowl: ")
    if not 0 < a1 - a0 <= TAU * (1 + 1e-12):
        raise ValueError(
            f"bowl: end_angle must exceed the start angle {a0!r} by at most 2 pi, got {a1!r}"
        )
    arc = Arc((0.0, 0.0), -r, a0, a1)
    if thickness is None:
        if arc.full:
            return Shape((arc,), (), closed=False)
        return shape_from_edges([arc], closed=False, end_vertices=end_vertices)
    t = _number("thickness", thickness, positive=True, where="bowl: ")
    if end_vertices:
        raise ValueError(
            "bowl: end_vertices is for a bowl without thickness (a cup's rim "
            "corners are always corners)"
        )
    outer = Arc((0.0, 0.0), r + t, a0, a1)
    if arc.full:
        return Shape((outer, arc))
    if arc.span > math.pi * (1 + 1e-12):
        raise ValueError(
            f"bowl: end_angle - start_angle must be at most pi (or a full turn) for a bowl "
            f"with thickness, got {arc.span!r}: a deeper cup's rims face over its own material"
        )
    rim_end, rim_start = Segment(outer.last, arc.first), Segment(arc.last, outer.first)
    return shape_from_edges([outer, rim_end, arc, rim_start])


def box_walls(
    width: float, height: float, *, end_vertices: bool = False, thickness: float | None = None
) -> Shape:
    """Open-top container: floor on y = 0 from x = -width/2 to width/2 and two side walls up to
    y = height, facing inwards.  Without ``thickness``: three segments, an open chain for a
    fixed body.  With ``thickness``: three bars of that thickness outside those faces (the
    floor bar under the side bars), a compound that can move."""
    w = _number("width", width, positive=True, where="box_walls: ")
    h = _number("height", height, positive=True, where="box_walls: ")
    if thickness is None:
        pts = [(-w / 2, h), (-w / 2, 0.0), (w / 2, 0.0), (w / 2, h)]
        return segment_chain(pts, end_vertices=end_vertices)
    t = _number("thickness", thickness, positive=True, where="box_walls: ")
    if end_vertices:
        raise ValueError(
            "box_walls: end_vertices is for walls without thickness (the bars' "
            "corners are always corners)"
        )
    x, y = w / 2, h
    return compound(
        [_box(-x - t, -t, x + t, 0.0), _box(-x - t, 0.0, -x, y), _box(x, 0.0, x + t, y)]
    )


def frame(width: float, height: float, thickness: float) -> Shape:
    """Hollow rectangle: an inner opening ``width`` x ``height`` centred at the origin inside
    bars of ``thickness`` (a compound of four bars: bottom and top the full outer width)."""
    w = _number("width", width, positive=True, where="frame: ")
    h = _number("height", height, positive=True, where="frame: ")
    t = _number("thickness", thickness, positive=True, where="frame: ")
    x, y = w / 2, h / 2
    return compound(
        [
            _box(-x - t, -y - t, x + t, -y),
            _box(x, -y, x + t, y),
            _box(-x - t, y, x + t, y + t),
            _box(-x - t, -y, -x, y),
        ]
    )


def _box(x0: float, y0: float, x1: float, y1: float) -> Shape:
    return polygon([(x0, y0), (x1, y0), (x1, y1), (x0, y1)])


def compound(parts: Sequence[Shape]) -> Shape:
    """One rigid body of several closed convex parts, all in the same (the body's own)
    coordinates.  Parts may touch but not overlap, so the mass properties are exactly the
    union's (the sum of the parts'); they need not touch (pieces held by massless links).
    A part's corner that lies on another part's boundary is hidden (a flat or reflex point of
    the union: runtime/collide/features.py)."""
    from runtime.model.regions import is_convex, overlap_depth  # regions imports this module

    try:
        parts = tuple(parts)
    except TypeError:
        raise ValueError(f"compound: parts must be a sequence of shapes, got {parts!r}") from None
    if not parts:
        raise ValueError("compound: parts needs at least 1 part, got 0")
    for k, p in enumerate(parts):
        if not isinstance(p, Shape):
            raise ValueError(f"compound: parts[{k}] must be a Shape, got {type(p).__name__}")
        if p.parts:
            raise ValueError(f"compound: parts[{k}] is itself a compound; list its parts instead")
        if not p.closed:
            raise ValueError(f"compound: parts[{k}] is an open chain without area; parts need area")
        if not is_convex(p):
            raise ValueError(f"compound: parts[{k}] is not convex; split it into convex parts")
    scale = max(p.bounding_radius for p in parts)
    for i in range(len(parts)):
        for j in range(i + 1, len(parts)):
            a, b = parts[i], parts[j]
            reach = _reach(a) + _reach(b) - math.dist(a.centroid, b.centroid)
            depth = overlap_depth(a, b) if reach > 0 else reach
            if depth > _JOIN * scale:
                raise ValueError(
                    f"compound: parts[{i}] and parts[{j}] overlap by {depth:.6g} m; parts may "
                    "touch but not overlap (the overlap's mass would count twice)"
                )
    edges = tuple(e for p in parts for e in p.edges)
    vertices = tuple(v for p in parts for v in p.vertices)
    return Shape(edges, vertices, True, parts)


def _reach(part: Shape) -> float:
    """Radius of a circle about the part's centroid that holds it."""
    cx, cy = part.centroid
    return part.translated(-cx, -cy).bounding_radius
