"""Broad phase: the pairs of bodies whose bounding circles come within reach, by sort and sweep.

Why: the narrow phase costs per pair of bodies, and in a pile almost every pair is far apart.
Each body's bounding circle (about its centre of mass) is widened by its reach (half the
pair tolerance plus its own margin); the circles are sorted by their lower end along the axis
on which the centres spread most and swept, so the cost is about linear in the number of
bodies plus pairs.  Pairs of two fixed bodies are skipped (they never move).
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
    pairs = pairs[:count]
    return pairs[np.argsort(pairs[:, 0] * n + pairs[:, 1])]


def candidate_pairs(
    centres: np.ndarray, radii: np.ndarray, fixed: np.ndarray, margin: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Index arrays ``(I, J)``, ``I < J``, sorted, of the pairs whose circles (``centres``,
    ``radii``) are at most ``margin`` apart, skipping pairs of two fixed bodies."""
    c = np.ascontiguousarray(centres, dtype=float).reshape(-1, 2)
    reach = np.asarray(radii, dtype=float) + 0.5 * max(float(margin), 0.0)
    pairs = sweep(c[:, 0].copy(), c[:, 1].copy(), reach, np.asarray(fixed, dtype=np.bool_))
    return pairs[:, 0].copy(), pairs[:, 1].copy()
