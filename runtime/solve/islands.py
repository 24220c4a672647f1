"""Islands: groups of moving bodies joined by contacts (fixed bodies join nothing).

Why: bodies in different islands cannot push each other, so the contact forces are solved per
island (A is block diagonal: small dense problems instead of one large one), and an impact in
one island is located and resolved by sub-stepping only that island, not the whole scene. For
the events, the contacts that join bodies are all contacts that can close within the step (the
swept search), so nothing outside an island can reach it during the step.
"""

from __future__ import annotations

import numpy as np

from runtime.compiled import njit


@njit
def _find(parent: np.ndarray, i: int) -> int:
    root = i
    while parent[root] != root:
        root = parent[root]
    while parent[i] != root:  # path compression
        parent[i], i = root, parent[i]
    return root


@njit
def _labels(n: int, body1: np.ndarray, body2: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    parent = np.arange(n)
    for k in range(body1.size):
        i, j = body1[k], body2[k]
        if fixed[i] or fixed[j]:
            continue
        a, b = _find(parent, i), _find(parent, j)
        if a != b:
            if a < b:
                parent[b] = a
            else:
                parent[a] = b
    labels = np.empty(n, np.int64)
    for i in range(n):
        labels[i] = _find(parent, i)
    return labels


def body_islands(n: int, body1: np.ndarray, body2: np.ndarray, fixed: np.ndarray) -> np.ndarray:
    """(n,) island label of each body: the smallest body index in its island. A fixed body is
    its own island (it joins no one)."""
    return _labels(n, np.asarray(body1, np.int64), np.asarray(body2, np.int64), fixed)


def contact_islands(
    body_label: np.ndarray, body1: np.ndarray, body2: np.ndarray, fixed: np.ndarray
) -> np.ndarray:
    """(m,) island label of each contact: that of its moving body (body 1 unless it is fixed)."""
    return np.where(fixed[body1], body_label[body2], body_label[body1])


def grouped(labels: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(order, offsets): ``order`` sorts the items by label (stably), and the items of group g
    are ``order[offsets[g]:offsets[g + 1]]``."""
    order = np.argsort(labels, kind="stable")
    if labels.size == 0:
        return order, np.zeros(1, np.int64)
    sorted_labels = labels[order]
    offsets = np.flatnonzero(sorted_labels[1:] != sorted_labels[:-1]) + 1
    return order, np.concatenate(([0], offsets, [labels.size])).astype(np.int64)
