"""The press of runtime.step.resting: velocities projected onto those that keep an island at rest.

Reference, written apart from the code under test: in u = M^1/2 v the resting velocities are the
null space of B = J M^-1/2 (scipy.linalg.null_space), and the press is the orthogonal projection
onto it, u' = N N^T u -- the least change of kinetic energy that stops every contact.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import null_space

from runtime.step.resting import project_island


def _island(rng, bodies: int, contacts: int, mechanism: float):
    """Random rows between random pairs (body 0 fixed), with one row a combination of two
    others plus ``mechanism`` of noise (0: exactly dependent, a redundant contact)."""
    inv_mass = np.column_stack(
        [1 / rng.uniform(0.5, 2, bodies)] * 2 + [1 / rng.uniform(0.01, 0.1, bodies)]
    )
    fixed = np.zeros(bodies, bool)
    fixed[0] = True
    inv_mass[0] = 0.0
    body1 = rng.integers(1, bodies, contacts)
    body2 = (body1 + rng.integers(1, bodies - 1, contacts)) % bodies
    jac = rng.normal(size=(contacts, 6))
    body1[-1], body2[-1] = body1[0], body2[0]  # the last row leans on the first
    jac[-1] = 0.7 * jac[0] + mechanism * rng.normal(size=6)
    return jac, body1, body2, inv_mass, fixed


def _matrix(jac, body1, body2, inv_mass, fixed):
    """B = J M^-1/2 over all bodies' coordinates (fixed ones: zero columns)."""
    n = len(fixed)
    B = np.zeros((len(jac), 3 * n))
    for k, (i, j) in enumerate(zip(body1, body2, strict=True)):
        B[k, 3 * i : 3 * i + 3] += jac[k, :3] * np.sqrt(inv_mass[i])
        B[k, 3 * j : 3 * j + 3] += jac[k, 3:] * np.sqrt(inv_mass[j])
    return B


@pytest.mark.parametrize("mechanism", [0.0, 1e-7, 1.0])
@pytest.mark.parametrize("seed", range(5))
def test_a_press_is_the_projection_onto_rest(seed: int, mechanism: float) -> None:
    rng = np.random.default_rng(seed)
    jac, body1, body2, inv_mass, fixed = _island(rng, 6, 9, mechanism)
    v = rng.normal(size=(6, 3))
    v[fixed] = 0.0
    rate = np.einsum("kc,kc->k", jac[:, :3], v[body1]) + np.einsum("kc,kc->k", jac[:, 3:], v[body2])
    p, dv = np.zeros(len(rate)), np.zeros_like(v)
    assert project_island(jac, body1, body2, inv_mass, fixed, rate, p, dv)
    B = _matrix(jac, body1, body2, inv_mass, fixed)
    w = inv_mass.ravel()
    scale = np.sqrt(np.divide(1.0, w, out=np.zeros_like(w), where=w > 0))  # M^1/2
    u = scale * v.ravel()
    N = null_space(B, rcond=1e-12)
    expected = (N @ (N.T @ u)) / np.where(scale > 0, scale, 1.0)
    after = v + dv
    # the projector onto a null space is known to rounding / its gap (the smallest kept
    # singular value relative to the largest): ~1e-9 next to a near-mechanism of 1e-7
    sv = np.linalg.svd(B, compute_uv=False)
    gap = np.min(sv[sv > 1e-12 * sv[0]]) / sv[0]
    bound = 64 * np.finfo(float).eps / gap * np.max(np.abs(v))
    assert np.max(np.abs(after.ravel() - expected)) <= bound
    assert np.max(np.abs(B @ (scale * after.ravel()))) <= 1e-12 * np.max(np.abs(rate))
    assert np.all(dv[fixed] == 0.0)
    energy = lambda w: 0.5 * np.sum((scale * w.ravel()) ** 2)  # noqa: E731
    assert energy(after) <= energy(v)
    # the impulses make the same change where they are well determined (no near-mechanism)
    if mechanism == 1.0:
        made = np.zeros_like(v)
        for k, (i, j) in enumerate(zip(body1, body2, strict=True)):
            made[i] += inv_mass[i] * jac[k, :3] * p[k]
            made[j] += inv_mass[j] * jac[k, 3:] * p[k]
        made[fixed] = 0.0
        assert np.max(np.abs(made - dv)) <= 1e-10 * np.max(np.abs(dv))
