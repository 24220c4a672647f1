"""The sparse assembly of a large island's A (runtime.solve.assembly.island_csr) against the
dense one, and against J W J^T written out from a dense Jacobian (numpy, independent of both)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import sparse

from runtime.solve import assembly


def _island(rng, bodies: int, contacts: int, fixed_share: float):
    jac = rng.normal(size=(contacts + 3, 6))
    body1 = rng.integers(0, bodies, contacts + 3)
    body2 = (body1 + rng.integers(1, bodies, contacts + 3)) % bodies  # never body1
    inv_mass = rng.uniform(0.1, 10.0, size=(bodies, 3))
    fixed = rng.random(bodies) < fixed_share
    return jac, body1, body2, inv_mass, fixed


def _dense_reference(jac, body1, body2, inv_mass, fixed, start, stop):
    n = len(fixed)
    J = np.zeros((stop - start, 3 * n))
    for r, k in enumerate(range(start, stop)):
        J[r, 3 * body1[k] : 3 * body1[k] + 3] += jac[k, :3]
        J[r, 3 * body2[k] : 3 * body2[k] + 3] += jac[k, 3:]
    W = np.where(np.repeat(fixed, 3), 0.0, inv_mass.reshape(-1))
    return J @ (W[:, None] * J.T)


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize(
    ("bodies", "contacts", "fixed_share"), [(2, 5, 0.0), (8, 30, 0.3), (40, 90, 0.1), (5, 12, 1.0)]
)
def test_island_csr_is_the_dense_matrix(seed, bodies, contacts, fixed_share) -> None:
    rng = np.random.default_rng(seed)
    jac, body1, body2, inv_mass, fixed = _island(rng, bodies, contacts, fixed_share)
    start, stop = 2, 2 + contacts  # an island in the middle of the order
    data, indices, indptr = assembly.island_csr(jac, body1, body2, inv_mass, fixed, start, stop)
    A = sparse.csr_array((data, indices, indptr), shape=(contacts, contacts))
    assert A.has_sorted_indices and A.has_canonical_format
    assert np.all(A.diagonal() == A.toarray().diagonal())  # the diagonal is stored, even if 0
    for i in range(contacts):
        assert i in indices[indptr[i] : indptr[i + 1]]
    dense = np.empty((contacts, contacts))
    assembly.island_matrix(jac, body1, body2, inv_mass, fixed, start, stop, dense)
    reference = _dense_reference(jac, body1, body2, inv_mass, fixed, start, stop)
    scale = np.max(np.abs(reference)) if np.any(reference) else 1.0
    np.testing.assert_allclose(A.toarray(), reference, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(A.toarray(), dense, rtol=0, atol=1e-13 * scale)
    # only entries of contacts sharing a moving body are stored
    moving = ~fixed
    share = np.array(
        [
            [
                bool(
                    {body1[start + a], body2[start + a]}
                    & {body1[start + b], body2[start + b]}
                    & set(np.flatnonzero(moving))
                )
                or a == b
                for b in range(contacts)
            ]
            for a in range(contacts)
        ]
    )
    assert np.array_equal(A.toarray() != 0, (A.toarray() != 0) & share)
    assert A.nnz == int(share.sum())
