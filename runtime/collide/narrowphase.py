"""Narrow phase, candidate stage (compiled): the feature pairs of bodies that may touch.

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

Here: the broad phase, the features turned to world axes, and per pair the corner helpers
(runtime.collide.corners) and the curve helpers (runtime.collide.curves), which write rows of
the candidate table (runtime.collide.candidates), contiguous per pair, pairs sorted.
"""

from __future__ import annotations

import math

import numpy as np

from runtime.collide import ovals
from runtime.collide.broadphase import sweep, sweep_groups
from runtime.collide.candidates import BODY1, BODY2, CASE, G, PairContext
from runtime.collide.corners import corner_on_corner, corners_on_edges
from runtime.collide.curves import curves_on_curves, curves_on_segments
from runtime.collide.features import (
    A_START,
    ARCS,
    CLOSED,
    CORNERS,
    ELLIPSES,
    ENDS,
    FIXED,
    RADIUS,
    SEGMENTS,
)
from runtime.compiled import leaf, njit
from runtime.settings import SCREEN_SLACK


@leaf
def _has(start, b, kind):
    return start[b + 1, kind] > start[b, kind]


@leaf
def _pair(rows, start, world, cand, k, ctx, i, j, i_first):
    """The candidates of bodies i < j, appended from row k; returns the new count."""
    for side in range(2):
        b1, b2 = (i, j) if side == 0 else (j, i)
        if _has(start, b1, CORNERS) or _has(start, b1, ENDS):
            k = corners_on_edges(rows, start, world, cand, k, ctx, b1, b2)
        curves = _has(start, b1, ARCS) or _has(start, b1, ELLIPSES)
        if curves and _has(start, b2, SEGMENTS):
            k = curves_on_segments(rows, start, world, cand, k, ctx, b1, b2)
    curves_i = _has(start, i, ARCS) or _has(start, i, ELLIPSES)
    if curves_i and (_has(start, j, ARCS) or _has(start, j, ELLIPSES)):
        k = curves_on_curves(rows, start, world, cand, k, ctx, i, j, i_first)
    if _has(start, i, CORNERS) and _has(start, j, CORNERS):
        one, two = (i, j) if i_first else (j, i)
        k = corner_on_corner(rows, start, world, cand, k, ctx, one, two)
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
def _by_body(pairs, owner):
    """The pairs of units of different bodies, sorted by their bodies' pair (stable), and the
    number of that body pair for each."""
    keep = owner[pairs[:, 0]] != owner[pairs[:, 1]]
    pairs = pairs[keep]
    key = owner[pairs[:, 0]] * (owner[-1] + 1) + owner[pairs[:, 1]]
    order = np.argsort(key, kind="mergesort")
    pairs, key = pairs[order], key[order]
    number = np.zeros(len(pairs))
    for p in range(1, len(pairs)):
        number[p] = number[p - 1] + (key[p] != key[p - 1])
    return pairs, number


@njit
def _kept_apart(apart, a, b, n):
    """Whether bodies a and b (of n) are a pair of the sorted codes ``apart``."""
    code = min(a, b) * n + max(a, b)
    k = np.searchsorted(apart, code)
    return k < apart.size and apart[k] == code


@njit
def find_candidates(
    poses, base, margins, allowed, groups, apart, rows, start, body, owner, compound, cand,
    kernel_inputs,
):  # fmt: skip
    """Broad phase, then the candidates of every pair of ``allowed`` units (of one collision
    group, or one of group -1, if ``groups`` is not empty: runtime.collide.broadphase) into
    ``cand`` (a row per candidate, runtime.collide.candidates.COLUMNS) and the
    ``kernel_inputs`` (:func:`_kernel_inputs`).  A unit is a body or a part of a compound body
    (``owner``: the body of each; ``poses``, ``margins``, ``allowed``, ``groups``: per unit,
    those of its body); pairs of bodies whose code min * n + max is in ``apart`` (sorted) are
    skipped (bodies a joint links); with ``compound``, pairs of one body's parts are skipped and the
    candidates are grouped by the pair of bodies (their PAIR column).  Returns their number
    (more than ``cand`` holds: grow it and call again), or -1 - u if the pose or margin of
    unit u is not finite."""
    n = len(poses)
    for b in range(n):
        if not (np.isfinite(poses[b, 0]) and np.isfinite(poses[b, 1]) and np.isfinite(poses[b, 2])):
            return -1 - b
        if not np.isfinite(margins[b]):
            return -1 - b
    reach = np.empty(n)
    for b in range(n):
        reach[b] = body[b, RADIUS] + 0.5 * max(base, 0.0) + max(margins[b], 0.0)
    x, y, fixed = poses[:, 0].copy(), poses[:, 1].copy(), body[:, FIXED] > 0
    if groups.size == 0:
        pairs = sweep(x, y, reach, fixed)
    else:
        pairs = sweep_groups(x, y, reach, fixed, groups)
    number = np.arange(len(pairs)).astype(np.float64)
    if compound:
        pairs, number = _by_body(pairs, owner)
    world = _world(rows, start, poses)
    k = 0
    for p in range(len(pairs)):
        i, j = pairs[p, 0], pairs[p, 1]
        if not (allowed[i] and allowed[j]):
            continue
        if apart.size and _kept_apart(apart, owner[i], owner[j], owner[-1] + 1):
            continue
        slack = SCREEN_SLACK * (body[i, RADIUS] + body[j, RADIUS])
        oix, oiy = poses[i, 0] - poses[j, 0], poses[i, 1] - poses[j, 1]
        ctx = PairContext(
            base + margins[i] + margins[j] + slack,
            slack,
            float(i),
            float(j),
            oix,
            oiy,
            number[p],
            poses[i, 2],
            poses[j, 2],
            body[i, CLOSED],
            body[j, CLOSED],
        )
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
