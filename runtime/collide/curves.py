"""Narrow phase, curves: convex arcs and ellipses on straight edges, and curves on curves.

Why: a convex arc whose span faces a straight edge touches it at the foot of its centre
(``circle_edge``); two circular edges touch along the line of their centres (``circle_circle``:
convex on convex, or convex in concave, both directions within the spans).  An ellipse stands
for its osculating circle at the contact point: its support point against an edge, the support
points along the separating direction against another convex curve, its farthest point from
the centre inside a concave arc (runtime.collide.ovals).
"""

from __future__ import annotations

import math

from runtime.collide import ovals
from runtime.collide.candidates import CIRCLE_CIRCLE, CIRCLE_EDGE, TAU, emit, in_span, offset
from runtime.collide.contact_set import EDGE
from runtime.collide.features import (
    A_INDEX,
    A_R,
    A_SPAN,
    A_START,
    ARCS,
    ELLIPSES,
    L_INDEX,
    S_INDEX,
    S_JOIN_END,
    S_JOIN_START,
    S_LENGTH,
    S_NX,
    S_NY,
    S_TX,
    S_TY,
    SEGMENTS,
    X,
    Y,
)
from runtime.collide.junctions import within
from runtime.compiled import leaf
from runtime.settings import SPAN_EPS


@leaf
def curves_on_segments(rows, start, world, cand, k, ctx, b1, b2):
    """Convex arcs and ellipses (osculating circles) of body 1 on straight edges of body 2."""
    (o1x, o1y), (o2x, o2y) = offset(ctx, b1), offset(ctx, b2)
    th1 = ctx.thi if b1 == ctx.i else ctx.thj
    for s in range(start[b2, SEGMENTS], start[b2 + 1, SEGMENTS]):
        nx, ny = world[s, S_NX], world[s, S_NY]
        for a in range(start[b1, ARCS], start[b1 + 1, ARCS]):
            if rows[a, A_R] > 0 and in_span(-ny, -nx, world[a, A_START], rows[a, A_SPAN]):
                centre = (world[a, X] + o1x, world[a, Y] + o1y, rows[a, A_R])
                geometry = (rows[a, X], rows[a, Y], rows[a, A_R])
                k = _circle_edge(
                    rows, world, cand, k, ctx, b1, centre, geometry, rows[a, A_INDEX], b2, s
                )
        for e in range(start[b1, ELLIPSES], start[b1 + 1, ELLIPSES]):
            qx, qy, t = ovals.support(ovals.oval(rows[e], th1, o1x, o1y), -nx, -ny)
            if nx * (qx - world[s, X] - o2x) + ny * (qy - world[s, Y] - o2y) <= ctx.tolerance:
                circle, geometry = osculating_circle(rows[e], t, th1, o1x, o1y)
                k = _circle_edge(
                    rows, world, cand, k, ctx, b1, circle[:3], geometry, rows[e, L_INDEX], b2, s
                )
    return k


@leaf
def _circle_edge(rows, world, cand, k, ctx, b1, centre, geometry, index1, b2, s):
    cx, cy, r = centre
    o2x, o2y = offset(ctx, b2)
    ax, ay, nx, ny = world[s, X] + o2x, world[s, Y] + o2y, world[s, S_NX], world[s, S_NY]
    gap = nx * (cx - ax) + ny * (cy - ay) - r
    u, slack = world[s, S_TX] * (cx - ax) + world[s, S_TY] * (cy - ay), SPAN_EPS * rows[s, S_LENGTH]
    joins, tol = (rows[s, S_JOIN_START], rows[s, S_JOIN_END]), ctx.tolerance
    if gap > tol or not within(u, gap, rows[s, S_LENGTH], slack, *joins, tol):
        return k
    g = geometry + (rows[s, X], rows[s, Y], rows[s, S_NX], rows[s, S_NY])
    return emit(
        cand,
        k,
        ctx,
        CIRCLE_EDGE,
        b1,
        EDGE,
        index1,
        b2,
        EDGE,
        rows[s, S_INDEX],
        g,
        gap,
        (cx - r * nx, cy - r * ny),
        (nx, ny),
        (math.nan, math.nan),
    )


@leaf
def osculating_circle(row, t, th, ox, oy):
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
def curves_on_curves(rows, start, world, cand, k, ctx, i, j, i_first):
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
                c1, g1 = osculating_circle(rows[r1], t, th1, o1x, o1y)
            else:
                reach1 = f1[2] if arc1 else max(f1[2], f1[3])
                reach2 = f2[2] if arc2 else max(f2[2], f2[3])
                if math.hypot(f1[0] - f2[0], f1[1] - f2[1]) > reach1 + reach2 + ctx.tolerance:
                    continue
                nx, ny = ovals.separation(f1, f2)
                if not arc1:
                    c1, g1 = osculating_circle(
                        rows[r1], ovals.support(f1, -nx, -ny)[2], th1, o1x, o1y
                    )
                if not arc2:
                    c2, g2 = osculating_circle(
                        rows[r2], ovals.support(f2, nx, ny)[2], th2, o2x, o2y
                    )
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
    if not (in_span(vy, vx, s2, w2) and in_span(-ny, -nx, s1, w1)):
        return k
    return emit(
        cand,
        k,
        ctx,
        CIRCLE_CIRCLE,
        b1,
        EDGE,
        index1,
        b2,
        EDGE,
        index2,
        g1 + g2 + (0.0,),
        gap,
        (x1 - r1 * nx, y1 - r1 * ny),
        (nx, ny),
        (math.nan, math.nan),
    )
