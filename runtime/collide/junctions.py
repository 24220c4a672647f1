"""Reflex joins of straight edges: where an edge holds a corner a little beyond its end.

Why: a straight edge holds a corner (or a smooth end, or a circle by its centre) only level
with it -- its span, closed by SPAN_EPS. Where two straight edges meet at a reflex join (the
inside of a V: one chain's, or two fixed walls ending at one point), a corner sliding into the
join along one edge reaches the other edge's line only at that edge's end, unwatched until it
is there; and a corner pressed into the join leaves both spans, behind both lines, where
neither edge holds it and it sinks through (a box sliding down a wall into a V of walls at 30
degrees; the mixed pile's half disc). Near such a join the free space is exactly what lies in
front of both lines, so each edge's line holds a corner beyond its end as far as that stays
true, for corners within the contact finder's tolerance of it: in front of the line, over the
free space up to the other edge and a tolerance behind that edge's line (1 / sin of the join's
free angle times the tolerance beyond the end); behind it, over the material behind both lines
(|tan| of the angle per unit of depth); at most settings.JOIN_REACH per unit of tolerance or
depth, so only near the join.

Each segment row of the feature tables (runtime.collide.features) carries the free angle of a
reflex join at its start and at its end (0: a free end or a convex join); a chain's own joins
are set when its tables are built (:func:`free_angle`), joins of two fixed bodies' edges when a
contact finder first sees the fixed bodies' poses (:func:`join_fixed_edges`), which also
hides the walls' end vertices there: as a chain's reflex join has none, only a corner fits into
the join, and with them a box's corner in a V touched four features and its forces failed.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.spatial import cKDTree

from runtime.collide.features import (
    C_WIDTH,
    CLOSED,
    CORNERS,
    FIXED,
    HIDDEN,
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
from runtime.compiled import leaf
from runtime.settings import JOIN_EPS, JOIN_REACH, TURN_EPS

__all__ = ["beyond", "free_angle", "join_fixed_edges", "within"]


def free_angle(ray1, normal1, ray2, normal2) -> float:
    """The angle of free space between two straight edges that meet at a point (``ray``: unit
    direction from the point along the edge; ``normal``: its outward normal), if the join is
    reflex -- each edge lies in front of the other's line -- else 0."""
    front1 = ray2[0] * normal1[0] + ray2[1] * normal1[1]
    front2 = ray1[0] * normal2[0] + ray1[1] * normal2[1]
    if front1 <= TURN_EPS or front2 <= TURN_EPS:
        return 0.0
    cos = ray1[0] * ray2[0] + ray1[1] * ray2[1]
    return math.acos(min(1.0, max(-1.0, cos)))


@leaf
def beyond(angle, gap, limit, depth):
    """How far beyond its end an edge with a reflex join of free angle ``angle`` (0: none) still
    holds a point ``gap`` in front of its line (< 0: behind it), if |gap| <= ``limit``: in front,
    over points up to ``depth`` behind the other edge's line -- the free space up to the other
    edge for gaps up to ``depth``, and a corner sliding into the join along that edge, sunk by
    the touch gap or more; behind, over the material behind both lines."""
    if angle <= 0.0 or not abs(gap) <= limit:
        return 0.0
    cos, sin = math.cos(angle), math.sin(angle)
    if gap >= 0.0:
        return min(1.0 / sin, JOIN_REACH) * depth
    reach = sin / -cos if cos < 0.0 else JOIN_REACH
    return min(reach, JOIN_REACH) * -gap


@leaf
def within(u, gap, length, slack, angle_start, angle_end, limit):
    """Whether a point at ``u`` along a straight edge of ``length`` (from its start) and ``gap``
    from its line is level with it: its span closed by ``slack``, and held beyond a reflex join's
    end (:func:`beyond`, for gaps and depths up to ``limit``)."""
    return (
        -slack - beyond(angle_start, gap, limit, limit)
        <= u
        <= length + slack + beyond(angle_end, gap, limit, limit)
    )


def _fixed_ends(rows, start, body, poses):
    """(points, rays, normals, owners, rows, columns) of every end of a straight edge of a fixed
    open chain, in world coordinates (``poses``: one per unit)."""
    points, rays, normals, owners, where = [], [], [], [], []
    for u in np.flatnonzero((body[:, FIXED] > 0) & (body[:, CLOSED] == 0)).tolist():
        x, y, th = poses[u]
        c, s = math.cos(th), math.sin(th)
        for r in range(start[u, SEGMENTS], start[u + 1, SEGMENTS]):
            tx, ty = c * rows[r, S_TX] - s * rows[r, S_TY], s * rows[r, S_TX] + c * rows[r, S_TY]
            nx, ny = c * rows[r, S_NX] - s * rows[r, S_NY], s * rows[r, S_NX] + c * rows[r, S_NY]
            ax, ay = x + c * rows[r, X] - s * rows[r, Y], y + s * rows[r, X] + c * rows[r, Y]
            length = rows[r, S_LENGTH]
            for point, ray, column in (
                ((ax, ay), (tx, ty), S_JOIN_START),
                ((ax + length * tx, ay + length * ty), (-tx, -ty), S_JOIN_END),
            ):
                points.append(point)
                rays.append(ray)
                normals.append((nx, ny))
                owners.append(u)
                where.append((r, column))
    return np.array(points).reshape(-1, 2), rays, normals, owners, where


def join_fixed_edges(rows, start, body, owner, poses, radii) -> None:
    """Set the free angle (in ``rows``, in place) at each end of a fixed open chain's straight
    edge that meets an edge of another fixed body at a reflex join (ends within JOIN_EPS of the
    largest such chain's bounding radius; ``radii`` per unit), and hide the chains' end
    vertices there; ``poses`` per unit."""
    points, rays, normals, owners, where = _fixed_ends(rows, start, body, poses)
    if len(points) < 2:
        return
    near = JOIN_EPS * float(np.max(radii[owners]))
    for a, b in sorted(cKDTree(points).query_pairs(max(near, np.finfo(float).tiny))):
        if owner[owners[a]] == owner[owners[b]]:
            continue  # one body's own joins are its tables' (runtime.collide.features)
        angle = free_angle(rays[a], normals[a], rays[b], normals[b])
        if angle > 0.0:
            for k in (a, b):
                r, column = where[k]
                rows[r, column] = max(rows[r, column], angle)
                _hide_corners(rows, start, owners[k], poses[owners[k]], points[k], near)


def _hide_corners(rows, start, unit, pose, point, near) -> None:
    """Hide the unit's corners at ``point`` (a chain's end vertex at a reflex join: as a chain's
    own reflex join, no vertex -- only a corner fits into the join, and the edges hold it)."""
    x, y, th = pose
    c, s = math.cos(th), math.sin(th)
    for r in range(start[unit, CORNERS], start[unit + 1, CORNERS]):
        px, py = x + c * rows[r, X] - s * rows[r, Y], y + s * rows[r, X] + c * rows[r, Y]
        if math.hypot(px - point[0], py - point[1]) <= near:
            rows[r, C_WIDTH] = HIDDEN
