"""Narrow phase, selection stage (compiled): which candidates are contacts, with kernel gaps.

Why: the candidate stage (runtime.collide.narrowphase) chose features by geometric distances;
here the generated kernels' gaps decide, per pair of bodies:

- a candidate is a contact if its gap is at most the pair's tolerance (base + both margins);
- a penetrating one (gap < 0) only if plausible: no deeper than half the thinner body (the
  thinner part, for compound bodies, whose units are their parts); a smooth
  end at most CONE_SLACK beyond its arc; a vertex in a closed body 2 inside it (its way out not
  positive) and not much deeper than its shallowest way out (WAY_OUT_MARGIN), unless nothing
  better describes the overlap: implausible candidates go only if the pair has a plausible
  penetration -- but never where the way out is 0 within rounding: a vertex on body 2's
  boundary is not inside it (a half disc's corner on a box's side, 1e-13 outside, was a
  contact 0.01 deep against the box's top);
- against a closed body, a body-1 feature with a contact at a larger gap loses its penetrating
  ones (only its shallowest stays);
- one constraint reported twice (from both bodies: two corners meeting; or from two parts of
  a compound body: a disc on the join of two flush sides; the same mid-point and gap within
  DUPLICATE_EPS, parallel normals) is kept once.

The candidates come grouped by pair of bodies (runtime.collide.narrowphase), so these rules
see all the contacts of two compound bodies together; "body" in them is a unit: a body or a
part of a compound body.

The kept candidates, in their order, become the arrays of
:class:`~runtime.collide.contact_set.Contacts` (points in world coordinates).
"""

from __future__ import annotations

import numpy as np

from runtime.collide.candidates import (
    CASE,
    END_ANGLE,
    INDEX1,
    KIND1,
    NX,
    NY,
    PAIR,
    PX,
    PY,
    VERTEX_CIRCLE,
    VERTEX_EDGE,
    WAY_OUT,
    G,
)
from runtime.collide.contact_set import END
from runtime.collide.features import CLOSED, HALF_WIDTH, RADIUS
from runtime.compiled import leaf, njit
from runtime.settings import (
    CONE_SLACK,
    DUPLICATE_EPS,
    INSIDE_EPS,
    PARALLEL_EPS,
    WAY_OUT_MARGIN,
)


@leaf
def _admit(k, gap, tol, body, body1, body2, cand, plausible):
    """Whether candidate k is a contact at its kernel gap (sets ``plausible[k]``)."""
    g = gap[k]
    plausible[k] = True
    if not g <= tol:
        return False
    if g >= 0.0:
        return True
    depth = min(body[body1[k], HALF_WIDTH], body[body2[k], HALF_WIDTH])
    if -g > depth or (cand[k, KIND1] == END and cand[k, END_ANGLE] > CONE_SLACK):
        return False
    b2 = body2[k]
    vertex = cand[k, CASE] == VERTEX_EDGE or cand[k, CASE] == VERTEX_CIRCLE
    if vertex and body[b2, CLOSED] > 0:
        out, rounding = cand[k, WAY_OUT], INSIDE_EPS * body[b2, HALF_WIDTH]
        if out > rounding:
            return False
        plausible[k] = g >= out - WAY_OUT_MARGIN * depth
        if not plausible[k] and out >= -rounding:
            return False  # a vertex on body 2's boundary: no depth beyond its way out
    return True


@leaf
def _select_pair(k0, k1, keep, plausible, admitted, gap, tol, eps, body, body1, body2, cand):
    """Set ``keep`` for the candidates k0 <= k < k1 of one pair (``admitted``: scratch)."""
    deep = False
    for k in range(k0, k1):
        keep[k] = _admit(k, gap, tol, body, body1, body2, cand, plausible)
        deep |= keep[k] and plausible[k] and gap[k] < 0.0
    alive = 0
    for k in range(k0, k1):
        keep[k] = keep[k] and (plausible[k] or not deep)
        alive += keep[k]
    if alive < 2:
        return
    for k in range(k0, k1):
        admitted[k] = keep[k]
    for k in range(k0, k1):  # against a closed body only the shallowest per body-1 feature
        if not keep[k] or gap[k] >= 0.0 or body[body2[k], CLOSED] == 0:
            continue
        for m in range(k0, k1):
            same = body1[m] == body1[k] and body2[m] == body2[k]
            same = same and cand[m, KIND1] == cand[k, KIND1] and cand[m, INDEX1] == cand[k, INDEX1]
            if admitted[m] and same and gap[m] > gap[k]:
                keep[k] = False
                break
    for k in range(k0, k1):  # one constraint seen from both bodies
        if not keep[k]:
            continue
        g, nx, ny = gap[k], cand[k, NX], cand[k, NY]
        mx, my = cand[k, PX] - 0.5 * g * nx, cand[k, PY] - 0.5 * g * ny
        for m in range(k0, k):
            if not keep[m]:
                continue
            h, kx, ky = gap[m], cand[m, NX], cand[m, NY]
            near = abs(mx - cand[m, PX] + 0.5 * h * kx) <= eps
            near = near and abs(my - cand[m, PY] + 0.5 * h * ky) <= eps
            if near and abs(g - h) <= eps and abs(nx * kx + ny * ky) >= 1.0 - PARALLEL_EPS:
                keep[k] = False
                break


@njit
def select(poses, base, margins, body, cand, count, body1, body2, gap, out):
    """Keep the contacts among the first ``count`` candidates ``cand`` (bodies ``body1``,
    ``body2``) at kernel gaps ``gap``: their rows go, in order, to the front of the arrays
    ``out`` = (case, body1, body2, geometry, feature, point, normal) and of ``gap``.  Returns
    their number."""
    keep, plausible = np.zeros(count, dtype=np.bool_), np.ones(count, dtype=np.bool_)
    admitted = np.zeros(count, dtype=np.bool_)
    k0 = 0
    while k0 < count:
        k1 = k0 + 1
        while k1 < count and cand[k1, PAIR] == cand[k0, PAIR]:
            k1 += 1
        i, j = body1[k0], body2[k0]
        tol = base + margins[i] + margins[j]
        eps = DUPLICATE_EPS * (body[i, RADIUS] + body[j, RADIUS])
        _select_pair(k0, k1, keep, plausible, admitted, gap, tol, eps, body, body1, body2, cand)
        k0 = k1
    return _write(poses, cand, count, keep, body1, body2, gap, *out)


@leaf
def _write(
    poses, cand, count, keep, body1, body2, gap, case, one, two, geometry, feature, point, normal
):
    """Write the kept candidates to the front of the output arrays; returns how many."""
    m = 0
    for k in range(count):
        if not keep[k]:
            continue
        j = max(body1[k], body2[k])
        case[m], one[m], two[m], gap[m] = cand[k, CASE], body1[k], body2[k], gap[k]
        for c in range(7):
            geometry[m, c] = cand[k, G + c]
        for c in range(4):
            feature[m, c] = cand[k, KIND1 + c]
        point[m, 0], point[m, 1] = cand[k, PX] + poses[j, 0], cand[k, PY] + poses[j, 1]
        normal[m, 0], normal[m, 1] = cand[k, NX], cand[k, NY]
        m += 1
    return m
