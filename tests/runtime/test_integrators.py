"""The general path's fixed-step integrators (runtime.step.integrators: Euler, midpoint, RK4)
converge at their orders on harmonic oscillators, against the closed form q = q0 cos(wt) +
(v0/w) sin(wt).

Why: the engine's scenes step through the compiled stages (runtime.step.compiled_stages), so
these Python integrators run only where the compiled path cannot (friction, joints, ovals,
stabilisation): a wrong stage or weight there passed every engine test of the fixed-step
methods (the integrators: mutants of bench/mutants.py). tests/runtime/test_arcs.py checks the
same orders through the engine, on either path.
"""

from __future__ import annotations

import numpy as np
import pytest

from runtime.step.integrators import FIXED_STEP

OMEGA = np.array([[1.0, 2.0, 0.5], [1.5, 0.7, 3.0]])  # one frequency per coordinate
Q0 = np.array([[0.3, -0.2, 1.0], [0.0, 0.5, -0.4]])
V0 = np.array([[1.0, 0.4, 0.0], [-0.6, 0.0, 0.9]])


def _rhs(q: np.ndarray, v: np.ndarray) -> np.ndarray:
    return -(OMEGA**2) * q


def _exact(t: float) -> tuple[np.ndarray, np.ndarray]:
    c, s = np.cos(OMEGA * t), np.sin(OMEGA * t)
    return Q0 * c + V0 / OMEGA * s, -Q0 * OMEGA * s + V0 * c


def _error(method: str, steps: int, duration: float = 1.0) -> float:
    q, v, h = Q0.copy(), V0.copy(), duration / steps
    for _ in range(steps):
        q, v = FIXED_STEP[method](_rhs, q, v, h, _rhs(q, v))
    q_exact, v_exact = _exact(duration)
    return float(max(np.max(np.abs(q - q_exact)), np.max(np.abs(v - v_exact))))


@pytest.mark.parametrize(("method", "order"), [("euler", 1), ("midpoint", 2), ("rk4", 4)])
def test_fixed_step_methods_converge_at_their_order(method, order):
    errors = np.array([_error(method, n) for n in (40, 80, 160)])
    observed = np.log2(errors[:-1] / errors[1:])
    assert np.all(np.abs(observed - order) < 0.1), (method, errors, observed)
