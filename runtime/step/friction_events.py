"""Friction transitions inside a trial step, located like impacts (issue #15).

Why: a trial step integrates each frictional contact in the mode its frame gave it
(runtime.solve.friction). Where a contact changes mode inside the step, the right-hand side
changes its formula, and a step across that instant would be first order at best. So the
instant is found and the island restarts there with a new frame (which decides the new modes):

* slip -> stick: a sliding contact's v_t reaches 0, i.e. s v_t (s its sliding sign) falls from
  > 0 to <= 0: located by runtime.step.events.locate (safeguarded Newton, slope s a_t from the
  forces at each point) until |v_t| <= settings.STICK_SPEED x settings.STICK_LOCATE (a contact
  set sliding against a residual v_t below the stick speed has s v_t <= 0 from the start: it
  is not moving its sliding way yet, and nothing is located);
* stick -> slip: a sticking contact's hold needs more than mu f_n (the friction LCP's slack
  becomes positive, runtime.solve.friction_lcp): a predicate of the state, not a smooth
  function (two corners of a box share their friction in any split), so bisected to
  settings.SLIP_TIME of the step, ending on the side where it slips -- the new frame then sees it
  slip and lets it slide.

Each point re-integrates the island's trial from its start, as for impacts, so the restart state
is a genuine integrator state.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from runtime import settings
from runtime.solve.friction import FrictionalForces, FrictionProblem
from runtime.solve.friction_lcp import FrictionInconsistent
from runtime.solve.friction_rows import FrictionRowEvaluator
from runtime.step.events import locate


class FrictionEvents:
    """The first friction transition of each island within a trial step."""

    def __init__(
        self,
        evaluator: FrictionRowEvaluator,
        forces: FrictionalForces,
        fixed: np.ndarray,
        refresh: Callable,
    ) -> None:
        """``refresh(contacts, poses)``: the contacts with an oval's point found again there
        (runtime.step.collision.Collision.refresh_ovals), as the trial's right-hand side does."""
        self.evaluator, self.forces, self.fixed, self.refresh = evaluator, forces, fixed, refresh
        self.with_gaps = forces.stabilisation is not None
        # the state's v_t, a_t and slips in one compiled call (runtime.step.compiled_friction.
        # friction_state), set by the stepper when it runs friction compiled
        self.state_call = None

    def first(
        self,
        problem: FrictionProblem,
        h: float,
        island_of_body: np.ndarray,
        trajectory: Callable[[int], object],
    ) -> dict[int, float]:
        """{island: time from the trial's start of its first friction transition}."""
        slide = problem.slide
        contacts = problem.contacts
        if slide is None or len(contacts) == 0:
            return {}
        mu = self.evaluator.friction
        frictional = np.sqrt(mu[contacts.body1] * mu[contacts.body2]) > 0
        moving = np.where(self.fixed[contacts.body1], contacts.body2, contacts.body1)
        island = island_of_body[moving]
        found: dict[int, float] = {}
        for g in np.unique(island[frictional & (island >= 0)]).tolist():
            members = island == g
            sub = problem.subset(members)
            state = self._state(sub, trajectory(g))
            try:
                times = self._transitions(sub, state, h)
            except FrictionInconsistent:
                times = self._inconsistent(sub, state, h)
            if times:
                found[g] = min(times)
        return found

    def _transitions(self, sub: FrictionProblem, state, h: float) -> list[float]:
        """The instants in (0, h] of the island's first slip -> stick and stick -> slip."""
        times = [self._slip_to_stick(sub, state, h), self._stick_to_slip(sub, state, h)]
        return [t for t in times if t is not None]

    def _inconsistent(self, sub: FrictionProblem, state, h: float) -> list[float]:
        """Where no forces obey the frame's modes somewhere in the trial (a state its stages did
        not solve: a 30-body mixed pile with mu = 0.5, 17 contacts sliding, met one at its end
        at t = 0.49 s and the run stopped): the instant they stop existing, bisected to
        settings.SLIP_TIME of the step and ending on the side where they do not -- the new frame
        there decides the modes again (and jams the island if it must: runtime.solve.friction)
        -- and the transitions before it."""
        lo, hi = 0.0, h
        while hi - lo > settings.SLIP_TIME * h:
            mid = 0.5 * (lo + hi)
            try:
                state(mid)
                lo = mid
            except FrictionInconsistent:
                hi = mid
        try:
            return [*self._transitions(sub, state, lo), hi]
        except FrictionInconsistent:  # (not consistent all the way to lo either)
            return [hi]

    def _state(self, sub: FrictionProblem, traj) -> Callable:
        """t -> (v_t, a_t, slips) of the island's contacts at its trajectory's state at t (the
        friction solution there)."""
        cache: dict[float, tuple] = {}
        fast = None if self.state_call is None else self._compiled_args(sub)

        def at(t: float):
            if t not in cache:
                q, v = traj.at(t)
                if fast is not None:
                    m = len(sub.contacts)
                    out = (np.empty(m), np.empty(m), np.empty(m, bool))
                    if self.state_call(q, v, *fast, *out):
                        cache[t] = out
                        return out
                contacts = self.refresh(sub.contacts, q)
                rows = self.evaluator.rows(contacts, q, v, self.with_gaps)
                solution = self.forces.solve(sub, rows)
                cache[t] = (rows.tangent_velocity, solution.tangent_accelerations, solution.slips)
            return cache[t]

        return at

    def _compiled_args(self, sub: FrictionProblem) -> tuple:
        """The arguments of runtime.step.compiled_friction.friction_state for ``sub`` but the
        state and the outputs (its basis flags: updated by each solve, as the general path's)."""
        f = self.forces
        contacts = sub.compiled_args(self.evaluator.mu(sub.contacts), self.fixed)
        return (*contacts, f.inverse_mass, self.fixed, f.free_acceleration)

    def _slip_to_stick(self, sub: FrictionProblem, state, h: float) -> float | None:
        sliding = np.flatnonzero(sub.slide != 0)
        if sliding.size == 0:
            return None
        starts = sub.slide[sliding] * state(0.0)[0][sliding]
        ends = sub.slide[sliding] * state(h)[0][sliding]
        # only a slip along its sliding direction can stop: a contact set sliding from below the
        # stick speed against its residual v_t (the direction its acceleration takes) is not
        # moving that way yet -- located, it stopped at t = 0, and again at every restart
        # (a falling pile with mu = 1 ran into MAX_EVENTS so, at t = 0.427 s)
        stopping = (starts > 0) & (ends <= 0)
        guesses = h * starts[stopping] / (starts[stopping] - ends[stopping])
        tol = settings.STICK_SPEED * settings.STICK_LOCATE
        earliest = None
        # by their linear guesses, so that the first located is likely the earliest: a contact
        # still sliding its way then (s v_t above the tolerance; the state there is cached) stops
        # later and is not located -- a landing pile's island has ~5 stopping in a step
        for k in sliding[stopping][np.argsort(guesses, kind="stable")].tolist():
            s = float(sub.slide[k])

            def speed(t: float, k=k, s=s) -> tuple[float, float]:
                v_t, a_t, _ = state(t)
                return s * float(v_t[k]), s * float(a_t[k])

            if earliest is not None and speed(earliest)[0] > tol:
                continue
            start, end = speed(0.0)[0], speed(h)[0]
            guess = h * start / (start - end) if start > end else h
            t, _ = locate(
                speed, 0.0, h, guess, gap_tol=tol,
                time_tol=settings.TIME_EPS * np.finfo(float).eps * h,
            )  # fmt: skip
            earliest = t if earliest is None else min(earliest, t)
        return earliest

    def _stick_to_slip(self, sub: FrictionProblem, state, h: float) -> float | None:
        if not state(h)[2].any():
            return None
        lo, hi = 0.0, h
        while hi - lo > settings.SLIP_TIME * h:
            mid = 0.5 * (lo + hi)
            if state(mid)[2].any():
                hi = mid
            else:
                lo = mid
        return hi
