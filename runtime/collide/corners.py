"""Narrow phase, corners: the corners (and smooth ends) of body 1 on the edges of body 2.

Why: a corner touches a straight edge (``vertex_edge``), a circular edge (``vertex_circle``, an
ellipse by its osculating circle at the support point along the separating direction) or,
beyond both bodies' edges, another corner (``vertex_circle`` with a circle of radius +0); only
for directions in its normal cone, or at most CONE_SLACK beside it on a straight side (the
lifted end of a box tilting on a floor).  A smooth end (where a convex arc runs into a straight
side) acts as a corner against straight edges, for directions beyond its arc.  A vertex that
may penetrate a closed body 2 gets its shallowest way out, for the plausibility test.
"""

from __future__ import annotations

import math

from runtime.collide import ovals
from runtime.collide.candidates import (
    TAU,
    VERTEX_CIRCLE,
    VERTEX_EDGE,
    emit,
    in_span,
    offset,
)
from runtime.collide.contact_set import EDGE, END, VERTEX
from runtime.collide.curves import osculating_circle
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
    CORNERS,
    E_INDEX,
    E_NX,
    E_NY,
    E_SIDE,
    ELLIPSES,
    ENDS,
    HIDDEN,
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
from runtime.settings import CONE_SLACK, SPAN_EPS

HALF_PI = 0.5 * math.pi


@leaf
def turn_to(nx, ny, ux, uy):
    """The angle (rad, in [0, 2 pi)) from direction n counter-clockwise to direction u: where u
    lies in a corner's normal cone that starts at n (runtime.step.clearance asks the same)."""
    return math.atan2(nx * uy - ny * ux, nx * ux + ny * uy) % TAU


@leaf
def end_angle(side, nx, ny, enx, eny):
    """How far (rad) the way into an edge of normal n, -n, lies beyond a smooth end's arc (the
    end's normal en, its arc's side ``side``): the end touches the edge from SPAN_EPS to pi / 2
    (runtime.step.clearance asks the same)."""
    return side * math.atan2(nx * eny - ny * enx, -nx * enx - ny * eny)


@leaf
def _corner_ok(rows, world, c, ux, uy, flat):
    """Whether corner row c may touch in the outward direction u: inside its normal cone,
    or, against a straight or concave edge (``flat``: no smooth feature next to the corner can
    touch it), at most CONE_SLACK beside it on a straight side; never if it is HIDDEN."""
    width = rows[c, C_WIDTH]
    if width == HIDDEN:
        return False
    angle = turn_to(world[c, C_NX], world[c, C_NY], ux, uy)
    if angle <= width + SPAN_EPS or angle >= TAU - SPAN_EPS:
        return True
    after = angle - width < TAU - angle
    straight = (rows[c, C_ARC_AFTER] if after else rows[c, C_ARC_BEFORE]) == 0.0
    return flat and straight and min(angle - width, TAU - angle) <= CONE_SLACK


@leaf
def _way_out(rows, start, world, b, o, px, py):
    """A lower bound of the signed distance of p from closed body b (offset o): the best its
    edges give (straight edges, arcs facing p and a convex arc's end tangents, a scaled radius
    for an ellipse).  Positive: p is outside; negative: at most minus the depth of p's
    shallowest way out.  (A unit is convex, or a cup of at most a half turn, whose material
    lies behind every edge's line or circle: runtime.model.shape_library.bowl.)"""
    px, py = px - o[0], py - o[1]
    best = -math.inf
    for s in range(start[b, SEGMENTS], start[b + 1, SEGMENTS]):
        best = max(best, world[s, S_NX] * (px - world[s, X]) + world[s, S_NY] * (py - world[s, Y]))
    for a in range(start[b, ARCS], start[b + 1, ARCS]):
        r = rows[a, A_R]
        if r > 0:
            vx, vy, a0 = px - world[a, X], py - world[a, Y], world[a, A_START]
            if in_span(vy, vx, a0, rows[a, A_SPAN]):
                best = max(best, math.hypot(vx, vy) - r)
            for angle in (a0, a0 + rows[a, A_SPAN]):
                best = max(best, math.cos(angle) * vx + math.sin(angle) * vy - r)
        else:  # concave: p facing it inside its circle is out of the material (a cup's hollow)
            vx, vy = px - world[a, X], py - world[a, Y]
            if in_span(vy, vx, world[a, A_START], rows[a, A_SPAN]):
                best = max(best, -r - math.hypot(vx, vy))
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
        out = _way_out(rows, start, world, b2, offset(ctx, b2), px, py)
    return end_angle, out


@leaf
def corners_on_edges(rows, start, world, cand, k, ctx, b1, b2):
    """Corners (and smooth ends) of body 1 on the edges of body 2."""
    tol, (o1x, o1y), (o2x, o2y) = ctx.tolerance, offset(ctx, b1), offset(ctx, b2)
    c0, c1, e0, e1 = (
        start[b1, CORNERS],
        start[b1 + 1, CORNERS],
        start[b1, ENDS],
        start[b1 + 1, ENDS],
    )
    for s in range(start[b2, SEGMENTS], start[b2 + 1, SEGMENTS]):
        ax, ay, nx, ny = world[s, X] + o2x, world[s, Y] + o2y, world[s, S_NX], world[s, S_NY]
        tx, ty, length = world[s, S_TX], world[s, S_TY], rows[s, S_LENGTH]
        slack, join0, join1 = SPAN_EPS * length, rows[s, S_JOIN_START], rows[s, S_JOIN_END]
        edge = (rows[s, X], rows[s, Y], rows[s, S_NX], rows[s, S_NY])
        for c in range(c0, c1):
            px, py = world[c, X] + o1x, world[c, Y] + o1y
            gap, u = nx * (px - ax) + ny * (py - ay), tx * (px - ax) + ty * (py - ay)
            if (
                gap <= tol
                and within(u, gap, length, slack, join0, join1, tol)
                and _corner_ok(rows, world, c, -nx, -ny, True)
            ):
                g = (rows[c, X], rows[c, Y], 0.0) + edge
                aux = _vertex(rows, start, world, ctx, b2, gap, px, py, math.nan)
                k = emit(
                    cand,
                    k,
                    ctx,
                    VERTEX_EDGE,
                    b1,
                    VERTEX,
                    rows[c, C_INDEX],
                    b2,
                    EDGE,
                    rows[s, S_INDEX],
                    g,
                    gap,
                    (px, py),
                    (nx, ny),
                    aux,
                )
        for e in range(e0, e1):  # a smooth end: only for directions beyond its arc
            px, py = world[e, X] + o1x, world[e, Y] + o1y
            gap, u = nx * (px - ax) + ny * (py - ay), tx * (px - ax) + ty * (py - ay)
            if gap > tol or not within(u, gap, length, slack, join0, join1, tol):
                continue
            enx, eny = world[e, E_NX], world[e, E_NY]
            angle = end_angle(rows[e, E_SIDE], nx, ny, enx, eny)
            if SPAN_EPS < angle <= HALF_PI:  # within CONE_SLACK if it penetrates: selection
                g = (rows[e, X], rows[e, Y], 0.0) + edge
                aux = _vertex(rows, start, world, ctx, b2, gap, px, py, angle)
                k = emit(
                    cand,
                    k,
                    ctx,
                    VERTEX_EDGE,
                    b1,
                    END,
                    rows[e, E_INDEX],
                    b2,
                    EDGE,
                    rows[s, S_INDEX],
                    g,
                    gap,
                    (px, py),
                    (nx, ny),
                    aux,
                )
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
                circle, geometry = osculating_circle(
                    rows[e], ovals.support(f2, nx, ny)[2], th2, o2x, o2y
                )
                k = _corner_arc(
                    rows, start, world, cand, k, ctx, b1, c, b2, circle, geometry, rows[e, L_INDEX]
                )
    return k


@leaf
def _corner_arc(rows, start, world, cand, k, ctx, b1, c, b2, circle, geometry, index2):
    """Corner row c of body 1 on the circle (centre, signed radius, start, span) of body 2."""
    cx, cy, r, a0, span = circle
    o1x, o1y = offset(ctx, b1)
    px, py = world[c, X] + o1x, world[c, Y] + o1y
    vx, vy = px - cx, py - cy
    dist, sig = math.hypot(vx, vy), (1.0 if r > 0 else -1.0)
    gap = sig * dist - r
    if gap > ctx.tolerance or dist == 0.0 or not in_span(vy, vx, a0, span):
        return k
    nx, ny = sig * vx / dist, sig * vy / dist
    if not _corner_ok(rows, world, c, -nx, -ny, r < 0):
        return k
    g = (rows[c, X], rows[c, Y], 0.0) + geometry + (0.0,)
    aux = _vertex(rows, start, world, ctx, b2, gap, px, py, math.nan)
    return emit(
        cand,
        k,
        ctx,
        VERTEX_CIRCLE,
        b1,
        VERTEX,
        rows[c, C_INDEX],
        b2,
        EDGE,
        index2,
        g,
        gap,
        (px, py),
        (nx, ny),
        aux,
    )


@leaf
def corner_on_corner(rows, start, world, cand, k, ctx, one, two):
    """Two corners facing each other, each in the other's normal cone, where neither has an
    edge of the other in front of it: ``vertex_circle`` with a circle of radius +0 (the
    kernels' formulas hold: sign(+0.0) = 1, ``d = |p1 - p2|``)."""
    o1, o2 = offset(ctx, one), offset(ctx, two)
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
                k = emit(
                    cand,
                    k,
                    ctx,
                    VERTEX_CIRCLE,
                    one,
                    VERTEX,
                    rows[c1, C_INDEX],
                    two,
                    VERTEX,
                    rows[c2, C_INDEX],
                    g,
                    gap,
                    (px, py),
                    (nx, ny),
                    aux,
                )
    return k
