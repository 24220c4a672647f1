"""Shapes of 2-D rigid bodies: straight and circular edges, ellipses, exact mass properties.

Why this module exists: the contact kernels (docs/conventions.md) need each body's features in
body coordinates -- vertices ``p``, straight edges ``(e, n)``, circular edges ``(c, r)`` with
the signed-radius convention (concave = negative) -- and the engine needs the area, centroid
and second moment of the region they bound, exactly, also for boundaries that mix segments and
circular arcs.  The named shapes (``disc``, ``polygon``, ``wall``, ...) are built in
runtime/model/shape_library.py and reachable from here.

Orientation: a boundary is traversed with the body's material on the LEFT (counter-clockwise
for a closed shape), so a segment's outward normal is the right-hand normal of ``end - start``.

Arc spans: an :class:`Arc` covers the angles ``start_angle -> end_angle`` swept
COUNTER-CLOCKWISE about its centre (``0 < end_angle - start_angle <= 2 pi``) whatever the sign
of its radius.  A convex arc (``radius > 0``, material inside the circle) is traversed in that
direction; a concave arc (``radius < 0``, material outside, a bowl) is traversed the other way,
from ``end_angle`` back to ``start_angle``.

Mass properties (Green's theorem, per unit density, about a reference point ``o``)::

    A = 1/2 loop (x dy - y dx),   A Cx = loop x^2/2 dy,   A Cy = -loop y^2/2 dx,
    J_o = loop (x^3 dy - y^3 dx) / 3.

A segment gives the polygon terms; an arc ``x = h + R cos t, y = k + R sin t`` gives closed
forms in ``sin, cos`` of its end angles (``_arc_terms``), signed by the traversal direction.
The polar second moment about the centroid is ``J_o - A |C - o|^2``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field

Point = tuple[float, float]
TAU = 2.0 * math.pi
_JOIN = 1e-9  # relative tolerance for edges meeting and for tangent continuity


def _number(name: str, value: object, *, positive: bool = False, where: str = "") -> float:
    try:
        x = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{where}{name} must be a number, got {value!r}") from None
    if not math.isfinite(x):
        raise ValueError(f"{where}{name} must be finite, got {value!r}")
    if positive and not x > 0:
        raise ValueError(f"{where}{name} must be > 0, got {x!r}")
    return x


def _point(name: str, value: object, where: str = "") -> Point:
    try:
        x, y = value  # type: ignore[misc]
    except (TypeError, ValueError):
        raise ValueError(f"{where}{name} must be a pair (x, y), got {value!r}") from None
    return (_number(f"{name}[0]", x, where=where), _number(f"{name}[1]", y, where=where))


def _set(obj: object, **values: object) -> None:
    """Set validated fields of a frozen dataclass in __post_init__."""
    for name, value in values.items():
        object.__setattr__(obj, name, value)


@dataclass(frozen=True)
class Segment:
    """Straight edge from ``start`` to ``end``; material on the left, outward normal right."""

    start: Point
    end: Point

    def __post_init__(self) -> None:
        _set(
            self,
            start=_point("start", self.start, "Segment: "),
            end=_point("end", self.end, "Segment: "),
        )
        if self.start == self.end:
            raise ValueError(f"Segment: start and end coincide at {self.start}")

    @property
    def length(self) -> float:
        return math.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1])

    @property
    def normal(self) -> Point:
        dx, dy = self.end[0] - self.start[0], self.end[1] - self.start[1]
        length = math.hypot(dx, dy)
        return (dy / length, -dx / length)

    # the path interface of every edge: traversal end points and the outward normals there
    first = property(lambda self: self.start)
    last = property(lambda self: self.end)

    def normal_first(self) -> Point:
        return self.normal

    normal_last = normal_first

    def translated(self, dx: float, dy: float) -> Segment:
        (x0, y0), (x1, y1) = self.start, self.end
        return Segment((x0 + dx, y0 + dy), (x1 + dx, y1 + dy))


@dataclass(frozen=True)
class Arc:
    """Circular edge ``centre + |radius| (cos a, sin a)``, ``a`` from ``start_angle`` to
    ``end_angle`` counter-clockwise.  ``radius > 0``: convex, traversed start -> end;
    ``radius < 0``: concave (material outside the circle), traversed end -> start."""

    centre: Point
    radius: float
    start_angle: float
    end_angle: float

    def __post_init__(self) -> None:
        r = _number("radius", self.radius, where="Arc: ")
        if r == 0.0:
            raise ValueError("Arc: radius must be non-zero (negative = concave), got 0.0")
        a0 = _number("start_angle", self.start_angle, where="Arc: ")
        a1 = _number("end_angle", self.end_angle, where="Arc: ")
        if not 0.0 < a1 - a0 <= TAU * (1 + 1e-12):
            raise ValueError(f"Arc: end_angle - start_angle must be in (0, 2 pi], got {a1 - a0!r}")
        centre = _point("centre", self.centre, "Arc: ")
        _set(self, centre=centre, radius=r, start_angle=a0, end_angle=min(a1, a0 + TAU))

    @property
    def convex(self) -> bool:
        return self.radius > 0

    @property
    def span(self) -> float:
        """Angular width, counter-clockwise from ``start_angle``."""
        return self.end_angle - self.start_angle

    @property
    def full(self) -> bool:
        return self.span >= TAU

    def contains_angle(self, angle: float, slack: float = 0.0) -> bool:
        """Whether the direction ``angle`` (seen from the centre) lies in the span, widened by
        ``slack`` radians at both ends."""
        d = (angle - self.start_angle) % TAU
        return d <= self.span + slack or d >= TAU - slack

    def point(self, angle: float) -> Point:
        r = abs(self.radius)
        return (self.centre[0] + r * math.cos(angle), self.centre[1] + r * math.sin(angle))

    def normal_at(self, angle: float) -> Point:
        """Outward normal of the body at the arc point ``angle``."""
        s = 1.0 if self.radius > 0 else -1.0
        return (s * math.cos(angle), s * math.sin(angle))

    @property
    def end_points(self) -> tuple[Point, Point]:
        """``(point(start_angle), point(end_angle))``: the span's ends, not traversal order."""
        return self.point(self.start_angle), self.point(self.end_angle)

    def _ends(self) -> tuple[float, float]:  # angles of the first and last point traversed
        a0, a1 = self.start_angle, self.end_angle
        return (a0, a1) if self.radius > 0 else (a1, a0)

    first = property(lambda self: self.point(self._ends()[0]))
    last = property(lambda self: self.point(self._ends()[1]))

    def normal_first(self) -> Point:
        return self.normal_at(self._ends()[0])

    def normal_last(self) -> Point:
        return self.normal_at(self._ends()[1])

    def translated(self, dx: float, dy: float) -> Arc:
        c = (self.centre[0] + dx, self.centre[1] + dy)
        return Arc(c, self.radius, self.start_angle, self.end_angle)


@dataclass(frozen=True)
class Ellipse:
    """A whole convex elliptic boundary ``centre + R(angle) (a cos t, b sin t)``.

    Contacts against it use the circular kernels with the osculating circle at the contact
    point (:meth:`osculating`), as docs/conventions.md prescribes for oval edges."""

    centre: Point
    a: float
    b: float
    angle: float = 0.0

    def __post_init__(self) -> None:
        w = "Ellipse: "
        _set(self, centre=_point("centre", self.centre, w), a=_number("a", self.a, positive=True, where=w),
             b=_number("b", self.b, positive=True, where=w), angle=_number("angle", self.angle, where=w))  # fmt: skip

    def point(self, t: float) -> Point:
        c, s = math.cos(self.angle), math.sin(self.angle)
        x, y = self.a * math.cos(t), self.b * math.sin(t)
        return (self.centre[0] + c * x - s * y, self.centre[1] + s * x + c * y)

    def osculating(self, t: float) -> tuple[Point, float]:
        """Centre (body coordinates) and radius of the osculating circle at parameter ``t``."""
        a, b, ct, st = self.a, self.b, math.cos(t), math.sin(t)
        x, y = (a * a - b * b) / a * ct**3, (b * b - a * a) / b * st**3
        rho = (a * a * st * st + b * b * ct * ct) ** 1.5 / (a * b)
        c, s = math.cos(self.angle), math.sin(self.angle)
        return (self.centre[0] + c * x - s * y, self.centre[1] + s * x + c * y), rho

    first = last = property(lambda self: self.point(0.0))

    def translated(self, dx: float, dy: float) -> Ellipse:
        return Ellipse((self.centre[0] + dx, self.centre[1] + dy), self.a, self.b, self.angle)


Edge = Segment | Arc | Ellipse


def _arc_terms(arc: Arc, ox: float, oy: float) -> tuple[float, float, float, float]:
    """Green's-theorem integrals (A, A Cx, A Cy, J) of an arc about the point ``o``."""
    h, k, R = arc.centre[0] - ox, arc.centre[1] - oy, abs(arc.radius)
    a0, a1 = arc.start_angle, arc.end_angle

    def dif(f):  # f(a1) - f(a0)
        return f(a1) - f(a0)

    s1 = dif(math.sin)  # int cos
    c1 = -dif(math.cos)  # int sin
    c2 = dif(lambda t: t / 2 + math.sin(2 * t) / 4)  # int cos^2
    s2 = dif(lambda t: t / 2 - math.sin(2 * t) / 4)  # int sin^2
    c3 = dif(lambda t: math.sin(t) - math.sin(t) ** 3 / 3)  # int cos^3
    s3 = dif(lambda t: -math.cos(t) + math.cos(t) ** 3 / 3)  # int sin^3
    c4 = dif(lambda t: 3 * t / 8 + math.sin(2 * t) / 4 + math.sin(4 * t) / 32)  # int cos^4
    s4 = dif(lambda t: 3 * t / 8 - math.sin(2 * t) / 4 + math.sin(4 * t) / 32)  # int sin^4
    area = 0.5 * (R * R * (a1 - a0) + h * R * s1 + k * R * c1)
    mx = 0.5 * R * (h * h * s1 + 2 * h * R * c2 + R * R * c3)
    my = 0.5 * R * (k * k * c1 + 2 * k * R * s2 + R * R * s3)
    jj = (R / 3) * (
        h**3 * s1 + 3 * h * h * R * c2 + 3 * h * R * R * c3 + R**3 * c4
        + k**3 * c1 + 3 * k * k * R * s2 + 3 * k * R * R * s3 + R**3 * s4
    )  # fmt: skip
    sign = 1.0 if arc.convex else -1.0
    return sign * area, sign * mx, sign * my, sign * jj


def _edge_terms(edge: Edge, ox: float, oy: float) -> tuple[float, float, float, float]:
    if isinstance(edge, Segment):
        x0, y0 = edge.start[0] - ox, edge.start[1] - oy
        x1, y1 = edge.end[0] - ox, edge.end[1] - oy
        dx, dy = x1 - x0, y1 - y0
        area = 0.5 * (x0 * y1 - x1 * y0)
        mx = dy * (x0 * x0 + x0 * x1 + x1 * x1) / 6
        my = -dx * (y0 * y0 + y0 * y1 + y1 * y1) / 6
        jj = (dy * (x0 + x1) * (x0 * x0 + x1 * x1) - dx * (y0 + y1) * (y0 * y0 + y1 * y1)) / 12
        return area, mx, my, jj
    if isinstance(edge, Arc):
        return _arc_terms(edge, ox, oy)
    h, k, area = edge.centre[0] - ox, edge.centre[1] - oy, math.pi * edge.a * edge.b
    jj = area * ((edge.a**2 + edge.b**2) / 4 + h * h + k * k)
    return area, area * h, area * k, jj


@dataclass(frozen=True)
class Shape:
    """A body's boundary in body coordinates.

    ``edges``: the boundary, material on the left (closed: counter-clockwise; ``closed=False``
    for an open chain such as a wall or a bowl, which bounds no area).  ``vertices``: the
    corner points, the points that take part in contacts as "vertex" features (besides them,
    the end of a convex arc where it runs smoothly into a straight side acts as a vertex
    against straight edges: runtime/collide/features.py).  Mass properties (per unit density) are
    those of the region a closed boundary encloses; an open chain has area, centroid and
    second moment zero.  A closed boundary may be several loops (a ring: two full arcs).

    ``parts``: a compound body (runtime.model.shape_library.compound): closed convex parts
    that do not overlap; ``edges`` and ``vertices`` are then the parts' in order, so a
    feature index names one part's feature, and the mass properties are the union's: the
    sums of the parts' (parallel-axis theorem for the moment).  ``_cache`` holds derived tables (the narrow phase's
    features)."""

    edges: tuple[Edge, ...]
    vertices: tuple[Point, ...] = ()
    closed: bool = True
    parts: tuple[Shape, ...] = ()
    area: float = field(init=False)
    centroid: Point = field(init=False)
    second_moment: float = field(init=False)
    bounding_radius: float = field(init=False)
    _cache: dict = field(init=False, repr=False, compare=False, default_factory=dict)

    def __post_init__(self) -> None:
        edges = tuple(self.edges)
        if not edges or not all(isinstance(e, Segment | Arc | Ellipse) for e in edges):
            raise ValueError(f"Shape: edges must be a non-empty sequence of edges, got {edges!r}")
        object.__setattr__(self, "edges", edges)
        verts = tuple(_point(f"vertices[{i}]", v, "Shape: ") for i, v in enumerate(self.vertices))
        object.__setattr__(self, "vertices", verts)
        parts = tuple(self.parts)
        if parts:
            if not all(isinstance(p, Shape) and p.closed and not p.parts for p in parts):
                raise ValueError("Shape: parts must be closed shapes without parts of their own")
            if not (
                self.closed
                and edges == tuple(e for p in parts for e in p.edges)
                and verts == tuple(v for p in parts for v in p.vertices)
            ):
                raise ValueError("Shape: a compound's edges and vertices are its parts', in order")
            object.__setattr__(self, "parts", parts)
        area, cx, cy, jc = 0.0, 0.0, 0.0, 0.0
        if parts:  # the parts' own (well conditioned for thin parts far from edges[0])
            area = math.fsum(p.area for p in parts)
            cx = math.fsum(p.area * p.centroid[0] for p in parts) / area
            cy = math.fsum(p.area * p.centroid[1] for p in parts) / area
            jc = math.fsum(p.second_moment_about((cx, cy)) for p in parts)
        elif self.closed:
            ox, oy = edges[0].first
            terms = [_edge_terms(e, ox, oy) for e in edges]
            area = math.fsum(t[0] for t in terms)
            if not area > 0:
                raise ValueError(
                    f"Shape: a closed boundary must enclose a positive area counter-clockwise, "
                    f"got area {area!r}"
                )
            mx, my = math.fsum(t[1] for t in terms) / area, math.fsum(t[2] for t in terms) / area
            cx, cy = ox + mx, oy + my
            jc = math.fsum(t[3] for t in terms) - area * (mx * mx + my * my)
        radius = max(_farthest(e) for e in edges)
        _set(self, area=area, centroid=(cx, cy), second_moment=jc, bounding_radius=radius)

    def translated(self, dx: float, dy: float) -> Shape:
        edges = tuple(e.translated(dx, dy) for e in self.edges)
        verts = tuple((x + dx, y + dy) for x, y in self.vertices)
        parts = tuple(p.translated(dx, dy) for p in self.parts)
        return Shape(edges, verts, self.closed, parts)

    def centred(self, about: Point | None = None) -> tuple[Shape, Point]:
        """``(shape, offset)``: the shape moved so the point ``about`` (default: its centroid)
        is the origin, and ``offset``, the old coordinates of the new origin.  An open chain
        is returned unchanged with offset ``(0, 0)``."""
        if not self.closed:
            return self, (0.0, 0.0)
        cx, cy = self.centroid if about is None else _point("center_of_mass", about)
        return self.translated(-cx, -cy), (cx, cy)

    def second_moment_about(self, point: Point) -> float:
        """Polar second moment (per unit density) about ``point``: the parallel-axis theorem,
        ``J_c + A |point - c|^2``."""
        dx, dy = point[0] - self.centroid[0], point[1] - self.centroid[1]
        return self.second_moment + self.area * (dx * dx + dy * dy)


def _farthest(edge: Edge) -> float:
    """Largest distance of the edge's points from the origin."""
    if isinstance(edge, Segment):
        return max(math.hypot(*edge.start), math.hypot(*edge.end))
    if isinstance(edge, Ellipse):
        return math.hypot(*edge.centre) + max(edge.a, edge.b)
    cx, cy = edge.centre
    if edge.contains_angle(math.atan2(cy, cx)) or (cx == 0.0 and cy == 0.0):
        return math.hypot(cx, cy) + abs(edge.radius)
    return max(math.hypot(*p) for p in edge.end_points)


def _turn(n_in: Point, n_out: Point) -> float:
    """Signed angle from the normal ``n_in`` to ``n_out`` (> 0: convex corner)."""
    return math.atan2(
        n_in[0] * n_out[1] - n_in[1] * n_out[0], n_in[0] * n_out[0] + n_in[1] * n_out[1]
    )


def shape_from_edges(
    edges: Sequence[Edge], *, closed: bool = True, end_vertices: bool = False
) -> Shape:
    """A shape from edges in traversal order (material on the left); checks that consecutive
    edges meet and finds the vertices: convex corners (the tangent turns left) and, with
    ``end_vertices``, the two ends of an open chain.  Reflex corners are not vertices: no body
    can touch them from outside."""
    edges = tuple(edges)
    if not edges:
        raise ValueError("shape_from_edges: edges must not be empty")
    if any(isinstance(e, Ellipse) for e in edges) and (len(edges) > 1 or not closed):
        raise ValueError("shape_from_edges: an Ellipse must be the only edge of a closed shape")
    scale = max(_farthest(e) for e in edges) or 1.0
    n = len(edges)
    verts: list[Point] = []
    if not closed and end_vertices:
        verts.append(edges[0].first)
    for k in range(0 if closed else 1, n):  # the join at the start of edge k
        i, e_in, e_out = (k - 1) % n, edges[k - 1], edges[k]
        if isinstance(e_in, Ellipse):
            continue
        p, q = e_in.last, e_out.first
        if math.hypot(p[0] - q[0], p[1] - q[1]) > _JOIN * scale:
            raise ValueError(f"shape_from_edges: edge {i} ends at {p} but edge {k} starts at {q}")
        if _turn(e_in.normal_last(), e_out.normal_first()) > _JOIN:
            verts.append(q)
    if not closed and end_vertices:
        verts.append(edges[-1].last)
    return Shape(edges, tuple(verts), closed)


# The named shapes (disc, polygon, wall, ...) live in runtime/model/shape_library.py; they are
# reachable here too (``shapes.disc(0.1)``), loaded on first use to avoid an import cycle.
_LIBRARY = (
    "box_walls", "bowl", "compound", "d_shape", "disc", "ellipse", "frame", "half_disc",
    "polygon", "rounded_rect", "segment_chain", "wall",
)  # fmt: skip


def __getattr__(name: str):
    if name in _LIBRARY:
        from runtime.model import shape_library

        return getattr(shape_library, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
