"""Broad phase: the pairs of bodies whose bounding circles come within reach, by sort and sweep.

Why: the narrow phase costs per pair of bodies, and in a pile almost every pair is far apart.
Each body's bounding circle (about its centre of mass) is widened by its reach (half the
pair tolerance plus its own margin); the circles are sorted by their lower end along the axis
on which the centres spread most and swept, so the cost is about linear in the number of
bodies plus pairs.  Pairs of two fixed bodies are skipped (they never move).

Collision groups (:func:`sweep_groups`): bodies of different groups never touch, as the copies
of one scene stepped together as an ensemble (runtime.step.ensemble); group -1 touches every
group (a fixed body the copies share).  The circles are swept group by group, so copies laid on
top of each other cost what copies side by side do.
"""

from __future__ import annotations

import numpy as np

from runtime.compiled import leaf, njit


@leaf
def _overlaps(a, c, r, f, order, pairs):
    """Sweep the circles sorted by lower end (along-axis centre a, across-axis centre c,
    radius r, fixed f); write the overlapping pairs (original indices, i < j) into ``pairs``
    while there is room.  Returns their number."""
    n, count = len(a), 0
    for p in range(n):
        for q in range(p + 1, n):
            if a[q] - r[q] > a[p] + r[p]:
                break
            da, dc, rr = a[p] - a[q], c[p] - c[q], r[p] + r[q]
            if da * da + dc * dc <= rr * rr and not (f[p] and f[q]):
                if count < len(pairs):
                    i, j = order[p], order[q]
                    pairs[count, 0], pairs[count, 1] = min(i, j), max(i, j)
                count += 1
    return count


@njit
def sweep(x, y, reach, fixed):
    """(P, 2) int64 pairs (i < j), sorted, of the circles (centres x, y; radii ``reach``) that
    overlap or touch, without pairs of two fixed bodies."""
    n = len(reach)
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64)
    along, across = (x, y) if np.ptp(x) >= np.ptp(y) else (y, x)
    order = np.argsort(along - reach, kind="mergesort")
    a, c, r, f = along[order], across[order], reach[order], fixed[order]  # contiguous, sorted
    pairs = np.empty((4 * n, 2), dtype=np.int64)
    count = _overlaps(a, c, r, f, order, pairs)
    if count > len(pairs):
        pairs = np.empty((count, 2), dtype=np.int64)
        _overlaps(a, c, r, f, order, pairs)
    return _sorted_pairs(pairs[:count], n)


@leaf
def _overlaps_grouped(a, c, r, f, g, order, pairs):
    """:func:`_overlaps` for circles sorted by group, then by lower end (group g, -1 first):
    the sweep stops at the end of a group, and each circle of group -1 is tried against every
    circle of the other groups."""
    n, count = len(a), 0
    for p in range(n):
        for q in range(p + 1, n):
            if g[q] != g[p] or a[q] - r[q] > a[p] + r[p]:
                break
            da, dc, rr = a[p] - a[q], c[p] - c[q], r[p] + r[q]
            if da * da + dc * dc <= rr * rr and not (f[p] and f[q]):
                if count < len(pairs):
                    i, j = order[p], order[q]
                    pairs[count, 0], pairs[count, 1] = min(i, j), max(i, j)
                count += 1
    shared = 0
    while shared < n and g[shared] == -1:
        shared += 1
    for p in range(shared):
        for q in range(shared, n):
            da, dc, rr = a[p] - a[q], c[p] - c[q], r[p] + r[q]
            if da * da + dc * dc <= rr * rr and not (f[p] and f[q]):
                if count < len(pairs):
                    i, j = order[p], order[q]
                    pairs[count, 0], pairs[count, 1] = min(i, j), max(i, j)
                count += 1
    return count


@njit
def sweep_groups(x, y, reach, fixed, groups):
    """:func:`sweep` with a collision group per circle (int64 >= -1): only pairs of one group,
    or with a circle of group -1, are reported."""
    n = len(reach)
    if n < 2:
        return np.zeros((0, 2), dtype=np.int64)
    along, across = (x, y) if np.ptp(x) >= np.ptp(y) else (y, x)
    order = _by_group(groups, np.argsort(along - reach, kind="mergesort"))
    a, c, r, f, g = along[order], across[order], reach[order], fixed[order], groups[order]
    pairs = np.empty((4 * n, 2), dtype=np.int64)
    count = _overlaps_grouped(a, c, r, f, g, order, pairs)
    if count > len(pairs):
        pairs = np.empty((count, 2), dtype=np.int64)
        _overlaps_grouped(a, c, r, f, g, order, pairs)
    return _sorted_pairs(pairs[:count], n)


@njit
def _by_group(groups, by_end):
    """``by_end`` (body indices) reordered stably by group, -1 first: a counting sort,
    O(n + groups), where the groups are numbered densely (an ensemble's copies: 10,000 groups
    took 0.27 ms to sort), else a merge sort."""
    n = by_end.size
    top = groups.max()
    if top > 4 * n:
        return by_end[np.argsort(groups[by_end], kind="mergesort")]
    start = np.zeros(top + 3, np.int64)  # start[g + 1]: where group g begins
    for k in range(n):
        start[groups[k] + 2] += 1
    for g in range(1, top + 3):
        start[g] += start[g - 1]
    out = np.empty(n, np.int64)
    for body in by_end:
        g = groups[body] + 1
        out[start[g]] = body
        start[g] += 1
    return out


@njit
def _sorted_pairs(pairs, n):
    """``pairs`` (i < j) sorted by (i, j); a pass, without the sort, when they are already."""
    code = pairs[:, 0] * n + pairs[:, 1]
    for k in range(1, code.size):
        if code[k] < code[k - 1]:
            return pairs[np.argsort(code)]
    return pairs


def candidate_pairs(
    centres: np.ndarray,
    radii: np.ndarray,
    fixed: np.ndarray,
    margin: float = 0.0,
    groups: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Index arrays ``(I, J)``, ``I < J``, sorted, of the pairs whose circles (``centres``,
    ``radii``) are at most ``margin`` apart, skipping pairs of two fixed bodies (and, given
    ``groups``, pairs of two different groups neither of which is -1)."""
    c = np.ascontiguousarray(centres, dtype=float).reshape(-1, 2)
    reach = np.asarray(radii, dtype=float) + 0.5 * max(float(margin), 0.0)
    flags = np.asarray(fixed, dtype=np.bool_)
    if groups is None:
        pairs = sweep(c[:, 0].copy(), c[:, 1].copy(), reach, flags)
    else:
        g = np.ascontiguousarray(groups, dtype=np.int64)
        pairs = sweep_groups(c[:, 0].copy(), c[:, 1].copy(), reach, flags, g)
    return pairs[:, 0].copy(), pairs[:, 1].copy()
