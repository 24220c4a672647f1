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

The same question for a touching contact (:func:`may_slide_off`): it is held, or watched, on
its feature's whole line or circle, so it can run past the feature's end while the next feature
closes in; where it may have, the quiet check declines and the search locates the instant it
left (:func:`room`) or asks the contact finder.
"""

from __future__ import annotations

import math

import numpy as np

from runtime.collide.contact_set import EDGE, END, VERTEX
from runtime.collide.corners import end_angle, turn_to
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
    HALF_WIDTH,
    L_A,
    L_B,
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
)  # fmt: skip
from runtime.collide.junctions import beyond
from runtime.compiled import leaf, njit
from runtime.settings import SPAN_EPS

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
def _turned(angle, x, y):
    """The vector (x, y) of a body turned by ``angle``: in world axes."""
    c, s = math.cos(angle), math.sin(angle)
    return c * x - s * y, s * x + c * y


@leaf
def _world(pose, x, y):
    """The point (x, y) of a body at ``pose``: in world coordinates."""
    dx, dy = _turned(pose[2], x, y)
    return pose[0] + dx, pose[1] + dy


@leaf
def _towards(rows, t, r, pose, x, y):
    """The direction from the world point (x, y) to feature (t, r)'s point or centre at
    ``pose`` -- away from it where that is a concave arc's centre (a bowl: its wall lies beyond
    the point, seen from its centre)."""
    ox, oy = _world(pose, rows[r, X], rows[r, Y])
    flip = -1.0 if t == ARCS and rows[r, A_R] < 0.0 else 1.0
    return flip * (ox - x), flip * (oy - y)


@leaf
def _feature(rows, kind, r, pose):
    """Feature row r of kind ``kind`` (runtime.collide.features) on a body at ``pose``: its kind
    and index as in a contact's key, and what holds it in world coordinates -- a segment
    (``straight``, from (x0, y0) to (x1, y1)), or an annulus about (x0, y0) between radii
    ``inner`` and ``outer`` (a corner or end: radius 0; an arc: its whole circle; an ellipse:
    between its semi-axes)."""
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
    x0, y0 = _world(pose, x, y)
    x1, y1 = _world(pose, ex, ey)
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


@leaf
def _row_of(rows, body_start, body, kind, index):
    """(table kind, row) of feature ``kind``, ``index`` (a contact's key) of ``body``."""
    first, last = (CORNERS, CORNERS) if kind == VERTEX else (ENDS, ENDS) if kind == END else (
        SEGMENTS, ELLIPSES)  # fmt: skip
    for t in range(first, last + 1):
        column = (C_INDEX, E_INDEX, S_INDEX, A_INDEX, L_INDEX)[t]
        for r in range(body_start[body, t], body_start[body + 1, t]):
            if rows[r, column] == index:
                return t, r
    return -1, -1


LEAVE = 2.0 * SPAN_EPS  # rad, and relative length: a resting contact has left its feature
# when the other feature lies this far beyond its end -- twice the contact finder's closure of
# spans and ends, so at that instant the finder picks the next feature, not this one again


@leaf
def _signed(turn, span):
    """How far the angle ``turn`` (in [0, 2 pi)) lies inside [0, span] (rad; negative: how far
    outside, to the nearer end) -- continuous, so a root search can find where it leaves."""
    if turn <= span:
        return min(turn, span - turn)
    return -min(turn - span, 2.0 * math.pi - turn)


@leaf
def _room(rows, t, r, pose, other_t, other_r, other_pose):
    """How far inside its ends, widened by LEAVE, feature (t, r) holds its contact with feature
    (other_t, other_r) at these poses (negative: beyond them): a straight edge by length, an
    arc by arc length, a corner's cone and a smooth end by angle (only the sign is compared,
    and it changes continuously); inf for features without ends, -inf where the other's
    position is unknown (an ellipse's contact point)."""
    if t == CORNERS:
        return _cone_room(rows, r, pose, other_t, other_r, other_pose)
    if t == ENDS:
        return _end_room(rows, r, pose, other_r, other_pose)
    if t != SEGMENTS and t != ARCS:
        return math.inf
    if other_t == ELLIPSES:
        return -math.inf
    if t == SEGMENTS:
        if other_t == SEGMENTS:
            return math.inf  # (no contact case joins two straight edges)
        ax, ay = _world(pose, rows[r, X], rows[r, Y])
        ox, oy = _world(other_pose, rows[other_r, X], rows[other_r, Y])  # a point or a centre
        tx, ty = _turned(pose[2], rows[r, S_TX], rows[r, S_TY])
        u, length = (ox - ax) * tx + (oy - ay) * ty, rows[r, S_LENGTH]
        before = after = 0.0
        if other_t != ARCS:  # a corner or end: held beyond a reflex join's end (junctions),
            # at most as far as the contact finder holds it (not for a depth behind the other
            # edge, which it widens by its tolerance): where it lets go, room is <= 0
            nx, ny = _turned(pose[2], rows[r, S_NX], rows[r, S_NY])
            gap = (ox - ax) * nx + (oy - ay) * ny
            before = beyond(rows[r, S_JOIN_START], gap, math.inf, 0.0)
            after = beyond(rows[r, S_JOIN_END], gap, math.inf, 0.0)
        return min(u + before, length - u + after) + LEAVE * length
    if rows[r, A_SPAN] >= 2.0 * math.pi:
        return math.inf
    if other_t == SEGMENTS:  # the arc touches the line where its normal opposes the line's
        nx, ny = _turned(other_pose[2], rows[other_r, S_NX], rows[other_r, S_NY])
        dx, dy = -nx, -ny
    else:
        cx, cy = _world(pose, rows[r, X], rows[r, Y])
        dx, dy = _towards(rows, other_t, other_r, other_pose, cx, cy)
    turn = (math.atan2(dy, dx) - pose[2] - rows[r, A_START] + LEAVE) % (2.0 * math.pi)
    return abs(rows[r, A_R]) * _signed(turn, rows[r, A_SPAN] + 2.0 * LEAVE)


@leaf
def _cone_room(rows, r, pose, other_t, other_r, other_pose):
    """How far (rad) the direction from corner row r to feature (other_t, other_r) lies inside
    the corner's normal cone widened by LEAVE: a side next to the corner may meet a curve
    beyond it (a half disc's corner resting on an ellipse, turning onto its flat side), and an
    arc next to it a straight edge (a half disc tipping about its corner on a wall turned its
    arc 4.5e-7 m into the wall). inf for a straight edge against a corner between straight
    sides, whose turn onto the next side brings another corner to it, which the frame
    watches."""
    if other_t == ELLIPSES:
        return -math.inf
    if other_t == SEGMENTS:
        if rows[r, C_ARC_BEFORE] == 0.0 and rows[r, C_ARC_AFTER] == 0.0:
            return math.inf
        sx, sy = _turned(other_pose[2], rows[other_r, S_NX], rows[other_r, S_NY])
        ux, uy = -sx, -sy  # the corner's outward direction onto the edge
    else:
        vx, vy = _world(pose, rows[r, X], rows[r, Y])
        ux, uy = _towards(rows, other_t, other_r, other_pose, vx, vy)
    nx, ny = _turned(pose[2], rows[r, C_NX], rows[r, C_NY])
    angle = (turn_to(nx, ny, ux, uy) + LEAVE) % (2.0 * math.pi)
    return _signed(angle, rows[r, C_WIDTH] + 2.0 * LEAVE)


@leaf
def _end_room(rows, r, pose, other_r, other_pose):
    """How far (rad) a smooth end (row r; it touches straight edges only) still faces segment
    row ``other_r`` from beyond its arc, widened by LEAVE: the contact finder takes it for
    directions SPAN_EPS to pi / 2 beyond (runtime.collide.corners); turned back onto the arc, a
    rounded box tipping from its flat side onto its corner, the arc touches instead."""
    nx, ny = _turned(other_pose[2], rows[other_r, S_NX], rows[other_r, S_NY])
    ex, ey = _turned(pose[2], rows[r, E_NX], rows[r, E_NY])
    angle = end_angle(rows[r, E_SIDE], nx, ny, ex, ey)
    return min(angle - SPAN_EPS, 0.5 * math.pi - angle) + LEAVE


@leaf
def room(k, q, body1, body2, feature, rows, body_start):
    """The smaller of the rooms (:func:`_room`) of contact k's two features at poses q: <= 0
    once it has left one of them; -inf if a feature is not in the tables."""
    i, j = body1[k], body2[k]
    ti, ri = _row_of(rows, body_start, i, feature[k, 0], feature[k, 1])
    tj, rj = _row_of(rows, body_start, j, feature[k, 2], feature[k, 3])
    if ri < 0 or rj < 0:
        return -math.inf
    return min(_room(rows, ti, ri, q[i], tj, rj, q[j]), _room(rows, tj, rj, q[j], ti, ri, q[i]))


@njit
def rooms(contacts, q, body1, body2, feature, rows, body_start):
    """:func:`room` of each contact of ``contacts`` (indices) at poses q."""
    out = np.empty(contacts.size)
    for a in range(contacts.size):
        out[a] = room(contacts[a], q, body1, body2, feature, rows, body_start)
    return out


@leaf
def may_slide_off(k, q0, q1, radii, switches, body1, body2, feature, rows, body_start, touch):
    """Whether touching contact k may have run off the end of one of its features by ``q1``
    (the step's end; from ``q0``): a resting contact is held (one moving apart watched) on its
    feature's whole line or circle, so past the end it would be held there while the next
    feature (a rounded box's side after its corner arc) closes in unwatched, or the next
    feature would take it (a disc rolling off a flat face onto a corner's arc, held up on the
    face's line). Not if neither
    body has several features or they moved less than the touch gap, or if at q1 each feature
    still holds the contact (:func:`room`): a step's short smooth path does not leave a
    feature and come back. An ellipse's contact point is not known here: a contact on one may
    always have slid."""
    i, j = body1[k], body2[k]
    if not (switches[i] or switches[j]):
        return False
    if not moved(q0, q1, radii, i) + moved(q0, q1, radii, j) > touch:
        return False
    return not room(k, q1, body1, body2, feature, rows, body_start) > 0.0


@njit
def sliding_off(q0, q1, radii, switches, resting, body1, body2, feature, rows, body_start, touch):
    """:func:`may_slide_off` for each contact of ``resting`` (indices): a bool per one."""
    out = np.zeros(resting.size, np.bool_)
    for a in range(resting.size):
        out[a] = may_slide_off(resting[a], q0, q1, radii, switches, body1, body2, feature, rows,
                               body_start, touch)  # fmt: skip
    return out


__all__ = ["LEAVE", "clear", "deepest", "may_slide_off", "moved", "room", "rooms", "sliding_off"]
