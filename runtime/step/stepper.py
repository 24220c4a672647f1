"""The time step, as a pipeline of stages over arrays (the Box2D b2World_Step of this engine).

Why: resting contacts and impacts need different treatment (forces on accelerations for the
first, velocity jumps for the second), and an impact must be handled when the gap is 0, not at
the end of a step when the bodies have sunk into each other or passed through each other.

One step of length h from (q, v), for the bodies of one island (at first: all of them):

1. contacts    -- the contacts that can close within h: each body's reach widened by how far it
                  can move (runtime.collide.sweep), so fast bodies cannot tunnel
                  (runtime.step.collision);
2. classify    -- open, colliding, resting, separating (runtime.step.classify), and the impacts
                  among the touching contacts resolved island by island (runtime.solve.impulses);
3. settle      -- resting contacts moving apart pressed back or lifting off (runtime.step.resting);
4. forces      -- the resting contacts' forces per island, warm-started (runtime.solve.forces);
5. integrate   -- a trial step with the forces solved again at every stage
                  (runtime.step.integrators);
6. events      -- per island (bodies joined by the contacts of 1), the first instant an open
                  contact's generated gap reaches 0 (runtime.step.events);
7. accept      -- islands without an event take the trial's end state; each island with one is
                  integrated to its event alone and goes to 1 with the rest of the step.

A step whose trial is quiet (runtime.step.quiet) ends at 5; `simulate` steps stretches of such
steps, with the same contacts, in one compiled loop of these same stages (runtime.step.coast).
Stages 1-5 and the quiet check are compiled calls where they can be (runtime.step.compiled_frame,
compiled_stages; with friction runtime.step.compiled_friction), the general path otherwise.

So an impact in one corner of a scene sub-steps only its island. An impulse can send a body
farther than its reach in step 1; then the islands are not independent any more, and the step
is done again with every body in one island (:class:`_Merge`), which is always correct.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from functools import partial

import numpy as np

from runtime import settings
from runtime.collide import sweep
from runtime.collide.contact_keys import find, key_set, member
from runtime.collide.features import features
from runtime.compiled import Bound
from runtime.solve.forces import ContactForces, ForceProblem, ForceSolution, Stabilisation
from runtime.solve.islands import body_islands, contact_islands
from runtime.solve.rows import RowEvaluator, Rows
from runtime.step.classify import LIFTING, RESTING, Bodies, Frame, Limits, make_frame
from runtime.step.collision import Collision
from runtime.step.events import EventSearch
from runtime.step.friction_stage import friction_stage
from runtime.step.integrators import FIXED_STEP, Trajectory
from runtime.step.lift_events import LiftEvents
from runtime.step.pair_scan import IslandsMeet
from runtime.step.resting import settle

_HELD = np.isin(np.arange(max(RESTING, LIFTING) + 1), (RESTING, LIFTING))  # by mode: held?


class _Merge(Exception):
    """An island's bodies may reach another island within the step: do it as one island."""


@dataclass(frozen=True)
class RestingSolution:
    """The resting contacts' forces at a frame: ``forces`` and ``free_rates`` (b) in
    frame.resting order, the accelerations, and the problem (island order) for the stages."""

    problem: ForceProblem
    accelerations: np.ndarray
    forces: np.ndarray
    free_rates: np.ndarray
    tangent_forces: np.ndarray | None = None  # friction f_t along t (None: no friction stage)
    joint_forces: np.ndarray | None = None  # per joint row (runtime.solve.linked_forces)


@dataclass
class StepReport:
    """What a step did: its first frame (the contacts at its start) with the forces of the
    resting (and lifting) contacts there, the located impacts (times from the step's start)
    and the kinetic energy the impacts took out."""

    frame: Frame | None = None
    recorded: np.ndarray | None = None  # frame indices of the recorded contacts
    forces: np.ndarray | None = None  # their forces
    tangent_forces: np.ndarray | None = None  # their friction forces (None: no friction stage)
    joint_forces: np.ndarray | None = None  # the joint rows' forces there
    impact_times: list[float] = field(default_factory=list)  # impacts and other located events
    lift_times: list[float] = field(default_factory=list)  # located lift-offs (lift_events)
    impact_loss: float = 0.0
    # its last trial quiet (runtime.step.quiet) and nothing located in the step but lift-offs
    # (after which the next steps can coast: runtime.step.coast)
    quiet: bool = False


class Stepper:
    """Steps one scene (see the module docstring); runtime.step.world.World drives it."""

    def __init__(
        self,
        scene,
        method: str = "rk4",
        stabilisation: Stabilisation | None = None,
        resting_speed: float = settings.RESTING_SPEED,
    ) -> None:
        self.scene, self.method = scene, method
        self.n = len(scene.bodies)
        self.fixed = np.asarray(scene.fixed, dtype=bool)
        self.moving = (~self.fixed).astype(float)
        self.bodies = Bodies.of(scene)
        self.collision = Collision(scene)
        self.evaluator = RowEvaluator(scene.contact_cases(), self.fixed)
        self.links = None  # joints, springs, damping, mutual gravity: the general path only
        if scene.linked:
            from runtime.solve.linked_forces import LinkedForces

            self.links = LinkedForces(scene, stabilisation)
        self.forces = self.links or ContactForces(scene, stabilisation)
        self.friction = friction_stage(scene, self.fixed, stabilisation, self.collision)
        # what a solve raises where no forces obey the friction modes (nothing without friction)
        self.refused = () if self.friction is None else self.friction.inconsistent
        if self.friction is not None:
            if self.links is not None:
                raise ValueError(
                    f"{scene.source}: friction together with joints, springs, damping or mutual "
                    "gravity is not supported yet (issues #15, #16): set friction = 0 or remove "
                    "the links"
                )
            self.evaluator, self.forces = self.friction.evaluator, self.friction.forces
        self.with_gaps = stabilisation is not None
        self.recovery = 0.0 if stabilisation is None else 0.5 * stabilisation.damping
        self.resting_speed = resting_speed
        self.touch = min(settings.TOUCH, scene.contact_tolerance)
        self.gravity = float(np.hypot(*scene.gravity))
        self.radii = np.array([s.bounding_radius for s in scene.shapes], dtype=float)
        half = np.array([features(s).half_width for s in scene.shapes], dtype=float)
        switches = np.array([len(s.edges) > 1 or bool(s.vertices) for s in scene.shapes])
        self.events = EventSearch(
            self.collision, self.evaluator, self.touch, self.radii, half, switches
        )
        # lift-offs located in fixed steps (their kink makes a step across them first order);
        # not yet with friction or links (their forces are solved with other rows)
        self.lifts = None
        if method in FIXED_STEP and self.friction is None and self.links is None:
            self.lifts = LiftEvents(self)
        # the keys (runtime.collide.contact_keys) of the contacts resting in the last frame,
        # and at the end of the last step
        self.held = self.recent = key_set(np.zeros(0, np.int64))
        self._limits: dict[float, Limits] = {}
        self.evaluations = 0  # right-hand-side evaluations (integrator stages)
        self.ovals = self.collision.finder.has_ovals
        self.compiled = (
            settings.COMPILED
            and method in FIXED_STEP
            and stabilisation is None
            and not self.ovals
            and self.links is None
            and self.friction is None
        )
        if self.compiled:
            # imported here: they compile in every contact case (runtime/solve/kernel_set.py);
            # the general path imports the kernels of the scene's cases only
            from runtime.step import compiled_frame, compiled_stages, quiet

            self._step = Bound(compiled_stages.step)
            self._frame_call = Bound(compiled_frame.settle_frame)
            self._method_id = compiled_stages.METHOD_ID[method]
            self._quiet_call = Bound(quiet.is_quiet)
            self._lifted_call = Bound(compiled_stages.lifted)
            self._lift_state_call = Bound(compiled_stages.lift_state)
        # a scene with friction: its trial steps in one compiled call each
        self.compiled_friction = (
            settings.COMPILED
            and method in FIXED_STEP
            and stabilisation is None
            and not self.ovals
            and self.friction is not None
        )
        if self.compiled_friction:
            from runtime.step import compiled_friction, compiled_stages, quiet

            self._friction_made = (None, None)  # (problem, its compiled arguments)
            self._friction_step = Bound(compiled_friction.step)
            self._friction_frame_call = Bound(compiled_friction.settle_frame)
            self._friction_frame = compiled_friction.frame
            self._friction_quiet_call = Bound(compiled_friction.friction_quiet)
            self.friction.events.state_call = Bound(compiled_friction.friction_state)
            self._quiet_call = Bound(quiet.is_quiet)
            self._method_id = compiled_stages.METHOD_ID[method]

    # -- stages ----------------------------------------------------------------------------

    def limits(self, h: float) -> Limits:
        """The contact limits for steps of ``h`` (runtime.step.classify.hold_gap)."""
        if h not in self._limits:
            self._limits[h] = Limits.for_step(
                self.resting_speed, self.touch, self.scene.contact_tolerance, h, self.gravity
            )
        return self._limits[h]

    def settled_frame(
        self, q, v, h, limits: Limits, active=None, margin=None
    ) -> tuple[Frame, RestingSolution]:
        """Stages 1 to 4: the contacts that can close within h, classified, impacts resolved,
        resting contacts pressed or lifting, and the resting forces -- in one compiled call
        when every island is small (runtime.step.compiled_frame), else stage by stage."""
        if margin is None:
            margin = sweep.margins(v, h, self.radii, self.moving, self.gravity)
        if self.friction is not None:
            self.forces.stick_speed = limits.stick_speed
        contacts = self.collision.swept(q, margin, active)
        keys = self.collision.keys(contacts)
        done = None
        if self.compiled:
            done = self._compiled_frame(contacts, keys, q, v, margin, limits)
        elif self.compiled_friction:
            done = self._friction_frame(self, contacts, keys, q, v, margin, limits)
        if done is None:
            impacts = None if self.links is None else self.links.frame_impacts(q, v)
            frame = make_frame(self.evaluator, self.bodies, contacts, q, v, margin, self.held,
                               limits, self.recent, keys, impacts)  # fmt: skip
            done = settle(
                frame, partial(self.solve, q), self.bodies, limits.creep_speed,
                limits.separation_speed, self.recovery,
            )  # fmt: skip
            if self.links is not None:
                done = self.links.hold_joints(q, frame, done, partial(self.solve, q))
            if self.friction is not None:
                done = self.friction.hold(*done, self.bodies, partial(self.solve, q))
        self._hold(done[0], active)
        return done

    def _compiled_frame(self, contacts, keys, q, v, margin, limits: Limits):
        """(frame, resting solution) by runtime.step.compiled_frame, or None if an island is
        too large or has no solution (the general path then takes it, and names a failure)."""
        m = len(contacts)
        if m == 0:
            return None
        held = member(keys, self.held)
        recent = held if self.recent is self.held else member(keys, self.recent)
        guess = self.forces.memory.get(keys)
        gap, rate, bias = np.empty(m), np.empty(m), np.empty(m)
        jac = np.empty((m, 6))
        modes = np.empty(m, np.int64)
        impulses, forces, rates = np.zeros(m), np.zeros(m), np.zeros(m)
        velocities, acc = v.copy(), np.empty_like(v)
        order, offsets, labels = (
            np.empty(m, np.int64),
            np.empty(m + 1, np.int64),
            np.empty(m, np.int64),
        )
        counts = np.zeros(2, np.int64)
        b = self.bodies
        ok, loss = self._frame_call(
            q, contacts.case, contacts.body1, contacts.body2,
            contacts.geometry, np.ascontiguousarray(self.fixed[contacts.body2]), held, recent,
            b.restitution, b.mass, b.inverse_mass, b.fixed, self.forces.free_acceleration,
            (limits.touch, limits.hold_gap, limits.resting_speed, limits.separation_speed,
             limits.creep_speed),
            settings.LCP_TOL, settings.DENSE_ISLAND, settings.SETTLE_ROUNDS,
            velocities, gap, rate, jac, bias, modes, impulses, guess, forces, rates, acc,
            (order, offsets, labels, counts),
        )  # fmt: skip
        if not ok:
            return None
        rows = Rows(gap, rate, jac, bias, contacts.body1, contacts.body2)
        frame = Frame(contacts, keys, rows, modes, velocities, margin, impulses, loss)
        rest = frame.resting  # ascending; the problem's rows are the same contacts by island
        count, islands = counts.tolist()
        order = order[:count]
        if count == m and (m == 1 or bool((order[1:] > order[:-1]).all())):
            # every contact resting, in island order already: the frame's arrays as they are
            # (nothing writes to them after this), no copies or lookups
            problem = ForceProblem(contacts, rest, offsets[:islands], guess, labels, keys)
            self.forces.memory.update(keys, guess)
            return frame, RestingSolution(problem, acc, forces, rates)
        problem = ForceProblem(
            contacts.take(order), np.searchsorted(rest, order), offsets[:islands].copy(),
            guess[order], labels[:count].copy(), keys[order],
        )  # fmt: skip
        self.forces.memory.update(problem.keys, problem.guess)
        return frame, RestingSolution(problem, acc, forces[rest], rates[rest])

    def _hold(self, frame: Frame, active) -> None:
        """Remember the frame's resting (and lifting) contacts, for the hysteresis of the next
        frame; those of bodies outside ``active`` stay as they were."""
        resting = key_set(frame.keys[_HELD[frame.modes]])
        if active is None:
            self.held = resting
            return
        mine = active | self.fixed
        body1, body2 = self.collision.finder.keys.bodies_of(self.held)
        others = self.held[~(mine[body1] & mine[body2])]
        self.held = key_set(np.concatenate([others, resting]))

    def solve(
        self, q: np.ndarray, frame: Frame, which: np.ndarray | None = None
    ) -> RestingSolution:
        """Stage 4 at the frame: forces of the contacts ``which`` (default: the resting ones)."""
        rest = frame.resting if which is None else which
        return self.contact_forces(frame.contacts.take(rest), q, frame.velocities)

    def contact_forces(self, contacts, q: np.ndarray, v: np.ndarray) -> RestingSolution:
        """Forces (and b, the free d'') of ``contacts`` held as resting at (q, v), in their
        order, and the accelerations they give."""
        labels = contact_islands(
            body_islands(self.n, contacts.body1, contacts.body2, self.fixed),
            contacts.body1,
            contacts.body2,
            self.fixed,
        )
        problem = self.forces.problem(contacts, labels, self.collision.keys(contacts))
        rows = self.evaluator.rows(problem.contacts, q, v, self.with_gaps)
        solution = self._solve(problem, rows, q, v)
        self.forces.remember(problem)
        m = len(contacts)
        forces, rates = np.empty(m), np.empty(m)
        forces[problem.order], rates[problem.order] = solution.forces, solution.free_rates
        tangent = getattr(solution, "tangent_forces", None)  # runtime.solve.friction's
        if tangent is not None:  # in the order of ``contacts``, as the forces
            ordered = np.empty(m)
            ordered[problem.order] = tangent
            tangent = ordered
        joints = getattr(solution, "joint_forces", None)  # runtime.solve.linked_forces'
        return RestingSolution(problem, solution.accelerations, forces, rates, tangent, joints)

    def _solve(self, problem: ForceProblem, rows: Rows, q, v) -> ForceSolution:
        """Stage 4 on kernel rows at (q, v); linked scenes' forces depend on the state too."""
        if self.links is None:
            return self.forces.solve(problem, rows)
        return self.links.solve(problem, rows, (q, v))

    def rhs(self, problem: ForceProblem):
        """(q, v) -> accelerations with the forces of ``problem``'s contacts solved there."""

        def accelerations(q: np.ndarray, v: np.ndarray) -> np.ndarray:
            self.evaluations += 1
            contacts = problem.contacts
            if self.ovals:  # an oval's contact point moves over it: found again at each stage
                contacts = self.collision.refresh_ovals(contacts, q)
            rows = self.evaluator.rows(contacts, q, v, self.with_gaps)
            solution: ForceSolution = self._solve(problem, rows, q, v)
            return solution.accelerations

        return accelerations

    def trajectory(self, problem: ForceProblem, q, v, h: float, a0) -> Trajectory:
        """Stage 5: t -> state after integrating t from (q, v) with ``problem``'s forces."""
        fast = None
        if self.compiled:
            fast = self._fast(problem, q, v, a0)
        elif self.compiled_friction:
            fast = self._fast_friction(problem, q, v, a0)
        return Trajectory(self.method, self.rhs(problem), q, v, h, a0, fast)

    def _fast(self, problem: ForceProblem, q, v, a0):
        """t -> the compiled step (runtime.step.compiled_stages), or None where it cannot."""
        c = problem.contacts
        args = (
            self._method_id, q, v, 0.0, a0, c.case, c.body1, c.body2,
            c.geometry, np.ascontiguousarray(self.fixed[c.body2]), problem.offsets,
            problem.guess, self.forces.inverse_mass, self.fixed, self.forces.free_acceleration,
            settings.LCP_TOL, settings.DENSE_ISLAND,
        )  # fmt: skip
        return self._compiled_trial(self._step, args)

    def _friction_args(self, problem):
        """problem.compiled_args for runtime.step.compiled_friction's step and quiet check, or
        None where they cannot take it: an island without a frictional contact, or modes not
        decided yet. The trial and its quiet check ask for the same problem: made once."""
        if self._friction_made[0] is problem:
            return self._friction_made[1]
        c = problem.contacts
        if problem.slide is None or len(c) == 0:
            return None
        mu = self.evaluator.mu(c)
        args = None
        if (np.add.reduceat(mu > 0, problem.offsets[:-1]) > 0).all():
            args = problem.compiled_args(mu, self.fixed)
        self._friction_made = (problem, args)
        return args

    def _fast_friction(self, problem, q, v, a0):
        """t -> the compiled step with friction (runtime.step.compiled_friction), or None."""
        contacts = self._friction_args(problem)
        if contacts is None:
            return None
        f = self.forces
        args = (self._method_id, q, v, 0.0, a0, *contacts, f.inverse_mass, self.fixed,
                f.free_acceleration)  # fmt: skip
        return self._compiled_trial(self._friction_step, args)

    def _friction_quiet(self, problem, end) -> bool:
        """Whether the trial's ``end`` state has no friction transition to locate
        (runtime.step.compiled_friction.friction_quiet); False where unsure."""
        if problem.slide is None or len(problem.contacts) == 0:
            return True
        contacts = self._friction_args(problem)
        f = self.forces
        return contacts is not None and self._friction_quiet_call(
            *end, *contacts, f.inverse_mass, self.fixed, f.free_acceleration
        )

    def _compiled_trial(self, call, args, at: int = 3):
        """t -> call(*args with t at index ``at``, q_out, v_out), or None where it declines."""

        def step(t: float):
            q_out, v_out = np.empty_like(args[1]), np.empty_like(args[2])
            if call(*args[:at], float(t), *args[at + 1 :], q_out, v_out):
                self.evaluations += 3 if self._method_id == 2 else self._method_id
                return q_out, v_out
            return None

        return step

    # -- the step --------------------------------------------------------------------------

    def step(
        self, q: np.ndarray, v: np.ndarray, h: float
    ) -> tuple[np.ndarray, np.ndarray, StepReport]:
        """One step of length h from (q, v): the new state and what the step did."""
        self.recent = held = self.held  # never changed in place: replaced
        limits = self.limits(h)
        report = StepReport()
        try:
            q1, v1 = self._advance(q, v, h, limits, report, split=True)
        except (_Merge, IslandsMeet):
            self.held, report = held, StepReport()
            q1, v1 = self._advance(q, v, h, limits, report, split=False)
        return q1, v1, report

    def _advance(self, q, v, h, limits, report, split, active=None, reach=None, t0=0.0):
        """The bodies ``active`` (a bool mask, None: all) advanced by h from (q, v), each island
        on its own when ``split``. ``reach``: (poses, margins) that this island's bodies must
        stay within (else :class:`_Merge`); ``t0``: time of q from the step's start."""
        elapsed, events, transitions = 0.0, 0, 0
        cap = math.inf  # the next trial's length at most (halved where the search met no forces)
        while True:
            # an impact located on the step's end can leave elapsed past h by rounding: the
            # rest of the step is then empty, as when it ends there exactly (not negative)
            remaining = max(h - elapsed, 0.0)
            margin = sweep.margins(v, remaining, self.radii, self.moving, self.gravity)
            if reach is not None:
                moved = sweep.displacement(reach[0], q, self.radii)
                if active is not None and np.any((moved + margin > reach[1])[active]):
                    raise _Merge
            frame, resting = self.settled_frame(q, v, remaining, limits, active, margin)
            report.impact_loss += frame.impact_loss
            if report.frame is None:
                self._record_first(report, q, frame, resting)
            start_v = frame.velocities
            trial, span, end = self._trial(resting, q, start_v, min(remaining, cap))
            cap = math.inf
            cut = span < remaining  # a shorter sub-step: it ends at a new frame, not the step's
            remaining = span
            if reach is not None:  # the impacts of this frame may have sped the island up
                moved = sweep.displacement(reach[0], end[0], self.radii)
                if np.any((moved > reach[1])[active]):
                    raise _Merge
            lifting = self._lifting(resting, end, remaining)
            if self._quiet(q, end, frame, resting, remaining, lifting):
                if cut:
                    (q, v), elapsed, events = end, elapsed + span, events + 1
                    continue
                report.quiet = events == len(report.lift_times) and active is None
                return end
            labels = self._islands(frame, active)
            if sweep.outran(q, end[0], self.radii, frame.margin):
                frame, labels = self._widen(q, end[0], frame, limits, active)
            trajectory = _IslandTrajectories(self, trial, resting, labels, split)
            try:
                firsts = self.events.first(frame, q, end, remaining, labels, trajectory)
                if self.friction is not None:  # stick <-> slip, located like impacts
                    found = self.friction.events.first(
                        resting.problem, remaining, labels, trajectory
                    )
                    transitions += any(t < firsts.get(g, np.inf) for g, t in found.items())
                    for g, t in found.items():
                        firsts[g] = min(firsts.get(g, t), t)
                    if transitions == settings.CHATTER:  # slow slips stick from the next frame
                        limits = replace(limits, stick_speed=max(limits.stick_speed,
                                                                 limits.resting_speed))  # fmt: skip
                lifts = {}  # pressing contacts that lift off, located likewise
                if lifting:
                    lifts = self.lifts.first(resting, remaining, labels, trajectory)
                    for g, t in lifts.items():
                        firsts[g] = min(firsts.get(g, t), t)
            except self.refused:
                # the search integrated to a state whose friction modes no forces obey (the
                # trial's stages did not meet it: a 30-body mixed pile with mu = 0.5, 43
                # contacts sliding, stopped so at t = 0.543 s): a trial half as long, from the
                # same frame (its impacts done), as the trial's own cuts (settings.TRIAL_CUTS)
                if span <= h * 0.5**settings.TRIAL_CUTS:
                    raise
                v, cap = start_v, 0.5 * span
                continue
            if not firsts and cut:
                (q, v), elapsed, events = end, elapsed + span, events + 1
                continue
            if not firsts:
                return end
            events += 1
            if events > settings.MAX_EVENTS:
                raise RuntimeError(f"more than {settings.MAX_EVENTS} events within one step")
            if not split or cut or np.unique(labels[labels >= 0]).size <= 1:  # sub-step all
                island = min(firsts, key=firsts.get)
                tau = firsts[island]
                _listed(report, lifts, island, tau).append(t0 + elapsed + tau)
                q, v = trajectory.everyone_at(island, tau)
                elapsed += tau
                continue
            new_q, new_v = end[0].copy(), end[1].copy()
            for island, tau in sorted(firsts.items(), key=lambda item: item[1]):
                members = labels == island
                _listed(report, lifts, island, tau).append(t0 + elapsed + tau)
                q_i, v_i = trajectory(island).at(tau)
                q_i, v_i = self._advance(
                    q_i, v_i, remaining - tau, limits, report, True, members,
                    (q, frame.margin), t0 + elapsed + tau,
                )  # fmt: skip
                new_q[members], new_v[members] = q_i[members], v_i[members]
            return new_q, new_v

    def _trial(self, resting: RestingSolution, q, v, h: float):
        """(trial, span, its end): the trial from (q, v) with the resting forces over h, or
        where an integrator stage finds that no forces obey the frame's friction modes (a
        Painleve configuration before the step's end: a falling 20-disc pile with mu = 0.5 met
        one at t = 0.672 s, 19 of 21 contacts sliding), over the longest span h / 2^k whose
        stages are solved (settings.TRIAL_CUTS halvings at most; the frame's own forces were)."""
        span = h
        for cuts in range(settings.TRIAL_CUTS + 1):
            try:
                trial = self.trajectory(resting.problem, q, v, span, resting.accelerations)
                return trial, span, trial.at(span)
            except self.refused:
                if cuts == settings.TRIAL_CUTS:
                    raise
                span /= 2

    def _quiet(
        self, q, end, frame: Frame, resting: RestingSolution, h: float, lifting: bool = False
    ) -> bool:
        """Whether the trial of length h from q (with the frame's velocities and the resting
        accelerations) to ``end`` has nothing for the event search to find (runtime.step.quiet;
        with friction, no friction transition either; ``lifting``: a contact may lift off):
        then it is the step, without the search."""
        if not (self.compiled or self.compiled_friction) or lifting:
            return False
        if self.compiled_friction and not self._friction_quiet(resting.problem, end):
            return False
        a0 = resting.accelerations
        c, rows, tables = frame.contacts, frame.rows, self.collision.finder.tables
        return self._quiet_call(
            q, end[0], end[1], frame.margin, self.radii, self.events.half_width,
            self.events.switches, c.case, c.body1, c.body2, c.geometry,
            np.ascontiguousarray(self.fixed[c.body2]), frame.modes, rows.gap,
            rows.gap_velocity, self.touch, settings.CREEP * self.resting_speed, settings.FAST_PAIR,
            self.fixed, self.events.deepest, tables.rows, tables.body_start, c.feature,
            frame.velocities, a0, float(h),
        )  # fmt: skip

    def _lifting(self, resting: RestingSolution, end, h: float) -> bool:
        """Whether a contact pressing at the trial's start may lift off by its ``end``: one
        that the trial's last stage no longer held clamped (its forces' guess, updated by every
        stage's solve), confirmed at the end by runtime.step.compiled_stages.lifted on the
        compiled path (True where unsure: the event search's runtime.step.lift_events
        decides)."""
        problem = resting.problem
        if self.lifts is None or len(problem.contacts) == 0:
            return False
        pressing = resting.forces[problem.order] > 0.0
        if not (pressing & ~problem.guess).any():
            return False
        if not self.compiled:
            return True
        return self._lifted_call(
            *end, *self.lift_state_args(problem), pressing, float(h), float(self.resting_speed)
        )

    def lift_state_args(self, problem: ForceProblem) -> tuple | None:
        """The arguments of runtime.step.compiled_stages.lift_state for ``problem`` but the
        state and the outputs (a copy of its guess); None off the compiled path."""
        if not self.compiled:
            return None
        c, f = problem.contacts, self.forces
        return (
            c.case, c.body1, c.body2, c.geometry, np.ascontiguousarray(self.fixed[c.body2]),
            problem.offsets, problem.guess.copy(), f.inverse_mass, self.fixed,
            f.free_acceleration, settings.LCP_TOL, settings.DENSE_ISLAND,
        )  # fmt: skip

    def _islands(self, frame: Frame, active) -> np.ndarray:
        """Island label per body from the frame's contacts (-1: fixed, or not ``active``)."""
        c = frame.contacts
        b1, b2 = (c.body1, c.body2) if self.links is None else self.links.joined(c.body1, c.body2)
        labels = body_islands(self.n, b1, b2, self.fixed)
        labels[self.fixed] = -1
        if active is not None:
            labels[~active] = -1
        return labels

    def _widen(self, q, end_q, frame: Frame, limits: Limits, active):
        """A body moved farther than its margin (a large contact force): the contacts to watch
        are found again with margins twice the distances moved; the resting set stays."""
        wider = np.maximum(frame.margin, 2.0 * sweep.displacement(q, end_q, self.radii))
        contacts = self.collision.swept(q, wider, active)
        keys = self.collision.keys(contacts)
        rows = self.evaluator.rows(contacts, q, frame.velocities)
        at = find(keys, frame.keys, np.argsort(frame.keys))
        known = at >= 0
        modes = np.zeros(len(contacts), dtype=int)
        impulses = np.zeros(len(contacts))
        modes[known], impulses[known] = frame.modes[at[known]], frame.impulses[at[known]]
        widened = Frame(
            contacts, keys, rows, modes, frame.velocities, wider, impulses, frame.impact_loss
        )
        return widened, self._islands(widened, active)

    def _record_first(self, report: StepReport, q, frame: Frame, resting: RestingSolution) -> None:
        """The contacts and forces a step records: those at its start, lifting ones counted as
        resting (their force is solved with them)."""
        report.frame = frame
        if not (frame.modes == LIFTING).any():
            report.recorded, report.forces = frame.resting, resting.forces
            report.tangent_forces = resting.tangent_forces
            report.joint_forces = resting.joint_forces
            return
        every = np.sort(np.concatenate([frame.resting, frame.lifting]))
        solved = self.solve(q, frame, every)
        report.recorded, report.forces = every, solved.forces
        report.tangent_forces = solved.tangent_forces
        report.joint_forces = solved.joint_forces

    def classify(
        self, q: np.ndarray, v: np.ndarray, h: float = 0.0
    ) -> tuple[Frame, RestingSolution]:
        """The frame at (q, v) with no time to move (the contacts touching now, with the limits
        of steps of h), settled, and its resting forces: what a record at the end of a run
        shows. A look, not a step: the memory the next step starts from (the resting sets and
        the warm-start guesses) is left as it was, so asking for the contacts between steps
        never changes the run (it did: a 200-disc pile failed at t = 0.622 s only when its
        contacts were looked at every 10 steps); with friction its bases too (a falling 30-disc
        pile with mu = 1 took another path when its contacts were looked at)."""
        bases = getattr(self.forces, "bases", None)  # (friction: runtime.solve.friction)
        memory = (
            self.held,
            self.recent,
            self.forces.memory.copy(),
            None if bases is None else bases.copy(),
        )
        try:
            return self.settled_frame(q, v, 0.0, self.limits(h))
        finally:
            self.held, self.recent, self.forces.memory, bases = memory
            if bases is not None:
                self.forces.bases = bases


class _IslandTrajectories:
    """island -> its own trajectory over the trial: the trial integrated again with only that
    island's resting contacts, made on first use -- or the trial itself, when not split or when
    the island holds every resting contact (its trajectory would be the trial's, integrated
    again: a friction scene's stick -> slip check at the step's end did that every step)."""

    def __init__(
        self, stepper: Stepper, trial: Trajectory, resting: RestingSolution, labels, split
    ):
        self.stepper, self.trial, self.resting = stepper, trial, resting
        self.labels, self.split = labels, split
        self.made: dict[int, Trajectory] = {}

    def everyone_at(self, island: int, t: float) -> tuple[np.ndarray, np.ndarray]:
        """The state of every body at t, for a sub-step that every island takes (a trial cut
        short: its stages, or the search, met no forces): ``island``'s from its own trajectory, where its event was
        located, the others' from the trial. Its own trajectory alone let the other islands'
        bodies fall free of their resting contacts for the sub-step (a disc resting on the
        side of a box spinning at 84 rad/s went 6.3e-7 m into it in 4.7e-5 s so)."""
        own = self(island)
        if own is self.trial:
            return own.at(t)
        q, v = (np.array(x) for x in self.trial.at(t))
        q_own, v_own = own.at(t)
        members = self.labels == island
        q[members], v[members] = q_own[members], v_own[members]
        return q, v

    def __call__(self, island: int) -> Trajectory:
        if not self.split:
            return self.trial
        if island not in self.made:
            problem, stepper, trial = self.resting.problem, self.stepper, self.trial
            keep = self.labels[_moving_body(problem.contacts, stepper.fixed)] == island
            if keep.all():  # every resting contact is the island's: its trajectory is the trial
                self.made[island] = trial
            else:
                self.made[island] = stepper.trajectory(
                    problem.subset(keep), trial.q0, trial.v0, trial.h, trial.a0
                )
        return self.made[island]


def _listed(report: StepReport, lifts: dict[int, float], island: int, tau: float) -> list:
    """The report's list for an event of ``island`` at ``tau``: its lift-offs where that is
    the island's located lift-off, else its impacts (and friction transitions)."""
    return report.lift_times if lifts.get(island) == tau else report.impact_times


def _moving_body(contacts, fixed: np.ndarray) -> np.ndarray:
    """The moving body of each contact (body 1 unless it is fixed)."""
    return np.where(fixed[contacts.body1], contacts.body2, contacts.body1)


__all__ = ["RESTING", "StepReport", "Stepper"]
