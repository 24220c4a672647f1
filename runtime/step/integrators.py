"""Fixed-step explicit integrators (Euler, midpoint, classic RK4) on y = (poses, velocities).

`rhs(y)` returns dy/dt; the contact forces are re-solved inside it at every stage. The adaptive
method is scipy.integrate.solve_ivp (RK45, DOP853), driven from runtime.step.simulation.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

Rhs = Callable[[np.ndarray], np.ndarray]


def euler(rhs: Rhs, y: np.ndarray, dt: float, k1: np.ndarray | None = None) -> np.ndarray:
    return y + dt * (rhs(y) if k1 is None else k1)


def midpoint(rhs: Rhs, y: np.ndarray, dt: float, k1: np.ndarray | None = None) -> np.ndarray:
    k1 = rhs(y) if k1 is None else k1
    return y + dt * rhs(y + 0.5 * dt * k1)


def rk4(rhs: Rhs, y: np.ndarray, dt: float, k1: np.ndarray | None = None) -> np.ndarray:
    """Classic RK4; `k1` = rhs(y) when the caller has it already (saves one contact solve)."""
    k1 = rhs(y) if k1 is None else k1
    k2 = rhs(y + 0.5 * dt * k1)
    k3 = rhs(y + 0.5 * dt * k2)
    k4 = rhs(y + dt * k3)
    return y + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


FIXED_STEP = {"euler": euler, "midpoint": midpoint, "rk4": rk4}
ADAPTIVE = {"rk45": "RK45", "dop853": "DOP853"}
METHODS = tuple(FIXED_STEP) + tuple(ADAPTIVE)
