"""Integrators (Euler, midpoint, classic RK4; scipy's RK45 and DOP853) and the trajectory of a
trial step.

The state is (poses, velocities), (n, 3) arrays each; ``rhs(poses, velocities)`` returns the
accelerations, with the contact forces of the resting set solved again at every stage. A
:class:`Trajectory` is t -> state after integrating t (0 < t <= h) from the step's start with one
step of the fixed-step method (so a state inside the step is a genuine integrator state, which is
what locating an impact in time needs), or the dense output of solve_ivp for the adaptive methods.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from runtime import settings

Rhs = Callable[[np.ndarray, np.ndarray], np.ndarray]  # (poses, velocities) -> accelerations
State = tuple[np.ndarray, np.ndarray]


def euler(rhs: Rhs, q: np.ndarray, v: np.ndarray, h: float, a1: np.ndarray) -> State:
    return q + h * v, v + h * a1


def midpoint(rhs: Rhs, q: np.ndarray, v: np.ndarray, h: float, a1: np.ndarray) -> State:
    half = 0.5 * h
    qm, vm = q + half * v, v + half * a1
    return q + h * vm, v + h * rhs(qm, vm)


def rk4(rhs: Rhs, q: np.ndarray, v: np.ndarray, h: float, a1: np.ndarray) -> State:
    """Classic RK4 on (q, v); ``a1`` = rhs(q, v), which the caller has already."""
    half = 0.5 * h
    v2 = v + half * a1
    a2 = rhs(q + half * v, v2)
    v3 = v + half * a2
    a3 = rhs(q + half * v2, v3)
    v4 = v + h * a3
    a4 = rhs(q + h * v3, v4)
    sixth = h / 6.0
    return q + sixth * (v + 2.0 * (v2 + v3) + v4), v + sixth * (a1 + 2.0 * (a2 + a3) + a4)


FIXED_STEP = {"euler": euler, "midpoint": midpoint, "rk4": rk4}
ADAPTIVE = {"rk45": "RK45", "dop853": "DOP853"}
# one impulse LCP a step, no located events (runtime.step.time_stepping)
TIME_STEPPING = "time-stepping"
METHODS = (*FIXED_STEP, *ADAPTIVE, TIME_STEPPING)


class Trajectory:
    """t -> (poses, velocities) after integrating t from (q0, v0), for 0 <= t <= h."""

    def __init__(
        self,
        method: str,
        rhs: Rhs,
        q0: np.ndarray,
        v0: np.ndarray,
        h: float,
        a0: np.ndarray,
        fast: Callable[[float], State | None] | None = None,
    ) -> None:
        """``fast(t)``: the same step compiled (runtime.step.compiled_stages), or None where it
        cannot do it; then ``rhs`` does it stage by stage."""
        self.method, self.rhs, self.q0, self.v0, self.h, self.a0 = method, rhs, q0, v0, h, a0
        self.fast = fast
        self.cache: dict[float, State] = {0.0: (q0, v0)}
        self.dense = None
        if method in ADAPTIVE:
            self.dense = self._solve_ivp()

    def at(self, t: float) -> State:
        found = self.cache.get(t)
        if found is None:
            found = self.cache[t] = self._integrate(t)
        return found

    def _integrate(self, t: float) -> State:
        if self.dense is None:
            if self.fast is not None:
                done = self.fast(t)
                if done is not None:
                    return done
            return FIXED_STEP[self.method](self.rhs, self.q0, self.v0, t, self.a0)
        n = self.q0.shape[0]
        y = self.dense.y[:, -1] if t >= self.h else self.dense.sol(t)
        return y[: 3 * n].reshape(n, 3), y[3 * n :].reshape(n, 3)

    def _solve_ivp(self):
        from scipy.integrate import solve_ivp  # imported on use: it costs ~1 s to import

        n = self.q0.shape[0]

        def f(_t: float, y: np.ndarray) -> np.ndarray:
            q, v = y[: 3 * n].reshape(n, 3), y[3 * n :].reshape(n, 3)
            return np.concatenate([v.ravel(), self.rhs(q, v).ravel()])

        y0 = np.concatenate([self.q0.ravel(), self.v0.ravel()])
        sol = solve_ivp(
            f,
            (0.0, self.h),
            y0,
            method=ADAPTIVE[self.method],
            rtol=settings.RTOL,
            atol=settings.ATOL,
            dense_output=True,
        )
        if not sol.success:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        return sol
