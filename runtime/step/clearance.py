"""Whether two bodies can meet within a step at a feature pair that no contact watches.

Why: the event search asks the contact finder, at many instants of a step, about every pair
with a fast body (runtime.step.pair_scan), because a feature pair that was no contact at the
start (a corner turning round onto an edge) can meet within it; and the quiet check
(runtime.step.quiet) sent every step with a fast body to that search. Most fast pairs cannot
meet anywhere new: a disc rolling fast in a bowl or flying off a cylinder has no other feature
near. A lower bound on the distance of each feature pair at the start, against how far the
bodies can move (their margins) and how deep a contact the finder admits, proves it in one
compiled loop, and the search and the quiet check skip such pairs -- the same outcome, as no
sample could have found a contact there.
"""

from __future__ import annotations

import math

import numpy as np

from runtime.collide.contact_set import EDGE, END, VERTEX
from runtime.collide.features import (
    A_INDEX,
    A_R,
    ARCS,
    C_INDEX,
    CORNERS,
    E_INDEX,
    ENDS,
    HALF_WIDTH,
    L_A,
    L_B,
    L_INDEX,
    S_INDEX,
    S_LENGTH,
    S_TX,
    S_TY,
    SEGMENTS,
    X,
    Y,
)  # fmt: skip
from runtime.compiled import leaf, njit

SLACK = 1e-9  # relative: the room the distance test keeps for rounding


def deepest(tables) -> np.ndarray:
    """(n,) the deepest contact the finder admits on each body (runtime.collide.selection: half
    the thinner unit of the pair): the half width of its thickest unit (inf for open chains)."""
    out = np.zeros(len(tables.body_start) - 1)
    np.maximum.at(out, tables.owner, tables.body[:, HALF_WIDTH])
    return out


@leaf
def moved(q0, q1, radii, i):
    """How far the farthest point of body i moved (runtime.collide.sweep.displacement)."""
    dx, dy = q1[i, 0] - q0[i, 0], q1[i, 1] - q0[i, 1]
    return math.sqrt(dx * dx + dy * dy) + abs(q1[i, 2] - q0[i, 2]) * radii[i]


@leaf
def _feature(rows, kind, r, pose):
    """Feature row r of kind ``kind`` (runtime.collide.features) on a body at ``pose``: its kind
    and index as in a contact's key, and what holds it in world coordinates -- a segment
    (``straight``, from (x0, y0) to (x1, y1)), or an annulus about (x0, y0) between radii
    ``inner`` and ``outer`` (a corner or end: radius 0; an arc: its whole circle; an ellipse:
    between its semi-axes)."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    x, y, inner, outer, straight = rows[r, X], rows[r, Y], 0.0, 0.0, False
    ex, ey = x, y
    if kind == CORNERS:
        key, index = VERTEX, rows[r, C_INDEX]
    elif kind == ENDS:
        key, index = END, rows[r, E_INDEX]
    elif kind == SEGMENTS:
        key, index, straight = EDGE, rows[r, S_INDEX], True
        ex, ey = x + rows[r, S_LENGTH] * rows[r, S_TX], y + rows[r, S_LENGTH] * rows[r, S_TY]
    elif kind == ARCS:
        key, index, inner = EDGE, rows[r, A_INDEX], abs(rows[r, A_R])
        outer = inner
    else:
        key, index = EDGE, rows[r, L_INDEX]
        inner, outer = min(rows[r, L_A], rows[r, L_B]), max(rows[r, L_A], rows[r, L_B])
    x0, y0 = pose[0] + c * x - s * y, pose[1] + s * x + c * y
    x1, y1 = pose[0] + c * ex - s * ey, pose[1] + s * ex + c * ey
    return key, index, straight, x0, y0, x1, y1, inner, outer


@leaf
def _reach_of_segment(ax, ay, bx, by, cx, cy):
    """(nearest, farthest) distance of the segment a-b from the point c."""
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    u = 0.0 if length2 == 0.0 else min(max(((cx - ax) * dx + (cy - ay) * dy) / length2, 0.0), 1.0)
    nearest = math.hypot(ax + u * dx - cx, ay + u * dy - cy)
    return nearest, max(math.hypot(ax - cx, ay - cy), math.hypot(bx - cx, by - cy))


@leaf
def _apart(f, g):
    """A lower bound on the distance between two features (:func:`_feature`); inf for two
    segments, which no contact case joins (straight edges meet at their corners)."""
    _, _, straight_f, fx, fy, fx1, fy1, f_in, f_out = f
    _, _, straight_g, gx, gy, gx1, gy1, g_in, g_out = g
    if straight_f and straight_g:
        return math.inf
    if straight_f or straight_g:
        if straight_f:
            near, far = _reach_of_segment(fx, fy, fx1, fy1, gx, gy)
            inner, outer = g_in, g_out
        else:
            near, far = _reach_of_segment(gx, gy, gx1, gy1, fx, fy)
            inner, outer = f_in, f_out
        return max(near - outer, inner - far)
    d = math.hypot(fx - gx, fy - gy)
    return max(d - f_out - g_out, f_in - d - g_out, g_in - d - f_out)


@leaf
def _known(i, f, j, g, body1, body2, feature):
    """Whether a contact of the frame is feature f of body i on feature g of body j."""
    for k in range(body1.size):
        a, b = feature[k], (f[0], f[1], g[0], g[1])
        if body1[k] == j and body2[k] == i:
            b = (g[0], g[1], f[0], f[1])
        elif not (body1[k] == i and body2[k] == j):
            continue
        if a[0] == b[0] and a[1] == b[1] and a[2] == b[2] and a[3] == b[3]:
            return True
    return False


@njit
def clear(i, j, q0, q1, margin, radii, depths, touch, rows, body_start, body1, body2, feature):
    """Whether bodies i and j cannot touch within the step from poses ``q0`` to ``q1`` at a
    feature pair that no contact of the frame (``body1``, ``body2``, ``feature``) has: every
    such pair is farther apart at the start (:func:`_apart`) than both bodies can move -- their
    margins, or twice what they moved if more (as the step widens its contacts:
    runtime.step.stepper) -- and the deepest contact the finder admits (the smaller of
    ``depths``, :func:`deepest`; at least the touch gap). A contact's gap is the distance of a
    point of each of its features, so a new contact found anywhere in the step would need its
    features that close."""
    depth = min(depths[i], depths[j])
    if not math.isfinite(depth):
        return False
    reach = max(margin[i], 2.0 * moved(q0, q1, radii, i))
    reach += max(margin[j], 2.0 * moved(q0, q1, radii, j))
    room = (reach + max(depth, touch)) * (1.0 + SLACK)  # (not finite: never clear)
    for kind_i in range(5):
        for a in range(body_start[i, kind_i], body_start[i + 1, kind_i]):
            f = _feature(rows, kind_i, a, q0[i])
            for kind_j in range(5):
                for b in range(body_start[j, kind_j], body_start[j + 1, kind_j]):
                    g = _feature(rows, kind_j, b, q0[j])
                    if not _apart(f, g) > room and not _known(i, f, j, g, body1, body2, feature):
                        return False
    return True


__all__ = ["clear", "deepest", "moved"]
