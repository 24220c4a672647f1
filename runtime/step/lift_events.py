"""Lift-offs inside a trial step, located like impacts.

Why: a resting contact's force is a smooth function of the state while it presses. Where it
falls to 0 inside a step and the contact then moves apart (a disc sliding off a cylinder), the
right-hand side changes its formula at that instant (the contact stops pushing), and a fixed
step across the kink is first order: RK4 at dt = 0.05 s let the disc over the cylinder leave
with a velocity 2e-3 m/s off, and its flight drifted by 1.8e-3 m. So the instant is found and
the island restarts there with a new frame, in which the contact carries no force and lifts.

* a lift: a contact pressing at the trial's start (a force above settings.LCP_TOL of its
  island's largest) that carries no force at its end and moves apart there (d'' h above the
  resting speed: slower, the kink's error is below what the engine treats as resting anyway;
  and a redundant contact of a pile whose share of the load moves to its neighbours keeps
  d'' = 0 and is no lift);
* located by the Illinois method on g(t) = f(t) - d''(t) / A_kk, which is continuous (f falls to
  0 where d'' rises from 0), until the bracket is settings.LIFT_TIME of the step, ending on the
  lifted side -- so the new frame sees the contact lift and it never presses again at once.

Each point re-integrates the island's trial from its start, as for impacts, so the restart state
is a genuine integrator state. runtime.step.compiled_stages.lifted is the same end-of-trial
test compiled, for the quiet check (runtime.step.stepper) and the coasted steps
(runtime.step.coast).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from runtime import settings
from runtime.solve.assembly import free_rates
from runtime.solve.forces import ForceProblem


class LiftEvents:
    """The first lift-off of each island within a trial step."""

    def __init__(self, stepper) -> None:
        """``stepper``: runtime.step.stepper.Stepper (its rows, its force solve, its masses)."""
        self.stepper = stepper

    def first(
        self, resting, h: float, island_of_body: np.ndarray, trajectory: Callable[[int], object]
    ) -> dict[int, float]:
        """{island: time from the trial's start of its first lift-off}; ``resting``: the frame's
        RestingSolution (its problem and forces at the start)."""
        problem: ForceProblem = resting.problem
        if len(problem.contacts) == 0:
            return {}
        forces = resting.forces[problem.order]
        if not (forces > 0.0).any():
            return {}
        fixed = self.stepper.fixed
        c = problem.contacts
        island = island_of_body[np.where(fixed[c.body1], c.body2, c.body1)]
        found: dict[int, float] = {}
        for g in np.unique(island[(forces > 0.0) & (island >= 0)]).tolist():
            members = island == g
            # pressing: a force the solve tells from 0 (settings.LCP_TOL of the island's
            # largest); a contact restarted just past its lift-off found again with 1.3e-7 N of
            # 165 N (one solution of a redundant set) was located lifting 4e-12 s on, then again
            # at 1.7e-21 s, until MAX_EVENTS (the mixed pile, seed 2, at t = 0.433 s)
            pressing = forces > settings.LCP_TOL * forces[members].max()
            sub = problem.subset(members)
            state = self._state(sub, trajectory(g))
            t = self._earliest(state, pressing[members], h)
            if t is not None:
                found[g] = t
        return found

    def _state(self, sub: ForceProblem, traj) -> Callable[[float], tuple]:
        """t -> (f, d'', A_kk) of the island's contacts at its trajectory's state at t."""
        stepper = self.stepper
        inv_mass = stepper.forces.inverse_mass
        cache: dict[float, tuple] = {}
        fast = stepper.lift_state_args(sub)  # (None: the general path)

        def at(t: float) -> tuple:
            if t not in cache:
                q, v = traj.at(t)
                if fast is not None:
                    m = len(sub.contacts)
                    out = (np.empty(m), np.empty(m), np.empty(m))
                    if stepper._lift_state_call(q, v, *fast, *out):
                        cache[t] = out
                        return out
                contacts = sub.contacts
                if stepper.ovals:
                    contacts = stepper.collision.refresh_ovals(contacts, q)
                rows = stepper.evaluator.rows(contacts, q, v, stepper.with_gaps)
                solution = stepper._solve(sub, rows, q, v)
                ddot = np.empty(len(contacts))
                jac, b1, b2 = rows.jacobian, rows.body1, rows.body2
                free_rates(jac, b1, b2, rows.bias, solution.accelerations, ddot)
                diagonal = (jac[:, :3] ** 2 * inv_mass[b1]).sum(1) + (
                    jac[:, 3:] ** 2 * inv_mass[b2]
                ).sum(1)
                cache[t] = (solution.forces, ddot, diagonal)
            return cache[t]

        return at

    def _earliest(self, state, pressing: np.ndarray, h: float) -> float | None:
        """The earliest located lift-off among the contacts that lift at the trial's end."""
        forces, ddot, _ = state(h)
        speed = self.stepper.resting_speed
        lifting = np.flatnonzero(pressing & (forces <= 0.0) & (ddot * h > speed))
        earliest = None
        for k in lifting.tolist():

            def g(t: float, k=k) -> float:
                f, a, diagonal = state(t)
                return float(f[k]) if f[k] > 0.0 else -float(a[k]) / float(diagonal[k])

            # still pressing at the earliest lift-off so far (its state cached): it lifts later
            if earliest is not None and g(earliest) > 0.0:
                continue
            t = _illinois(g, 0.0, h, g(0.0), g(h), settings.LIFT_TIME * h)
            earliest = t if earliest is None else min(earliest, t)
        return earliest


def _illinois(g: Callable[[float], float], lo, hi, g_lo, g_hi, time_tol) -> float:
    """The end on the ``g <= 0`` side of a bracket [lo, hi] of g's sign change (g(lo) > 0 >=
    g(hi)) narrowed to ``time_tol`` by regula falsi with the Illinois modification (the end
    that stays has its value halved, so a convex or concave g does not stall it)."""
    side = 0
    for _ in range(settings.LOCATE_ITERATIONS):
        if hi - lo <= time_tol:
            break
        t = hi - g_hi * (hi - lo) / (g_hi - g_lo) if g_hi != g_lo else 0.5 * (lo + hi)
        if not lo < t < hi:
            t = 0.5 * (lo + hi)
        value = g(t)
        if value > 0.0:
            lo, g_lo = t, value
            if side == 1:
                g_hi *= 0.5
            side = 1
        else:
            hi, g_hi = t, value
            if side == -1:
                g_lo *= 0.5
            side = -1
    return hi


__all__ = ["LiftEvents"]
