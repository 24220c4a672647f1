"""The compiled reverse Cuthill-McKee order (runtime.solve.lcp_envelope.reverse_cuthill_mckee).

References: scipy's reverse_cuthill_mckee (scipy.sparse.csgraph), an implementation apart from
ours, for the envelope it leaves; and exact properties of two patterns: a path in any numbering
gets bandwidth 1, and every node of every connected part appears once.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from lcp_oracle import packed_pile
from scipy.sparse.csgraph import reverse_cuthill_mckee as scipy_order

from runtime.solve.lcp_envelope import reverse_cuthill_mckee


def _pattern(matrix) -> sp.csr_array:
    s = sp.csr_array(matrix, dtype=float)
    s.sort_indices()
    return s


def _order(s: sp.csr_array) -> np.ndarray:
    return reverse_cuthill_mckee(s.indptr.astype(np.int64), s.indices.astype(np.int64))


def _envelope(s: sp.csr_array, order: np.ndarray) -> int:
    """Entries of the lower envelope in this order: sum over rows of (row - first column)."""
    p = s[order][:, order].tocoo()
    first = np.arange(s.shape[0])
    np.minimum.at(first, p.row, p.col)
    return int((np.arange(s.shape[0]) - first).sum())


def _geometric(seed: int, n: int, reach: float) -> sp.csr_array:
    """Points in the unit square joined when closer than ``reach``: several parts, some
    isolated points, like a scene's islands."""
    rng = np.random.default_rng(seed)
    x = rng.random((n, 2))
    near = np.linalg.norm(x[:, None] - x[None], axis=2) < reach
    return _pattern(near)


def test_a_shuffled_path_gets_bandwidth_one() -> None:
    n = 200
    label = np.random.default_rng(5).permutation(n)
    path = sp.lil_array((n, n))
    for k in range(n - 1):
        path[label[k], label[k + 1]] = path[label[k + 1], label[k]] = 1.0
    s = _pattern(path + sp.eye_array(n))
    order = _order(s)
    position = np.empty(n, np.int64)
    position[order] = np.arange(n)
    coo = s.tocoo()
    assert np.abs(position[coo.row] - position[coo.col]).max() == 1


@pytest.mark.parametrize("seed", range(6))
def test_random_parts_get_a_permutation_with_scipys_envelope(seed: int) -> None:
    """Every node once, and an envelope within 10 % of scipy's order of the same pattern (the
    two differ only in how they break ties and pick each part's first node)."""
    s = _geometric(seed, 300, 0.07)
    order = _order(s)
    assert np.array_equal(np.sort(order), np.arange(300))
    ours, theirs = _envelope(s, order), _envelope(s, scipy_order(s, symmetric_mode=True))
    assert ours <= 1.1 * theirs
    assert ours < 0.2 * _envelope(s, np.arange(300))  # and far below no ordering at all


def test_a_pile_s_body_space_matrix() -> None:
    """K = J^T J of the packed pile (the matrix runtime.solve.lcp_loaded factors): within 10 %
    of scipy's envelope, with the unused (rotation) columns placed too."""
    _, _, J, _ = packed_pile(10, 6)
    s = _pattern(np.abs(J.T) @ np.abs(J) > 0)
    order = _order(s)
    assert np.array_equal(np.sort(order), np.arange(J.shape[1]))
    assert _envelope(s, order) <= 1.1 * _envelope(s, scipy_order(s, symmetric_mode=True))
