"""Narrow phase: the contacts between two bodies whose bounding circles overlap.

Why: every contact must be one of the four cases of docs/conventions.md with its kernel
geometry in body coordinates, and its gap must be the kernel's ``gap`` for those arguments:

- ``vertex_edge``   a corner of body 1 on a straight edge of body 2, ``d = n . (p - e)``;
- ``vertex_circle`` a corner on a convex or concave circular edge, ``d = sigma |p - c| - r2``;
- ``circle_edge``   a convex circular edge on a straight edge, ``d = n . (c1 - e) - r1``;
- ``circle_circle`` convex on convex, or convex in concave, ``d = sigma |c1 - c2| - r2 - r1``.

A circular contact counts only if its point lies in the arc's span; beyond an arc's end the
contact belongs to the neighbouring feature: a corner, or, where the arc runs smoothly into a
straight side (a rounded box), that join point ("end"), which then acts as a vertex against
straight edges (a rounded box flat on a floor has two contacts, one at each end of its flat
side).  Straight edges lying on each other give the two ends of their overlap as vertex
contacts.  An ellipse becomes its osculating circle at the contact point (conventions, "oval
edge"): the point is found (support point, nearest or farthest point, or the separating
direction of two convex curves) and the circle routines take over.

Penetrating candidates (``gap < 0``) are kept only if plausible: no deeper than half the
thinner body; a corner's normal cone (nearly) containing the contact direction; a vertex in a
closed body 2 inside it and not much deeper than its shallowest way out (unless nothing better
describes the overlap); per feature against a closed body only the shallowest.  One constraint
reported from both bodies (two corners meeting) is kept once.

Positions are relative to body j's centre of mass, as the kernels compute them (``x1 - x2``
first), so gaps keep their precision far from the origin.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from runtime.model.shapes import TAU, Arc, Ellipse, Segment, Shape

SPAN_EPS = 1e-9  # rad, and relative length: closed spans, so flat-on-flat contacts survive
CONE_SLACK = 0.1  # rad: how far a corner's normal cone may miss a straight edge's normal
WAY_OUT_MARGIN = 0.05  # of the depth limit: how much deeper than its way out a vertex may be
HALF_PI = math.pi / 2
Candidate = tuple  # (case, body1, body2, geometry, gap, feature, point, normal, plausible)


class Table(NamedTuple):
    """A shape's contact features in body coordinates, built once per Shape.  ``g1``/``g2``
    are the feature's kernel arguments as body 1 / body 2."""

    corners: tuple  # (id, x, y, n_in x, y, cone width, arc before?, arc after?, g1)
    ends: tuple  # smooth convex-arc/segment joins: (id, x, y, nx, ny, side beyond arc, g1)
    segments: tuple  # (id, ax, ay, nx, ny, tx, ty, length, g2)
    arcs: tuple  # (id, cx, cy, signed r, start angle, span, g1, g2)
    ellipses: tuple  # (id, Ellipse)
    closed: bool
    half_width: float  # penetration limit: half the smallest width (inf for an open chain)


def table(shape: Shape) -> Table:
    found = shape._cache.get("narrowphase")
    if found is None:
        found = shape._cache["narrowphase"] = _build(shape)
    return found


def _circle_args(x: float, y: float, r: float) -> tuple[dict, dict]:
    return {"cx1": x, "cy1": y, "r1": r}, {"cx2": x, "cy2": y, "r2": r}


def _build(shape: Shape) -> Table:
    edges, n = shape.edges, len(shape.edges)
    cones, ends = [], []
    for i in range(n if shape.closed else n - 1):
        e_in, e_out = edges[i], edges[(i + 1) % n]
        if isinstance(e_in, Ellipse):
            continue
        (ax, ay), (bx, by) = e_in.normal_last(), e_out.normal_first()
        turn = math.atan2(ax * by - ay * bx, ax * bx + ay * by)
        arc_in, arc_out = isinstance(e_in, Arc), isinstance(e_out, Arc)
        if turn > 1e-9:
            cones.append((e_out.first, (ax, ay), turn, arc_in, arc_out))
        elif turn > -1e-9 and arc_in != arc_out and (e_in if arc_in else e_out).radius > 0:
            x, y = e_out.first
            ends.append((("end", i), x, y, ax, ay, 1.0 if arc_in else -1.0, {"px1": x, "py1": y}))
    if not shape.closed:  # chain ends: the half-plane of directions beyond the end
        (fx, fy), last = edges[0].normal_first(), edges[-1].normal_last()
        cones.append((edges[0].first, (-fx, -fy), math.pi, False, isinstance(edges[0], Arc)))
        cones.append((edges[-1].last, last, math.pi, isinstance(edges[-1], Arc), False))
    tiny = 1e-9 * shape.bounding_radius
    corners = []
    for k, (x, y) in enumerate(shape.vertices):
        near = [c for c in cones if math.hypot(c[0][0] - x, c[0][1] - y) <= tiny]
        cone = near[0][1:] if near else ((1.0, 0.0), TAU, False, False)
        corners.append((("vertex", k), x, y, *cone[0], *cone[1:], {"px1": x, "py1": y}))
    segments, arcs, ellipses = [], [], []
    for j, e in enumerate(edges):
        if isinstance(e, Segment):
            (ax, ay), (nx, ny) = e.start, e.normal
            g2 = {"ex2": ax, "ey2": ay, "nx2": nx, "ny2": ny}
            segments.append((("edge", j), ax, ay, nx, ny, -ny, nx, e.length, g2))
        elif isinstance(e, Arc):
            g = _circle_args(*e.centre, e.radius)
            arcs.append((("edge", j), *e.centre, e.radius, e.start_angle, e.span, *g))
        else:
            ellipses.append((("edge", j), e))
    half = _half_width(shape) if shape.closed else math.inf
    return Table(*map(tuple, (corners, ends, segments, arcs, ellipses)), shape.closed, half)


def _half_width(shape: Shape) -> float:
    """Half the smallest width of the shape (over 180 directions, boundary sampled)."""
    pts: list = []
    for e in shape.edges:
        if isinstance(e, Segment):
            pts += [e.start, e.end]
        elif isinstance(e, Arc):
            pts += [e.point(e.start_angle + e.span * k / 64) for k in range(65)]
        else:
            pts += [e.point(TAU * k / 128) for k in range(128)]
    a = np.linspace(0.0, math.pi, 180, endpoint=False)
    proj = np.asarray(pts) @ np.array([np.cos(a), np.sin(a)])
    return 0.5 * float(np.min(proj.max(axis=0) - proj.min(axis=0)))


def rotated(tab: Table, th: float) -> tuple:
    """The features turned to world axes but not translated (per call and body)."""
    c, s = math.cos(th), math.sin(th)
    corners = [(f, c * x - s * y, s * x + c * y, c * nx - s * ny, s * nx + c * ny, *rest)
               for f, x, y, nx, ny, *rest in tab.corners]  # fmt: skip
    ends = [(f, c * x - s * y, s * x + c * y, c * nx - s * ny, s * nx + c * ny, *rest)
            for f, x, y, nx, ny, *rest in tab.ends]  # fmt: skip
    segs = [(f, c * ax - s * ay, s * ax + c * ay, c * nx - s * ny, s * nx + c * ny,
             c * tx - s * ty, s * tx + c * ty, ln, g2)
            for f, ax, ay, nx, ny, tx, ty, ln, g2 in tab.segments]  # fmt: skip
    arcs = [(f, c * x - s * y, s * x + c * y, r, a0 + th, *rest)
            for f, x, y, r, a0, *rest in tab.arcs]  # fmt: skip
    ells = [(f, e, c * e.centre[0] - s * e.centre[1], s * e.centre[0] + c * e.centre[1],
             e.angle + th, c, s) for f, e in tab.ellipses]  # fmt: skip
    return corners, ends, segs, arcs, ells


def _in_span(ang: float, start: float, span: float) -> bool:
    d = (ang - start) % TAU
    return d <= span + SPAN_EPS or d >= TAU - SPAN_EPS


def _corner_ok(corner: tuple, ux: float, uy: float, flat: bool) -> bool:
    """Whether a corner may touch in the outward direction ``u``: inside its normal cone, or,
    against a straight or concave edge (which no smooth feature next to the corner can touch),
    at most CONE_SLACK beside it on a straight side (the lifted end of a box tilting on a
    floor).  Otherwise a neighbouring feature is the contact, not this corner."""
    nx, ny, width = corner[3], corner[4], corner[5]
    ang = math.atan2(nx * uy - ny * ux, nx * ux + ny * uy) % TAU
    if ang <= width + SPAN_EPS or ang >= TAU - SPAN_EPS:
        return True
    after = ang - width < TAU - ang
    straight = not (corner[7] if after else corner[6])
    return flat and straight and min(ang - width, TAU - ang) <= CONE_SLACK


def _way_out(w: tuple, o: tuple, px: float, py: float) -> float:
    """A lower bound of the signed distance of ``p`` from a closed convex body (turned features
    ``w``, offset ``o``), the best its edges give: ``n . (p - e)`` for straight edges,
    ``|p - c| - r`` for convex arcs whose span faces p, the tangent lines at arc ends, a
    scaled radius for an ellipse.  Positive: p is outside; negative: at most minus the depth
    of p's shallowest way out."""
    px, py = px - o[0], py - o[1]
    best = max(
        (n_x * (px - x) + n_y * (py - y) for _, x, y, n_x, n_y, *_ in w[2]), default=-math.inf
    )
    for _, cx, cy, r, a0, span, *_ in w[3]:
        if r > 0:
            vx, vy = px - cx, py - cy
            if _in_span(math.atan2(vy, vx), a0, span):
                best = max(best, math.hypot(vx, vy) - r)
            for a in (a0, a0 + span):
                best = max(best, math.cos(a) * vx + math.sin(a) * vy - r)
    for _, e, cx, cy, ph, _, _ in w[4]:  # (scaled radius - 1) times the lower bound
        vx, vy, c, s = px - cx, py - cy, math.cos(ph), math.sin(ph)
        k = math.hypot((c * vx + s * vy) / e.a, (c * vy - s * vx) / e.b) - 1
        best = max(best, k * (min(e.a, e.b) if k > 0 else max(e.a, e.b)))
    return best


def _maximise(f, df, n: int = 64) -> float:
    """Argmax of a smooth 2 pi-periodic ``f``: best of a grid, refined on ``df = 0``."""
    grid = [TAU * k / n for k in range(n)]
    k = max(range(n), key=lambda m: f(grid[m]))
    lo, hi = grid[k] - TAU / n, grid[k] + TAU / n
    if df(lo) > 0 > df(hi):
        from scipy.optimize import brentq

        return brentq(df, lo, hi, xtol=1e-15, rtol=1e-15)
    return grid[k]


def _support(kind: str, feat: tuple, o: tuple):
    """Support map ``u -> (x, y, t)`` of a turned ``"ell"``ipse (t its parameter there), full
    ``"arc"`` circle or ``"pt"`` corner: its point farthest along ``u``."""
    if kind == "ell":
        e, c, s = feat[1], math.cos(feat[4]), math.sin(feat[4])
        x0, y0 = feat[2] + o[0], feat[3] + o[1]

        def ellipse(ux: float, uy: float) -> tuple:
            t = math.atan2(e.b * (c * uy - s * ux), e.a * (c * ux + s * uy))
            x, y = e.a * math.cos(t), e.b * math.sin(t)
            return x0 + c * x - s * y, y0 + s * x + c * y, t

        return ellipse
    r, x0, y0 = (feat[3] if kind == "arc" else 0.0), feat[1] + o[0], feat[2] + o[1]
    return lambda ux, uy: (x0 + r * ux, y0 + r * uy, 0.0)


def _separation(s1, s2) -> tuple[float, float]:
    """Unit normal n (body 2 -> body 1) maximising ``n . (s1(-n) - s2(n))``: the separating
    direction of two convex features (their distance, or minus the penetration depth)."""

    def parts(a):
        n = math.cos(a), math.sin(a)
        p, q = s1(-n[0], -n[1]), s2(*n)
        return n, p[0] - q[0], p[1] - q[1]

    def sep(a):
        (nx, ny), dx, dy = parts(a)
        return nx * dx + ny * dy

    def dsep(a):
        (nx, ny), dx, dy = parts(a)
        return nx * dy - ny * dx

    a = _maximise(sep, dsep)
    return math.cos(a), math.sin(a)


def _farthest(ell: tuple, o: tuple, gx: float, gy: float) -> float:
    """Parameter of the ellipse point farthest from ``g`` (where, inside a concave arc centred
    at g, the ellipse touches: its curvature there is at least the arc's)."""
    e, c, s = ell[1], math.cos(ell[4]), math.sin(ell[4])
    dx, dy = gx - ell[2] - o[0], gy - ell[3] - o[1]
    px, py = c * dx + s * dy, -s * dx + c * dy  # g in the ellipse's frame

    def f(t):
        return (e.a * math.cos(t) - px) ** 2 + (e.b * math.sin(t) - py) ** 2

    def df(t):
        x, y = e.a * math.cos(t), e.b * math.sin(t)
        return -e.a * math.sin(t) * (x - px) + e.b * math.cos(t) * (y - py)

    return _maximise(f, df)


def _osculating(ell: tuple, t: float) -> tuple:
    """The ellipse's osculating circle at ``t`` as a turned full convex arc."""
    (bx, by), rho = ell[1].osculating(t)
    c, s = ell[5], ell[6]
    return (ell[0], c * bx - s * by, s * bx + c * by, rho, 0.0, TAU, *_circle_args(bx, by, rho))


class Pair:
    """Candidate contacts between bodies ``i`` (offset ``(ox, oy)`` from body j) and ``j``;
    ``wi``, ``wj`` their turned feature tables (see :func:`rotated`)."""

    def __init__(self, i, j, ti, tj, wi, wj, ox, oy, fixed_i, fixed_j, tol) -> None:
        self.i, self.j, self.ti, self.tj, self.wi, self.wj = i, j, ti, tj, wi, wj
        self.oi, self.oj, self.tol = (ox, oy), (0.0, 0.0), tol
        self.depth = min(ti.half_width, tj.half_width)
        # convex/convex: the fixed body is body 2 when possible (for the *_static2 kernels),
        # otherwise the lower index (i) is body 1
        self.i_first = not (fixed_i and not fixed_j)
        self.out: list[Candidate] = []

    def candidates(self) -> list[Candidate]:
        sides = ((self.i, self.wi, self.oi), (self.j, self.wj, self.oj))
        for (b1, w1, o1), (b2, w2, o2) in (sides, sides[::-1]):
            if w1[0] or w1[1]:
                self._points(b1, w1, o1, b2, w2, o2)
            if (w1[3] or w1[4]) and w2[2]:
                self._curves_on_segments(b1, w1, o1, b2, w2, o2)
        if (self.wi[3] or self.wi[4]) and (self.wj[3] or self.wj[4]):
            self._curves_on_curves()
        if self.wi[0] and self.wj[0]:
            self._corner_corner()
        return self.out

    def add(self, case, b1, b2, geom, gap, feature, point, normal) -> None:
        """Keep a candidate; a penetrating one only within the depth limit, and a penetrating
        vertex (point) of body 1 in a closed body 2 only if it is inside body 2; it is
        implausible (last element False) if much deeper than its shallowest way out (a
        vertex behind the line of a far edge)."""
        plausible = True
        if gap < 0:
            if -gap > self.depth:
                return
            t2, w2, o2 = (
                (self.ti, self.wi, self.oi) if b2 == self.i else (self.tj, self.wj, self.oj)
            )
            if t2.closed and case[0] == "v":
                out = _way_out(w2, o2, *point)
                if out > 1e-9 * t2.half_width:
                    return
                plausible = gap >= out - WAY_OUT_MARGIN * self.depth
        self.out.append((case, b1, b2, geom, gap, feature, point, normal, plausible))

    def _points(self, b1, w1, o1, b2, w2, o2) -> None:
        """Corners (and smooth ends) of body 1 on the edges of body 2."""
        tol, corners, ends = self.tol, w1[0], w1[1]
        for f2, ax, ay, nx, ny, tx, ty, ln, g2 in w2[2]:
            ax, ay, slack = ax + o2[0], ay + o2[1], SPAN_EPS * ln
            for k, feat in enumerate(corners + ends):
                px, py = feat[1] + o1[0], feat[2] + o1[1]
                gap, s = nx * (px - ax) + ny * (py - ay), tx * (px - ax) + ty * (py - ay)
                if gap > tol or not -slack <= s <= ln + slack:
                    continue
                if k < len(corners):
                    ok = _corner_ok(feat, -nx, -ny, True)
                else:  # a smooth end: only for directions beyond its arc
                    a = feat[5] * math.atan2(
                        nx * feat[4] - ny * feat[3], -nx * feat[3] - ny * feat[4]
                    )
                    ok = SPAN_EPS < a <= (HALF_PI if gap >= 0 else CONE_SLACK)
                if ok:
                    geom = {**feat[-1], **g2}
                    self.add("vertex_edge", b1, b2, geom, gap, (feat[0], f2), (px, py), (nx, ny))
        for arc in w2[3]:
            for corner in corners:
                self._corner_arc(b1, corner, o1, b2, arc, o2)
        for ell in w2[4] if corners else ():
            reach, s2 = max(ell[1].a, ell[1].b) + tol, _support("ell", ell, o2)
            for corner in corners:
                px, py = corner[1] + o1[0], corner[2] + o1[1]
                if math.hypot(px - ell[2] - o2[0], py - ell[3] - o2[1]) <= reach:
                    nx, ny = _separation(_support("pt", corner, o1), s2)
                    self._corner_arc(b1, corner, o1, b2, _osculating(ell, s2(nx, ny)[2]), o2)

    def _corner_arc(self, b1, corner, o1, b2, arc, o2) -> None:
        f2, cx, cy, r, a0, span, _, g2 = arc
        vx, vy = corner[1] + o1[0] - cx - o2[0], corner[2] + o1[1] - cy - o2[1]
        dist, sig = math.hypot(vx, vy), (1.0 if r > 0 else -1.0)
        gap = sig * dist - r
        if gap > self.tol or dist == 0.0 or not _in_span(math.atan2(vy, vx), a0, span):
            return
        nx, ny = sig * vx / dist, sig * vy / dist
        if _corner_ok(corner, -nx, -ny, r < 0):
            point, geom = (corner[1] + o1[0], corner[2] + o1[1]), {**corner[-1], **g2}
            self.add("vertex_circle", b1, b2, geom, gap, (corner[0], f2), point, (nx, ny))

    def _corner_corner(self) -> None:
        """Two corners facing each other, each in the other's normal cone, where neither has
        an edge of the other in front of it: ``vertex_circle`` with a circle of radius 0 (the
        kernels' formulas hold: sign(+0.0) = 1, ``d = |p1 - p2|``)."""
        one, two = (self.wi[0], self.oi, self.i), (self.wj[0], self.oj, self.j)
        if not self.i_first:
            one, two = two, one
        for c1 in one[0]:
            p1 = (c1[1] + one[1][0], c1[2] + one[1][1])
            for c2 in two[0]:
                vx, vy = p1[0] - c2[1] - two[1][0], p1[1] - c2[2] - two[1][1]
                gap = math.hypot(vx, vy)
                if gap > self.tol or gap == 0.0:
                    continue
                nx, ny = vx / gap, vy / gap
                if _corner_ok(c1, -nx, -ny, False) and _corner_ok(c2, nx, ny, False):
                    geom = {**c1[-1], "cx2": c2[-1]["px1"], "cy2": c2[-1]["py1"], "r2": 0.0}
                    feature = (c1[0], c2[0])
                    self.add("vertex_circle", one[2], two[2], geom, gap, feature, p1, (nx, ny))

    def _curves_on_segments(self, b1, w1, o1, b2, w2, o2) -> None:
        """Convex arcs and ellipses (osculating circles) of body 1 on straight edges of body 2."""
        for seg in w2[2]:
            f2, ax, ay, nx, ny, tx, ty, ln, g2 = seg
            ax, ay, slack = ax + o2[0], ay + o2[1], SPAN_EPS * ln
            arcs = [a for a in w1[3] if a[3] > 0 and _in_span(math.atan2(-ny, -nx), a[4], a[5])]
            for ell in w1[4]:
                qx, qy, t = _support("ell", ell, o1)(-nx, -ny)
                if nx * (qx - ax) + ny * (qy - ay) <= self.tol:
                    arcs.append(_osculating(ell, t))
            for f1, cx, cy, r, _, _, g1, _ in arcs:
                cx, cy = cx + o1[0], cy + o1[1]
                gap, s = nx * (cx - ax) + ny * (cy - ay) - r, tx * (cx - ax) + ty * (cy - ay)
                if gap <= self.tol and -slack <= s <= ln + slack:
                    point, geom = (cx - r * nx, cy - r * ny), {**g1, **g2}
                    self.add("circle_edge", b1, b2, geom, gap, (f1, f2), point, (nx, ny))

    def _curves_on_curves(self) -> None:
        """Circular and elliptic edges of i against those of j: circle_circle contacts."""
        mine = [("arc", a) for a in self.wi[3]] + [("ell", e) for e in self.wi[4]]
        theirs = [("arc", a) for a in self.wj[3]] + [("ell", e) for e in self.wj[4]]
        for ki, fi in mine:
            for kj, fj in theirs:
                concave_i, concave_j = ki == "arc" and fi[3] < 0, kj == "arc" and fj[3] < 0
                if concave_i and concave_j:
                    continue
                one, two = (self.i, ki, fi, self.oi), (self.j, kj, fj, self.oj)
                if concave_i or (not concave_j and not self.i_first):
                    one, two = two, one
                (b1, k1, f1, o1), (b2, k2, f2, o2) = one, two
                if k1 == k2 == "arc":
                    self._arc_arc(b1, f1, o1, b2, f2, o2)
                elif concave_i or concave_j:  # an ellipse inside a concave arc
                    t = _farthest(f1, o1, f2[1] + o2[0], f2[2] + o2[1])
                    self._arc_arc(b1, _osculating(f1, t), o1, b2, f2, o2)
                elif self._near(one, two):
                    s1, s2 = _support(k1, f1, o1), _support(k2, f2, o2)
                    nx, ny = _separation(s1, s2)
                    if k1 == "ell":
                        f1 = _osculating(f1, s1(-nx, -ny)[2])
                    if k2 == "ell":
                        f2 = _osculating(f2, s2(nx, ny)[2])
                    self._arc_arc(b1, f1, o1, b2, f2, o2)

    def _near(self, one, two) -> bool:
        """Bounding circles of two curves (arc: its circle; ellipse: its major circle)."""
        (_, k1, f1, o1), (_, k2, f2, o2) = one, two
        c1, c2 = f1[2:4] if k1 == "ell" else f1[1:3], f2[2:4] if k2 == "ell" else f2[1:3]
        r1 = max(f1[1].a, f1[1].b) if k1 == "ell" else f1[3]
        r2 = max(f2[1].a, f2[1].b) if k2 == "ell" else f2[3]
        dist = math.hypot(c1[0] + o1[0] - c2[0] - o2[0], c1[1] + o1[1] - c2[1] - o2[1])
        return dist <= r1 + r2 + self.tol

    def _arc_arc(self, b1, a1, o1, b2, a2, o2) -> None:
        f1, x1, y1, r1, s1, w1, g1, _ = a1
        f2, x2, y2, r2, s2, w2, _, g2 = a2
        vx, vy = x1 + o1[0] - x2 - o2[0], y1 + o1[1] - y2 - o2[1]
        dist, sig = math.hypot(vx, vy), (1.0 if r2 > 0 else -1.0)
        gap = sig * dist - r2 - r1
        if gap > self.tol or dist == 0.0:
            return
        nx, ny = sig * vx / dist, sig * vy / dist
        if _in_span(math.atan2(vy, vx), s2, w2) and _in_span(math.atan2(-ny, -nx), s1, w1):
            point = (x1 + o1[0] - r1 * nx, y1 + o1[1] - r1 * ny)
            self.add("circle_circle", b1, b2, {**g1, **g2}, gap, (f1, f2), point, (nx, ny))


def filtered(cands: list[Candidate], closed: list[bool], eps: float) -> list[Candidate]:
    """Implausible candidates go if the pair has a plausible penetration.  Against a closed body, a
    body-1 feature with a contact at gap >= 0 loses its penetrating ones, otherwise keeps only
    its shallowest.  One constraint reported from both bodies (same mid-point within ``eps``,
    parallel normals, same gap) is kept once.  Returns (case, ..., point, normal) tuples."""
    if any(c[8] and c[4] < 0 for c in cands):
        cands = [c for c in cands if c[8]]
    if len(cands) < 2:
        return [c[:8] for c in cands]
    best: dict = {}
    for c in cands:
        if closed[c[2]]:
            key = (c[1], c[5][0], c[2])
            best[key] = max(best.get(key, -math.inf), c[4])
    out: list[Candidate] = []
    for c in cands:
        if c[4] < 0 and closed[c[2]] and c[4] != best[(c[1], c[5][0], c[2])]:
            continue
        (px, py), (nx, ny), g = c[6], c[7], c[4]
        mx, my = px - 0.5 * g * nx, py - 0.5 * g * ny
        for d in out:
            (qx, qy), (kx, ky), h = d[6], d[7], d[4]
            same = abs(mx - qx + 0.5 * h * kx) <= eps and abs(my - qy + 0.5 * h * ky) <= eps
            if same and abs(g - h) <= eps and abs(nx * kx + ny * ky) >= 1 - 1e-9:
                break
        else:
            out.append(c[:8])
    return out
