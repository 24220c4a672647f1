"""Deep overlaps at t = 0, which the contact finder does not report.

The narrow phase (runtime/collide/selection.py) keeps a penetrating contact only if it is plausible
for a simulation step, e.g. no deeper than half the thinner body, so a disc placed with its
centre on a floor, or inside another body, yields no contact at all.  A scene file with such a
mistake must still be refused, so this module samples each body's boundary (corners, points
along every edge, and the centroid of each part where it is material: not a cup's or a
frame's hollow) and asks whether a sample lies inside the material of another body, and how
deep (its exact distance from the boundary, also for an ellipse: runtime/model/regions.py):
inside a closed shape (exact winding number; for a compound body, the deepest in one of its
parts), or behind a fixed wall, bowl or box while the body also reaches in front of it (a
body entirely behind a one-sided wall is not in contact with it).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from runtime.collide.broadphase import candidate_pairs
from runtime.model.regions import edge_distance, winding
from runtime.model.shapes import TAU, Arc, Segment

__all__ = ["deepest_overlap"]

SAMPLES_PER_EDGE = 24


def _world(points: np.ndarray, pose: np.ndarray) -> np.ndarray:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return points @ np.array([[c, s], [-s, c]]) + pose[:2]


def _local(points: np.ndarray, pose: np.ndarray) -> np.ndarray:
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return (points - pose[:2]) @ np.array([[c, -s], [s, c]])


def samples(shape: Any) -> np.ndarray:
    """Points of the shape (body coordinates): corners, points along the edges, and the
    centroid of each part (or of the shape) that lies in its material."""
    pts = [np.asarray(v, dtype=float) for v in shape.vertices]
    t = np.linspace(0.0, 1.0, SAMPLES_PER_EDGE)
    for e in shape.edges:
        if isinstance(e, Segment):
            a, b = np.asarray(e.start), np.asarray(e.end)
            pts.extend(a + np.outer(t, b - a))
        elif isinstance(e, Arc):
            pts.extend(np.array(e.point(a)) for a in e.start_angle + t * e.span)
        else:
            pts.extend(np.array(e.point(a)) for a in np.linspace(0, TAU, 4 * SAMPLES_PER_EDGE))
    if shape.closed:
        for part in shape.parts or (shape,):
            centroid = np.asarray(part.centroid, dtype=float)
            if winding(part, centroid)[0] != 0:
                pts.append(centroid)
    return np.array(pts, dtype=float).reshape(-1, 2)


def _depth_closed(shape: Any, p: np.ndarray) -> np.ndarray:
    """How deep the points are inside the shape: the depth in the part they are in (a lower
    bound of the depth in a compound, whose parts' shared sides are inside it)."""
    depth = np.zeros(len(p))
    for part in shape.parts or (shape,):
        inside = winding(part, p) != 0
        if inside.any():
            nearest = np.min([edge_distance(e, p) for e in part.edges], axis=0)
            depth = np.maximum(depth, np.where(inside, nearest, 0.0))
    return depth


def _behind(e: Any, p: np.ndarray) -> np.ndarray:
    """How far the points are behind an edge of an open chain (into its material), NaN where
    they are not level with the edge."""
    if isinstance(e, Segment):
        a, n = np.asarray(e.start), np.asarray(e.normal)
        u = np.asarray(e.end) - a
        t = (p - a) @ u / float(u @ u)
        return np.where((t >= 0) & (t <= 1), -(p - a) @ n, np.nan)
    v = p - np.asarray(e.centre)
    on_span = np.array([e.contains_angle(a) for a in np.arctan2(v[:, 1], v[:, 0])], dtype=bool)
    out = np.hypot(*v.T) - abs(e.radius)
    return np.where(on_span, -out if e.convex else out, np.nan)


def _depth_open(shape: Any, p: np.ndarray) -> np.ndarray:
    depth = np.zeros(len(p))
    for e in shape.edges:
        behind = _behind(e, p)
        if np.nanmin(behind, initial=np.inf) < 0:  # the body reaches in front of this edge
            depth = np.maximum(depth, np.nan_to_num(behind, nan=0.0))
    return depth


def deepest_overlap(
    shapes: list[Any],
    poses: np.ndarray,
    fixed: list[bool],
    tolerance: float,
    apart: Sequence[tuple[int, int]] = (),
) -> tuple[int, int, float, tuple[float, float]] | None:
    """The first pair ``(i, j, depth, world point)`` where a sample point of body ``i`` lies
    more than ``tolerance`` inside body ``j`` (the deepest such point), or None; pairs
    ``apart`` (i < j: bodies a joint links, which never touch) are not checked."""
    skip = set(apart)
    radii = np.array([float(s.bounding_radius) for s in shapes])
    centres = np.asarray(poses, dtype=float)[:, :2]
    first, second = candidate_pairs(centres, radii, np.asarray(fixed, dtype=bool), tolerance)
    cache: dict[int, np.ndarray] = {}
    for a, b in zip(first.tolist(), second.tolist(), strict=True):
        if (a, b) in skip:
            continue
        for i, j in ((a, b), (b, a)):
            if i not in cache:
                cache[i] = _world(samples(shapes[i]), poses[i])
            local = _local(cache[i], poses[j])
            with np.errstate(all="ignore"):
                closed = shapes[j].closed
                depth = _depth_closed(shapes[j], local) if closed else _depth_open(shapes[j], local)
            k = int(np.argmax(depth))
            if depth[k] > tolerance:
                return i, j, float(depth[k]), (float(cache[i][k, 0]), float(cache[i][k, 1]))
    return None
