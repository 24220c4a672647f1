"""Narrow phase, candidate stage (compiled): the feature pairs of two bodies that may touch.

Why: every contact must be one of the four cases of docs/conventions.md with its kernel
geometry in body coordinates, and its gap must be the generated kernel's ``gap`` for those
arguments.  This stage chooses the features with geometric distances (a screening gap, equal
to the kernel's up to rounding, with the tolerance widened by SCREEN_SLACK); the kernels then
give the gaps and runtime.collide.selection decides with them.  Its choices:

- ``vertex_edge``: a corner (or a smooth end) of body 1 over a straight edge of body 2, its
  projection within the edge; a corner only for directions in its normal cone, or at most
  CONE_SLACK beside it on a straight side (the lifted end of a box tilting on a floor), a
  smooth end only for directions beyond its arc;
- ``vertex_circle``: a corner on a circular edge, the direction within the arc's span; an
  ellipse stands for its osculating circle at the support point along the separating
  direction; two corners facing each other beyond each other's edges are a circle of radius 0;
- ``circle_edge``: a convex arc whose span faces the edge (or an ellipse's osculating circle at
  its support point), the centre's projection within the edge;
- ``circle_circle``: convex on convex, or convex in concave, both directions within the spans;
  ellipses by their osculating circles (separating direction, or the farthest point inside a
  concave arc: runtime.collide.ovals).

Which body is body 2 is fixed by the case (a vertex is body 1, a concave arc body 2, a curve on
a straight edge is body 1); for two convex curves (and two corners) the fixed body is body 2 if
there is one (so the engine can use the ``*_static2`` kernels), otherwise the lower index is
body 1.  Positions are relative to the pair's higher-index body j, as the kernels compute
them (``x1 - x2`` first), so they keep their precision far from the origin.

Candidates are rows of one float table (:data:`COLUMNS`), contiguous per pair, pairs sorted.
The helpers of a pair share a :class:`PairContext` and return the running count.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from generated import CASE_ID, GEOMETRY_COLUMNS
from runtime.collide import ovals
from runtime.collide.broadphase import sweep
from runtime.collide.contact_set import EDGE, END, VERTEX
from runtime.collide.features import (
    A_INDEX,
    A_R,
    A_SPAN,
    A_START,
    ARCS,
    C_ARC_AFTER,
    C_ARC_BEFORE,
    C_INDEX,
    C_NX,
    C_NY,
    C_WIDTH,
    CLOSED,
    CORNERS,
    E_INDEX,
    E_NX,
    E_NY,
    E_SIDE,
    ELLIPSES,
    ENDS,
    FIXED,
    L_INDEX,
    RADIUS,
    S_INDEX,
    S_LENGTH,
    S_NX,
    S_NY,
    S_TX,
    S_TY,
    SEGMENTS,
    X,
    Y,
)
from runtime.compiled import leaf, njit
from runtime.settings import CONE_SLACK, SCREEN_SLACK, SPAN_EPS

TAU = 2.0 * math.pi
HALF_PI = 0.5 * math.pi
VERTEX_EDGE, VERTEX_CIRCLE = CASE_ID["vertex_edge"], CASE_ID["vertex_circle"]
CIRCLE_EDGE, CIRCLE_CIRCLE = CASE_ID["circle_edge"], CASE_ID["circle_circle"]
PAIR, CASE, BODY1, BODY2, KIND1, INDEX1, KIND2, INDEX2, G = range(9)  # G: 7 geometry columns
SCREEN, PX, PY, NX, NY, END_ANGLE, WAY_OUT = range(G + 7, G + 14)
COLUMNS = G + 14


class PairContext(NamedTuple):
    """What the helpers of one pair of bodies i < j share (all floats, one tuple for numba)."""

    tolerance: float  # the pair's, widened by slack: what the screening gaps are held to
    slack: float  # SCREEN_SLACK times the pair's size
    i: float
    j: float
    oix: float  # offset of body i's centre of mass from body j's (positions are relative to j)
    oiy: float
    number: float  # of the pair, in the broad phase's order
    thi: float  # angles of the bodies
    thj: float
    closed_i: float  # 1.0: the body is closed (a vertex can be inside it)
    closed_j: float


# the geometry written below: feature 1 from column 0, feature 2 from column 3
assert GEOMETRY_COLUMNS["vertex_edge"] == dict(px1=0, py1=1, ex2=3, ey2=4, nx2=5, ny2=6)
assert GEOMETRY_COLUMNS["circle_circle"] == dict(cx1=0, cy1=1, r1=2, cx2=3, cy2=4, r2=5)
assert GEOMETRY_COLUMNS["vertex_circle"] == dict(px1=0, py1=1, cx2=3, cy2=4, r2=5)
assert GEOMETRY_COLUMNS["circle_edge"] == dict(cx1=0, cy1=1, r1=2, ex2=3, ey2=4, nx2=5, ny2=6)


@leaf
def _emit(cand, k, ctx, case, b1, kind1, index1, b2, kind2, index2, g, gap, p, n, aux):
    """Write candidate k (``aux``: end angle, way out) if there is room; returns k + 1 (the
    count goes on, so the caller can grow the table and search again)."""
    if k < len(cand):
        row = cand[k]
        row[PAIR], row[CASE], row[BODY1], row[BODY2] = ctx.number, case, b1, b2
        row[KIND1], row[INDEX1], row[KIND2], row[INDEX2] = kind1, index1, kind2, index2
        for c in range(7):
            row[G + c] = g[c]
        row[SCREEN], row[PX], row[PY], row[NX], row[NY] = gap, p[0], p[1], n[0], n[1]
        row[END_ANGLE], row[WAY_OUT] = aux
    return k + 1


@leaf
def _offset(ctx, b):
    return (ctx.oix, ctx.oiy) if b == ctx.i else (0.0, 0.0)


@leaf
def _in_span(y, x, start, span):
    """Whether the direction (x, y) lies in the span (closed by SPAN_EPS); a full turn holds
    every direction (no atan2)."""
    if span + SPAN_EPS >= TAU:
        return True
    d = (math.atan2(y, x) - start) % TAU
    return d <= span + SPAN_EPS or d >= TAU - SPAN_EPS


@leaf
def _corner_ok(rows, world, c, ux, uy, flat):
    """Whether corner row c may touch in the outward direction u: inside its normal cone,
    or, against a straight or concave edge (``flat``: no smooth feature next to the corner can
    touch it), at most CONE_SLACK beside it on a straight side."""
    nx, ny, width = world[c, C_NX], world[c, C_NY], rows[c, C_WIDTH]
    angle = math.atan2(nx * uy - ny * ux, nx * ux + ny * uy) % TAU
    if angle <= width + SPAN_EPS or angle >= TAU - SPAN_EPS:
        return True
    after = angle - width < TAU - angle
    straight = (rows[c, C_ARC_AFTER] if after else rows[c, C_ARC_BEFORE]) == 0.0
    return flat and straight and min(angle - width, TAU - angle) <= CONE_SLACK


@leaf
def _way_out(rows, start, world, b, o, px, py):
    """A lower bound of the signed distance of p from closed body b (offset o): the best its
    edges give (straight edges, convex arcs facing p and their end tangents, a scaled radius
    for an ellipse).  Positive: p is outside; negative: at most minus the depth of p's
    shallowest way out."""
    px, py = px - o[0], py - o[1]
    best = -math.inf
    for s in range(start[b, SEGMENTS], start[b + 1, SEGMENTS]):
        best = max(best, world[s, S_NX] * (px - world[s, X]) + world[s, S_NY] * (py - world[s, Y]))
    for a in range(start[b, ARCS], start[b + 1, ARCS]):
        r = rows[a, A_R]
        if r > 0:
            vx, vy, a0 = px - world[a, X], py - world[a, Y], world[a, A_START]
            if _in_span(vy, vx, a0, rows[a, A_SPAN]):
                best = max(best, math.hypot(vx, vy) - r)
            for angle in (a0, a0 + rows[a, A_SPAN]):
                best = max(best, math.cos(angle) * vx + math.sin(angle) * vy - r)
    for e in range(start[b, ELLIPSES], start[b + 1, ELLIPSES]):
        w = world[e]
        vx, vy, ea, eb, c, s = px - w[0], py - w[1], w[2], w[3], w[4], w[5]
        k = math.hypot((c * vx + s * vy) / ea, (c * vy - s * vx) / eb) - 1.0
        best = max(best, k * (min(ea, eb) if k > 0 else max(ea, eb)))
    return best


@leaf
def _vertex(rows, start, world, ctx, b2, gap, px, py, end_angle):
    """(end angle, way out) of a vertex candidate: the way out only where it can penetrate."""
    closed = ctx.closed_i if b2 == ctx.i else ctx.closed_j
    out = math.nan
    if closed > 0 and gap <= ctx.slack:
        out = _way_out(rows, start, world, b2, _offset(ctx, b2), px, py)
    return end_angle, out


@leaf
def _points(rows, start, world, cand, k, ctx, b1, b2):
    """Corners (and smooth ends) of body 1 on the edges of body 2."""
    tol, (o1x, o1y), (o2x, o2y) = ctx.tolerance, _offset(ctx, b1), _offset(ctx, b2)
    c0, c1, e0, e1 = (
        start[b1, CORNERS],
        start[b1 + 1, CORNERS],
        start[b1, ENDS],
        start[b1 + 1, ENDS],
    )
    for s in range(start[b2, SEGMENTS], start[b2 + 1, SEGMENTS]):
        ax, ay, nx, ny = world[s, X] + o2x, world[s, Y] + o2y, world[s, S_NX], world[s, S_NY]
        tx, ty, length = world[s, S_TX], world[s, S_TY], rows[s, S_LENGTH]
        slack = SPAN_EPS * length
        edge = (rows[s, X], rows[s, Y], rows[s, S_NX], rows[s, S_NY])
        for c in range(c0, c1):
            px, py = world[c, X] + o1x, world[c, Y] + o1y
            gap, u = nx * (px - ax) + ny * (py - ay), tx * (px - ax) + ty * (py - ay)
            if (
                gap <= tol
                and -slack <= u <= length + slack
                and _corner_ok(rows, world, c, -nx, -ny, True)
            ):
                g = (rows[c, X], rows[c, Y], 0.0) + edge
                aux = _vertex(rows, start, world, ctx, b2, gap, px, py, math.nan)
                k = _emit(cand, k, ctx, VERTEX_EDGE, b1, VERTEX, rows[c, C_INDEX], b2, EDGE,
                          rows[s, S_INDEX], g, gap, (px, py), (nx, ny), aux)  # fmt: skip
        for e in range(e0, e1):  # a smooth end: only for directions beyond its arc
            px, py = world[e, X] + o1x, world[e, Y] + o1y
            gap, u = nx * (px - ax) + ny * (py - ay), tx * (px - ax) + ty * (py - ay)
            if gap > tol or not -slack <= u <= length + slack:
                continue
            enx, eny = world[e, E_NX], world[e, E_NY]
            angle = rows[e, E_SIDE] * math.atan2(nx * eny - ny * enx, -nx * enx - ny * eny)
            if SPAN_EPS < angle <= HALF_PI:  # within CONE_SLACK if it penetrates: selection
                g = (rows[e, X], rows[e, Y], 0.0) + edge
                aux = _vertex(rows, start, world, ctx, b2, gap, px, py, angle)
                k = _emit(cand, k, ctx, VERTEX_EDGE, b1, END, rows[e, E_INDEX], b2, EDGE,
                          rows[s, S_INDEX], g, gap, (px, py), (nx, ny), aux)  # fmt: skip
    for a in range(start[b2, ARCS], start[b2 + 1, ARCS]):
        circle = (
            world[a, X] + o2x,
            world[a, Y] + o2y,
            rows[a, A_R],
            world[a, A_START],
            rows[a, A_SPAN],
        )
        geometry = (rows[a, X], rows[a, Y], rows[a, A_R])
        for c in range(c0, c1):
            k = _corner_arc(
                rows, start, world, cand, k, ctx, b1, c, b2, circle, geometry, rows[a, A_INDEX]
            )
    if c1 == c0:
        return k
    th2 = ctx.thi if b2 == ctx.i else ctx.thj
    for e in range(start[b2, ELLIPSES], start[b2 + 1, ELLIPSES]):
        f2 = ovals.oval(rows[e], th2, o2x, o2y)
        reach = max(f2[2], f2[3]) + tol
        for c in range(c0, c1):
            px, py = world[c, X] + o1x, world[c, Y] + o1y
            if math.hypot(px - f2[0], py - f2[1]) <= reach:
                nx, ny = ovals.separation((px, py, 0.0, 0.0, 1.0, 0.0, 0.0), f2)
                circle, geometry = _osculating(rows[e], ovals.support(f2, nx, ny)[2], th2, o2x, o2y)
                k = _corner_arc(rows, start, world, cand, k, ctx, b1, c, b2, circle, geometry,
                                rows[e, L_INDEX])  # fmt: skip
    return k


@leaf
def _corner_arc(rows, start, world, cand, k, ctx, b1, c, b2, circle, geometry, index2):
    """Corner row c of body 1 on the circle (centre, signed radius, start, span) of body 2."""
    cx, cy, r, a0, span = circle
    o1x, o1y = _offset(ctx, b1)
    px, py = world[c, X] + o1x, world[c, Y] + o1y
    vx, vy = px - cx, py - cy
    dist, sig = math.hypot(vx, vy), (1.0 if r > 0 else -1.0)
    gap = sig * dist - r
    if gap > ctx.tolerance or dist == 0.0 or not _in_span(vy, vx, a0, span):
        return k
    nx, ny = sig * vx / dist, sig * vy / dist
    if not _corner_ok(rows, world, c, -nx, -ny, r < 0):
        return k
    g = (rows[c, X], rows[c, Y], 0.0) + geometry + (0.0,)
    aux = _vertex(rows, start, world, ctx, b2, gap, px, py, math.nan)
    return _emit(cand, k, ctx, VERTEX_CIRCLE, b1, VERTEX, rows[c, C_INDEX], b2, EDGE, index2, g,
                 gap, (px, py), (nx, ny), aux)  # fmt: skip


@leaf
def _corner_corner(rows, start, world, cand, k, ctx, one, two):
    """Two corners facing each other, each in the other's normal cone, where neither has an
    edge of the other in front of it: ``vertex_circle`` with a circle of radius +0 (the
    kernels' formulas hold: sign(+0.0) = 1, ``d = |p1 - p2|``)."""
    o1, o2 = _offset(ctx, one), _offset(ctx, two)
    for c1 in range(start[one, CORNERS], start[one + 1, CORNERS]):
        px, py = world[c1, X] + o1[0], world[c1, Y] + o1[1]
        for c2 in range(start[two, CORNERS], start[two + 1, CORNERS]):
            vx, vy = px - world[c2, X] - o2[0], py - world[c2, Y] - o2[1]
            gap = math.hypot(vx, vy)
            if gap > ctx.tolerance or gap == 0.0:
                continue
            nx, ny = vx / gap, vy / gap
            if _corner_ok(rows, world, c1, -nx, -ny, False) and _corner_ok(
                rows, world, c2, nx, ny, False
            ):
                g = (rows[c1, X], rows[c1, Y], 0.0, rows[c2, X], rows[c2, Y], 0.0, 0.0)
                aux = _vertex(rows, start, world, ctx, two, gap, px, py, math.nan)
                k = _emit(cand, k, ctx, VERTEX_CIRCLE, one, VERTEX, rows[c1, C_INDEX], two, VERTEX,
                          rows[c2, C_INDEX], g, gap, (px, py), (nx, ny), aux)  # fmt: skip
    return k


@leaf
def _curves_on_segments(rows, start, world, cand, k, ctx, b1, b2):
    """Convex arcs and ellipses (osculating circles) of body 1 on straight edges of body 2."""
    (o1x, o1y), (o2x, o2y) = _offset(ctx, b1), _offset(ctx, b2)
    th1 = ctx.thi if b1 == ctx.i else ctx.thj
    for s in range(start[b2, SEGMENTS], start[b2 + 1, SEGMENTS]):
        nx, ny = world[s, S_NX], world[s, S_NY]
        for a in range(start[b1, ARCS], start[b1 + 1, ARCS]):
            if rows[a, A_R] > 0 and _in_span(-ny, -nx, world[a, A_START], rows[a, A_SPAN]):
                centre = (world[a, X] + o1x, world[a, Y] + o1y, rows[a, A_R])
                geometry = (rows[a, X], rows[a, Y], rows[a, A_R])
                k = _circle_edge(
                    rows, world, cand, k, ctx, b1, centre, geometry, rows[a, A_INDEX], b2, s
                )
        for e in range(start[b1, ELLIPSES], start[b1 + 1, ELLIPSES]):
            qx, qy, t = ovals.support(ovals.oval(rows[e], th1, o1x, o1y), -nx, -ny)
            if nx * (qx - world[s, X] - o2x) + ny * (qy - world[s, Y] - o2y) <= ctx.tolerance:
                circle, geometry = _osculating(rows[e], t, th1, o1x, o1y)
                k = _circle_edge(rows, world, cand, k, ctx, b1, circle[:3], geometry, rows[e, L_INDEX],
                                 b2, s)  # fmt: skip
    return k


@leaf
def _circle_edge(rows, world, cand, k, ctx, b1, centre, geometry, index1, b2, s):
    cx, cy, r = centre
    o2x, o2y = _offset(ctx, b2)
    ax, ay, nx, ny = world[s, X] + o2x, world[s, Y] + o2y, world[s, S_NX], world[s, S_NY]
    gap = nx * (cx - ax) + ny * (cy - ay) - r
    u, slack = world[s, S_TX] * (cx - ax) + world[s, S_TY] * (cy - ay), SPAN_EPS * rows[s, S_LENGTH]
    if gap > ctx.tolerance or not -slack <= u <= rows[s, S_LENGTH] + slack:
        return k
    g = geometry + (rows[s, X], rows[s, Y], rows[s, S_NX], rows[s, S_NY])
    return _emit(cand, k, ctx, CIRCLE_EDGE, b1, EDGE, index1, b2, EDGE, rows[s, S_INDEX], g, gap,
                 (cx - r * nx, cy - r * ny), (nx, ny), (math.nan, math.nan))  # fmt: skip


@leaf
def _osculating(row, t, th, ox, oy):
    """(world circle: centre, radius, start 0, full span; body geometry) of the osculating
    circle of ellipse ``row`` at parameter t, the body at angle th and offset o."""
    bx, by, rho = ovals.osculating(row, t)
    c, s = math.cos(th), math.sin(th)
    return (c * bx - s * by + ox, c * by + s * bx + oy, rho, 0.0, TAU), (bx, by, rho)


@leaf
def _curve(rows, start, world, b, m, o, th):
    """Curve m of body b (its arcs, then its ellipses): (table row, is arc?, convex feature
    for ovals.support, world circle if an arc)."""
    a = start[b, ARCS] + m
    if a < start[b + 1, ARCS]:
        x, y, r = world[a, X] + o[0], world[a, Y] + o[1], rows[a, A_R]
        return a, True, (x, y, r, 0.0, 1.0, 0.0, 0.0), (x, y, r, world[a, A_START], rows[a, A_SPAN])
    e = start[b, ELLIPSES] + a - start[b + 1, ARCS]
    f = ovals.oval(rows[e], th, o[0], o[1])
    return e, False, f, (f[0], f[1], 0.0, 0.0, 0.0)


@leaf
def _curves_on_curves(rows, start, world, cand, k, ctx, i, j, i_first):
    """Circular and elliptic edges of i against those of j: circle_circle contacts."""
    curves_i = start[i + 1, ARCS] - start[i, ARCS] + start[i + 1, ELLIPSES] - start[i, ELLIPSES]
    curves_j = start[j + 1, ARCS] - start[j, ARCS] + start[j + 1, ELLIPSES] - start[j, ELLIPSES]
    oi, oj, thi, thj = (ctx.oix, ctx.oiy), (0.0, 0.0), ctx.thi, ctx.thj
    for mi in range(curves_i):
        ri, arc_i, fi, ci = _curve(rows, start, world, i, mi, oi, thi)
        concave_i = arc_i and rows[ri, A_R] < 0
        for mj in range(curves_j):
            rj, arc_j, fj, cj = _curve(rows, start, world, j, mj, oj, thj)
            concave_j = arc_j and rows[rj, A_R] < 0
            if concave_i and concave_j:
                continue
            one = (i, ri, arc_i, thi) + oi
            two = (j, rj, arc_j, thj) + oj
            f1, f2, c1, c2 = fi, fj, ci, cj
            if concave_i or (not concave_j and not i_first):
                one, two, f1, f2, c1, c2 = two, one, fj, fi, cj, ci
            b1, r1, arc1, th1, o1x, o1y = one
            b2, r2, arc2, th2, o2x, o2y = two
            g1 = (rows[r1, X], rows[r1, Y], rows[r1, A_R])
            g2 = (rows[r2, X], rows[r2, Y], rows[r2, A_R])
            if arc1 and arc2:
                pass
            elif concave_i or concave_j:  # an ellipse inside a concave arc
                t = ovals.farthest(f1, f2[0], f2[1])
                c1, g1 = _osculating(rows[r1], t, th1, o1x, o1y)
            else:
                reach1 = f1[2] if arc1 else max(f1[2], f1[3])
                reach2 = f2[2] if arc2 else max(f2[2], f2[3])
                if math.hypot(f1[0] - f2[0], f1[1] - f2[1]) > reach1 + reach2 + ctx.tolerance:
                    continue
                nx, ny = ovals.separation(f1, f2)
                if not arc1:
                    c1, g1 = _osculating(rows[r1], ovals.support(f1, -nx, -ny)[2], th1, o1x, o1y)
                if not arc2:
                    c2, g2 = _osculating(rows[r2], ovals.support(f2, nx, ny)[2], th2, o2x, o2y)
            index1 = rows[r1, A_INDEX] if arc1 else rows[r1, L_INDEX]
            index2 = rows[r2, A_INDEX] if arc2 else rows[r2, L_INDEX]
            k = _arc_arc(cand, k, ctx, int(b1), c1, g1, index1, int(b2), c2, g2, index2)
    return k


@leaf
def _arc_arc(cand, k, ctx, b1, c1, g1, index1, b2, c2, g2, index2):
    x1, y1, r1, s1, w1 = c1
    x2, y2, r2, s2, w2 = c2
    vx, vy = x1 - x2, y1 - y2
    dist, sig = math.hypot(vx, vy), (1.0 if r2 > 0 else -1.0)
    gap = sig * dist - r2 - r1
    if gap > ctx.tolerance or dist == 0.0:
        return k
    nx, ny = sig * vx / dist, sig * vy / dist
    if not (_in_span(vy, vx, s2, w2) and _in_span(-ny, -nx, s1, w1)):
        return k
    return _emit(cand, k, ctx, CIRCLE_CIRCLE, b1, EDGE, index1, b2, EDGE, index2, g1 + g2 + (0.0,),
                 gap, (x1 - r1 * nx, y1 - r1 * ny), (nx, ny), (math.nan, math.nan))  # fmt: skip


@leaf
def _has(start, b, kind):
    return start[b + 1, kind] > start[b, kind]


@leaf
def _pair(rows, start, world, cand, k, ctx, i, j, i_first):
    """The candidates of bodies i < j, appended from row k; returns the new count."""
    for side in range(2):
        b1, b2 = (i, j) if side == 0 else (j, i)
        if _has(start, b1, CORNERS) or _has(start, b1, ENDS):
            k = _points(rows, start, world, cand, k, ctx, b1, b2)
        curves = _has(start, b1, ARCS) or _has(start, b1, ELLIPSES)
        if curves and _has(start, b2, SEGMENTS):
            k = _curves_on_segments(rows, start, world, cand, k, ctx, b1, b2)
    curves_i = _has(start, i, ARCS) or _has(start, i, ELLIPSES)
    if curves_i and (_has(start, j, ARCS) or _has(start, j, ELLIPSES)):
        k = _curves_on_curves(rows, start, world, cand, k, ctx, i, j, i_first)
    if _has(start, i, CORNERS) and _has(start, j, CORNERS):
        one, two = (i, j) if i_first else (j, i)
        k = _corner_corner(rows, start, world, cand, k, ctx, one, two)
    return k


@njit
def _world(rows, start, poses):
    """The features turned to world axes, not translated (same rows and columns): points,
    normals and tangents turned, arcs' start angles and ellipses' angles advanced (an ellipse
    row becomes centre, semi-axes, cos and sin of its world angle)."""
    world = rows.copy()
    for b in range(len(poses)):
        th = poses[b, 2]
        c, s = math.cos(th), math.sin(th)
        for kind, pairs in ((CORNERS, 2), (ENDS, 2), (SEGMENTS, 3), (ARCS, 1), (ELLIPSES, 1)):
            for r in range(start[b, kind], start[b + 1, kind]):
                for p in range(0, 2 * pairs, 2):
                    x, y = rows[r, p], rows[r, p + 1]
                    world[r, p], world[r, p + 1] = c * x - s * y, s * x + c * y
        for r in range(start[b, ARCS], start[b + 1, ARCS]):
            world[r, A_START] = rows[r, A_START] + th
        for r in range(start[b, ELLIPSES], start[b + 1, ELLIPSES]):
            f = ovals.oval(rows[r], th, 0.0, 0.0)
            for p in range(6):
                world[r, p] = f[p]
    return world


@njit
def find_candidates(poses, base, margins, rows, start, body, cand, kernel_inputs):
    """Broad phase, then the candidates of every pair into ``cand`` (row per candidate,
    :data:`COLUMNS`) and the ``kernel_inputs`` (see :func:`_kernel_inputs`).  Returns their
    number (more than ``cand`` holds: grow it and call again), or -1 - b if the pose or margin
    of body b is not finite."""
    n = len(poses)
    for b in range(n):
        if not (np.isfinite(poses[b, 0]) and np.isfinite(poses[b, 1]) and np.isfinite(poses[b, 2])):
            return -1 - b
        if not np.isfinite(margins[b]):
            return -1 - b
    reach = np.empty(n)
    for b in range(n):
        reach[b] = body[b, RADIUS] + 0.5 * max(base, 0.0) + max(margins[b], 0.0)
    pairs = sweep(poses[:, 0].copy(), poses[:, 1].copy(), reach, body[:, FIXED] > 0)
    world = _world(rows, start, poses)
    k = 0
    for p in range(len(pairs)):
        i, j = pairs[p, 0], pairs[p, 1]
        slack = SCREEN_SLACK * (body[i, RADIUS] + body[j, RADIUS])
        oix, oiy = poses[i, 0] - poses[j, 0], poses[i, 1] - poses[j, 1]
        ctx = PairContext(base + margins[i] + margins[j] + slack, slack, i, j, oix, oiy, p,
                          poses[i, 2], poses[j, 2], body[i, CLOSED], body[j, CLOSED])  # fmt: skip
        i_first = not (body[i, FIXED] > 0 and body[j, FIXED] == 0)
        k = _pair(rows, start, world, cand, k, ctx, i, j, i_first)
    if k <= len(cand):
        _kernel_inputs(cand, k, *kernel_inputs)
    return k


@njit
def _kernel_inputs(cand, count, body1, body2, geometry, members, case_start):
    """Copy the candidates' bodies and geometry into the arrays the kernels' ``batch_gap``
    takes, and group their indices by case in ``members`` (case c from ``case_start[c]``)."""
    case_start[:] = 0
    for k in range(count):
        body1[k], body2[k] = int(cand[k, BODY1]), int(cand[k, BODY2])
        for c in range(7):
            geometry[k, c] = cand[k, G + c]
        case_start[int(cand[k, CASE]) + 1] += 1
    for c in range(len(case_start) - 1):
        case_start[c + 1] += case_start[c]
    fill = case_start[:-1].copy()
    for k in range(count):
        c = int(cand[k, CASE])
        members[fill[c]] = k
        fill[c] += 1
