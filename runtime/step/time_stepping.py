"""Time stepping (method "time-stepping"): one velocity-level contact LCP a step (Stewart and
Trinkle 1996, Anitescu and Potra 1997), then the overlaps the step left projected out.

Why: the other methods locate every impact at its instant and hold resting contacts by Baraff's
forces; a landing pile has thousands of impacts a second, each a few dense solves over its
island (issue #12: the 50-disc pile 326x pymunk, the 200-disc pile did not finish its second in
600 s). A scene that needs no impact instants -- a pile, a hopper, plastic contact -- can take one
impulse solve a step instead, whose cost does not grow with the impacts. What it gives up:
impacts happen at the step, not at their instant (the method is first order in h), and
restitution acts on the approach speed at the step's start. What it keeps: the gaps and Jacobians
of the generated kernels, and no overlap deeper than settings.PROJECTION_TOL of the touch gap
after any step.

A step of length h, each stage a function of arrays:

1. free velocities        vf = v + h a_free
2. contacts               every pair that can close within h (the swept finder), with d and the
                          Jacobian J at q (generated kernels: d' = J v)
3. impulses               p >= 0 per island, A p + b >= 0, p.(A p + b) = 0, A = J W J^T,
                          b = J vf + max(d, 0) / h: a contact open by d may close by d within the
                          step, no more (a speculative contact); a contact with restitution
                          e > 0 that closes within the step faster than the resting speed:
                          b = (1 + e) d', so d'+ >= -e d' (Newton's law, applied at the step's
                          start: the bounce comes early by at most the gap, |d'| h)
4. integrate              v+ = vf + W J^T p,  q+ = q + h v+   (semi-implicit Euler)
5. project                while a contact at q+ overlaps deeper than the tolerance (the step's
                          contacts checked first: enough when no body outran its margin): the
                          smallest move in the kinetic-energy metric that opens the linearised gaps,
                          dq = W J^T mu with A mu + d >= 0, mu >= 0 complementary (Newton:
                          quadratic; velocities untouched)

Friction, joints and springs are not modelled by this method yet: such a scene is refused with
the reason. The contacts and forces a World shows at a state are Baraff's, as for the other
methods (runtime.step.stepper.Stepper.classify).
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.collide import sweep
from runtime.collide.contact_keys import Guesses, key_set, member
from runtime.solve.assembly import add_forces
from runtime.solve.island_impulses import solve_impulses
from runtime.step.classify import OPEN, RESTING, Frame
from runtime.step.guards import contact_names
from runtime.step.integrators import TIME_STEPPING
from runtime.step.stepper import Stepper, StepReport

METHOD = TIME_STEPPING


class TimeStepper(Stepper):
    """Steps one scene by time stepping (see the module docstring); a World drives it as it
    drives a Stepper, whose contact finder, kernel rows and frame at a state it shares."""

    def __init__(self, scene, method: str = METHOD, stabilisation=None, resting_speed=None):
        options = {} if resting_speed is None else {"resting_speed": resting_speed}
        super().__init__(scene, METHOD, None, **options)
        _refuse(scene, self, stabilisation)
        inverse = self.bodies.inverse_mass.copy()
        inverse[self.fixed] = 0.0
        self.inverse_mass = np.ascontiguousarray(inverse)
        self.tolerance = settings.PROJECTION_TOL * self.touch
        self.reach = np.where(self.fixed, 0.0, scene.contact_tolerance)
        self.clamped = key_set(np.zeros(0, np.int64))  # keys of the rows held at the last solve
        self.impulses = Guesses(dtype=float)  # key -> the impulse of the last step's solve

    def step(
        self, q: np.ndarray, v: np.ndarray, h: float
    ) -> tuple[np.ndarray, np.ndarray, StepReport]:
        """(poses, velocities) after h, and what the step did (its contacts and their mean
        forces p / h; the kinetic energy the impulses took out)."""
        free = v + h * self.forces.free_acceleration
        margin = sweep.margins(free, h, self.radii, self.moving, self.gravity)
        contacts = self.collision.swept(q, margin, None)
        keys = self.collision.keys(contacts)
        rows = self.evaluator.rows(contacts, q, free)
        p = self._impulses(contacts, keys, rows, h)
        after = free + self._moved(contacts, rows.jacobian, p)
        self.evaluations += 1
        moved = q + h * after
        end = moved if self._clear(contacts, q, moved, margin) else self._project(moved, after)
        loss = self.bodies.kinetic(free) - self.bodies.kinetic(after)
        modes = np.where(p > 0.0, RESTING, OPEN)
        frame = Frame(contacts, keys, rows, modes, after, margin, p, loss)
        report = StepReport(frame, frame.resting, p[frame.resting] / h, impact_loss=loss)
        return end, after, report

    # -- stages ----------------------------------------------------------------------------

    def _impulses(self, contacts, keys, rows, h) -> np.ndarray:
        """Stage 3: the impulse of every contact (see the module docstring)."""
        if not len(contacts):
            return np.zeros(0)
        gap, rate = rows.gap, rows.gap_velocity  # d' at the free velocities
        b = rate + np.maximum(gap, 0.0) / h
        e = np.maximum(
            self.bodies.restitution[contacts.body1], self.bodies.restitution[contacts.body2]
        )
        bounce = (e > 0.0) & (gap + h * rate <= self.touch) & (rate < -self.resting_speed)
        b[bounce] = (1.0 + e[bounce]) * rate[bounce]  # J v+ >= -e d': Newton's law
        p, clamped = self._impulse_lcp(contacts, keys, rows.jacobian, b, self.impulses.get(keys))
        self.clamped, self.impulses = key_set(keys[clamped]), Guesses(keys, p, dtype=float)
        return p

    def _impulse_lcp(
        self, contacts, keys, jacobian, b, start=None
    ) -> tuple[np.ndarray, np.ndarray]:
        """The LCP p >= 0, J W J^T p + b >= 0, complementary, island by island, warm-started
        from the rows clamped at the last step's impulse solve and from ``start`` (impulses to
        start from, the last step's; none for the projection's position LCP)."""
        guess = member(keys, self.clamped)
        return solve_impulses(
            contacts.body1,
            contacts.body2,
            jacobian,
            b,
            guess,
            self.inverse_mass,
            self.fixed,
            start,
        )

    def _moved(self, contacts, jacobian, p) -> np.ndarray:
        """W J^T p: the velocity change of impulses p (or the move of position multipliers)."""
        change = np.zeros((self.n, 3))
        add_forces(jacobian, contacts.body1, contacts.body2, self.inverse_mass, p, change)
        return change

    def _clear(self, contacts, q, moved, margin) -> bool:
        """Stage 5's check, from the step's own contacts: none overlaps at ``moved`` deeper
        than the tolerance. Enough when no body moved farther than its margin: the step's
        contacts then hold every feature pair that can meet (runtime.collide.sweep), so the
        contact finder's second pass (~8 % of the falling 200-disc pile's step) is not needed.
        Not: a body an impulse sent farther, or ovals (their contacts' geometry is of the poses
        they were found at); and any overlap here is judged by :meth:`_project`."""
        if self.collision.finder.has_ovals or sweep.outran(q, moved, self.radii, margin):
            return False
        return not len(contacts) or self.evaluator.gaps(contacts, moved).min() >= -self.tolerance

    def _project(self, q, v) -> np.ndarray:
        """Stage 5: q with every overlap deeper than the tolerance projected out."""
        for _ in range(settings.PROJECTION_ROUNDS):
            contacts = self.collision.swept(q, self.reach, None)
            if not len(contacts):
                return q
            gap = self.evaluator.gaps(contacts, q)
            if gap.min() >= -self.tolerance:
                return q
            jacobian = self.evaluator.rows(contacts, q, v, with_gaps=False).jacobian
            mu, _ = self._impulse_lcp(contacts, self.collision.keys(contacts), jacobian, gap)
            q = q + self._moved(contacts, jacobian, mu)
        deepest = int(np.argmin(gap))
        raise RuntimeError(
            f"the overlaps of a time step were not projected out in {settings.PROJECTION_ROUNDS} "
            f"rounds: {contact_names(self.scene, contacts.take([deepest]))} still overlap by "
            f"{-gap[deepest]:.3g} m (jammed: no move opens every gap); a smaller dt may do"
        )


def _refuse(scene, stepper: Stepper, stabilisation) -> None:
    """A scene this method does not model: say why (ValueError), instead of a wrong run."""
    why = None
    if stepper.friction is not None:
        why = "friction (set friction = 0)"
    elif stepper.links is not None:
        why = "joints, springs, damping or mutual gravity"
    elif stabilisation is not None:
        why = "stabilisation (its overlaps are projected out; drop the stabilisation)"
    if why is not None:
        raise ValueError(
            f"{scene.source}: method {METHOD!r} does not model {why} yet; use rk4, which does"
        )
