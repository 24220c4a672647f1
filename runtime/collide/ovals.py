"""Ovals (ellipses) in contact, compiled: where an ellipse touches, and its osculating circle.

Why: a contact on an ellipse stands for the ellipse's osculating circle at the contact point
(docs/conventions.md, "oval edge"), so the narrow phase must find that point, and the engine
must find it again whenever the bodies move (issue #13: at every integrator stage), or the
circle it holds describes the oval only to second order.  The point is

- against a straight edge of normal n: the ellipse's support point in -n (closed form);
- against a corner, a circle or another ellipse: the support points along the separating
  direction of the two convex features, the unit n maximising n . (s1(-n) - s2(n)) (s the
  support maps): their distance, or minus their penetration depth;
- inside a concave arc: the ellipse point farthest from the arc's centre (where the curvature
  of the ellipse is at least the arc's).

The last two maximise a smooth periodic function: the best of a grid, then Brent's root
search on its derivative (as scipy's brentq, compiled).  Positions are relative to body 2's
centre of mass (o: a body's offset from it), axes are world axes.
"""

from __future__ import annotations

import math

from runtime.collide.contact_set import EDGE, VERTEX
from runtime.collide.features import (
    A_INDEX,
    A_R,
    ARCS,
    C_INDEX,
    CORNERS,
    ELLIPSES,
    L_A,
    L_ANGLE,
    L_B,
    L_INDEX,
    S_INDEX,
    S_NX,
    S_NY,
    SEGMENTS,
    X,
    Y,
)
from runtime.compiled import leaf, njit
from runtime.settings import ROOT_GRID, ROOT_RTOL, ROOT_XTOL

TAU = 2.0 * math.pi
SEPARATION, FARTHEST = 0, 1  # the functions the maximiser knows
NONE = (0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0)  # no feature (a point at the origin)
ROOT_ITERATIONS = 100


@leaf
def oval(row, th, ox, oy):
    """The convex feature (see :func:`support`) of an ellipse row of a body at angle ``th``
    and offset ``o``: world centre (relative), semi-axes, cos/sin of its world angle."""
    c, s = math.cos(th), math.sin(th)
    x, y, phi = row[X], row[Y], row[L_ANGLE] + th
    return (
        c * x - s * y + ox,
        s * x + c * y + oy,
        row[L_A],
        row[L_B],
        math.cos(phi),
        math.sin(phi),
        1.0,
    )


@leaf
def circle(row, th, ox, oy, r):
    """The convex feature of a circle of radius r (0: a point) about the point of ``row``."""
    c, s = math.cos(th), math.sin(th)
    return (c * row[X] - s * row[Y] + ox, s * row[X] + c * row[Y] + oy, r, 0.0, 1.0, 0.0, 0.0)


@leaf
def support_parameter(a, b, c, s, ux, uy):
    """Parameter t of the ellipse point farthest along u (ellipse turned by (c, s))."""
    return math.atan2(b * (c * uy - s * ux), a * (c * ux + s * uy))


@leaf
def support(f, ux, uy):
    """Point of the convex feature ``f`` farthest along u, and its parameter (0 if a circle).
    ``f`` = (x, y, a, b, c, s, is ellipse), a tuple: an ellipse (turned by the angle of cos c,
    sin s), or a circle of radius a (0: a point)."""
    if f[6] == 0.0:
        return f[0] + f[2] * ux, f[1] + f[2] * uy, 0.0
    a, b, c, s = f[2], f[3], f[4], f[5]
    t = support_parameter(a, b, c, s, ux, uy)
    x, y = a * math.cos(t), b * math.sin(t)
    return f[0] + c * x - s * y, f[1] + s * x + c * y, t


@leaf
def _value(mode, p, x):
    """The function to maximise at x, and its derivative."""
    if mode == SEPARATION:  # p: feature 1 (7 numbers), feature 2 (7 numbers)
        nx, ny = math.cos(x), math.sin(x)
        x1, y1, _ = support(p[:7], -nx, -ny)
        x2, y2, _ = support(p[7:], nx, ny)
        dx, dy = x1 - x2, y1 - y2
        return nx * dx + ny * dy, nx * dy - ny * dx
    a, b, px, py = p[0], p[1], p[2], p[3]  # FARTHEST: ellipse (a, b), point in its frame
    ex, ey = a * math.cos(x) - px, b * math.sin(x) - py
    return ex * ex + ey * ey, -a * math.sin(x) * ex + b * math.cos(x) * ey


@leaf
def _root(mode, p, xa, xb):
    """Root of the derivative in [xa, xb] (signs differ): Brent's method as scipy's brentq."""
    xpre, xcur = xa, xb
    fpre, fcur = _value(mode, p, xpre)[1], _value(mode, p, xcur)[1]
    xblk, fblk, spre, scur = 0.0, 0.0, 0.0, 0.0
    for _ in range(ROOT_ITERATIONS):
        if fpre != 0.0 and fcur != 0.0 and (fpre < 0.0) != (fcur < 0.0):
            xblk, fblk = xpre, fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre, xcur, xblk = xcur, xblk, xcur
            fpre, fcur, fblk = fcur, fblk, fcur
        delta = 0.5 * (ROOT_XTOL + ROOT_RTOL * abs(xcur))
        sbis = 0.5 * (xblk - xcur)
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:  # secant
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:  # inverse quadratic
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2.0 * abs(stry) < min(abs(spre), 3.0 * abs(sbis) - delta):
                spre, scur = scur, stry
            else:
                spre = scur = sbis
        else:
            spre = scur = sbis
        xpre, fpre = xcur, fcur
        xcur += scur if abs(scur) > delta else (delta if sbis > 0.0 else -delta)
        fcur = _value(mode, p, xcur)[1]
    return xcur


@leaf
def maximise(mode, p):
    """Argmax over a turn of the smooth periodic function ``mode`` with parameters ``p``: the
    best of ROOT_GRID points, refined on the root of the derivative around it."""
    best, k = -math.inf, 0
    for m in range(ROOT_GRID):
        v = _value(mode, p, TAU * m / ROOT_GRID)[0]
        if v > best:
            best, k = v, m
    x = TAU * k / ROOT_GRID
    lo, hi = x - TAU / ROOT_GRID, x + TAU / ROOT_GRID
    if _value(mode, p, lo)[1] > 0.0 > _value(mode, p, hi)[1]:
        return _root(mode, p, lo, hi)
    return x


@leaf
def separation(f1, f2):
    """Unit normal n (from feature 2 toward feature 1) maximising n . (s1(-n) - s2(n))."""
    a = maximise(SEPARATION, f1 + f2)
    return math.cos(a), math.sin(a)


@leaf
def farthest(f, gx, gy):
    """Parameter of the point of the ellipse ``f`` farthest from g."""
    dx, dy, c, s = gx - f[0], gy - f[1], f[4], f[5]
    p = (f[2], f[3], c * dx + s * dy, -s * dx + c * dy) + NONE + (0.0, 0.0, 0.0)  # 14 numbers
    return maximise(FARTHEST, p)


@leaf
def osculating(row, t):
    """Centre (body coordinates) and radius of the osculating circle of an ellipse row at t."""
    a, b, ct, st = row[L_A], row[L_B], math.cos(t), math.sin(t)
    x, y = (a * a - b * b) / a * ct**3, (b * b - a * a) / b * st**3
    rho = (a * a * st * st + b * b * ct * ct) ** 1.5 / (a * b)
    c, s = math.cos(row[L_ANGLE]), math.sin(row[L_ANGLE])
    return row[X] + c * x - s * y, row[Y] + s * x + c * y, rho


@leaf
def _row(table, start, b, kind, index, column):
    """Row of body b's features of ``kind`` whose index column is ``index`` (-1: none)."""
    for r in range(start[b, kind], start[b + 1, kind]):
        if table[r, column] == index:
            return r
    return -1


@njit
def refresh(poses, body1, body2, feature, geometry, rows, start):
    """Rewrite in place the osculating circles (geometry columns 0-2 or 3-5) of the contacts
    whose feature on a side is an ellipse, found again for ``poses``."""
    for k in range(len(body1)):
        i, j = body1[k], body2[k]
        e1, e2 = -1, -1
        if feature[k, 0] == EDGE:
            e1 = _row(rows, start, i, ELLIPSES, feature[k, 1], L_INDEX)
        if feature[k, 2] == EDGE:
            e2 = _row(rows, start, j, ELLIPSES, feature[k, 3], L_INDEX)
        if e1 < 0 and e2 < 0:
            continue
        ox, oy = poses[i, 0] - poses[j, 0], poses[i, 1] - poses[j, 1]
        th1, th2 = poses[i, 2], poses[j, 2]
        f1 = oval(rows[e1], th1, ox, oy) if e1 >= 0 else NONE
        f2 = oval(rows[e2], th2, 0.0, 0.0) if e2 >= 0 else NONE
        t1, t2 = math.nan, math.nan
        s = _row(rows, start, j, SEGMENTS, feature[k, 3], S_INDEX)
        if e1 >= 0 and feature[k, 2] == EDGE and s >= 0:  # on a straight edge
            c, sn = math.cos(th2), math.sin(th2)
            nx = c * rows[s, S_NX] - sn * rows[s, S_NY]
            ny = sn * rows[s, S_NX] + c * rows[s, S_NY]
            t1 = support_parameter(f1[2], f1[3], f1[4], f1[5], -nx, -ny)
        elif feature[k, 0] == VERTEX:  # a corner on an ellipse
            corner = rows[_row(rows, start, i, CORNERS, feature[k, 1], C_INDEX)]
            nx, ny = separation(circle(corner, th1, ox, oy, 0.0), f2)
            t2 = support(f2, nx, ny)[2]
        elif e1 >= 0 and e2 >= 0:
            nx, ny = separation(f1, f2)
            t1, t2 = support(f1, -nx, -ny)[2], support(f2, nx, ny)[2]
        elif e1 >= 0:  # body 2 is an arc: concave (the ellipse inside it) or convex
            r = _row(rows, start, j, ARCS, feature[k, 3], A_INDEX)
            arc = circle(rows[r], th2, 0.0, 0.0, rows[r, A_R])
            if rows[r, A_R] < 0:
                t1 = farthest(f1, arc[0], arc[1])
            else:
                nx, ny = separation(f1, arc)
                t1 = support(f1, -nx, -ny)[2]
        else:  # body 1 is a convex arc
            r = _row(rows, start, i, ARCS, feature[k, 1], A_INDEX)
            nx, ny = separation(circle(rows[r], th1, ox, oy, rows[r, A_R]), f2)
            t2 = support(f2, nx, ny)[2]
        if e1 >= 0 and not math.isnan(t1):
            geometry[k, 0], geometry[k, 1], geometry[k, 2] = osculating(rows[e1], t1)
        if e2 >= 0 and not math.isnan(t2):
            geometry[k, 3], geometry[k, 4], geometry[k, 5] = osculating(rows[e2], t2)
