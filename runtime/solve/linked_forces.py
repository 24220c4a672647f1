"""Contact forces of a scene whose bodies are also linked: joints as bilateral rows of Baraff's
problem, and state-dependent applied forces (springs, damping, mutual gravity) in its free
accelerations (issue #16).

Why a subclass of ContactForces: the step (runtime.step.stepper) asks for forces the same way
whatever acts; only what b and the rows are changes. At a state (q, v):

    a0 = gravity + applied(q, v)                         (runtime.solve.applied_forces)
    rows = contact rows (resting set) + joint rows        (runtime.solve.joints)
    d'' = A f + b, A = J W J^T, b = J a0 + bias           (contacts: a >= 0, f >= 0, f.a = 0;
                                                           joints: a = 0, f free in sign)

solved per island, joints joining bodies into one island (runtime.solve.lcp.solve_warm with the
``joint`` mask). The exact bias keeps d'' = 0 on every joint row, so d and d' drift only by
the integrator's error; with a Stabilisation the joints' d'' is asked to be -k_d d' - k_p d,
as for contacts.

Impacts and presses: an impulse on a contact of a jointed body must move the joint's other
bodies too. :meth:`LinkedForces.impacts` eliminates the joint rows (Schur complement: the
contacts see A_cc - A_cj A_jj^+ A_jc, the effective mass with the joints held), resolves the
contacts' impulses with runtime.solve.impulses unchanged, and adds the joint impulses that keep
d' = 0. :meth:`LinkedForces.hold_joints` removes a joint rate left by a press (a plastic joint
impulse, least kinetic energy) unless a Stabilisation is there to damp it; the drift of d'
is never touched without one.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import partial

import numpy as np

from runtime import settings
from runtime.collide.contact_keys import member
from runtime.solve import assembly, impulses, lcp
from runtime.solve.applied_forces import AppliedForces
from runtime.solve.forces import ContactForces, ForceProblem, ForceSolution
from runtime.solve.islands import body_islands, contact_islands, grouped
from runtime.solve.joints import JointSet
from runtime.solve.rows import Rows

__all__ = ["LinkedForces", "LinkedSolution"]


@dataclass(frozen=True)
class LinkedSolution(ForceSolution):
    """Also the force of each joint row (N, in JointSet order: run.joint_forces records it)."""

    joint_forces: np.ndarray = None


def _concat(a: Rows, b: Rows) -> Rows:
    return Rows(*(np.concatenate([x, y]) for x, y in zip(_fields(a), _fields(b), strict=True)))


def _fields(r: Rows):
    return (r.gap, r.gap_velocity, r.jacobian, r.bias, r.body1, r.body2)


class LinkedForces(ContactForces):
    """ContactForces with joints and applied forces (see the module docstring)."""

    def __init__(self, scene, stabilisation=None) -> None:
        super().__init__(scene, stabilisation)
        self.n = len(scene.bodies)
        self.gravity = self.free_acceleration.copy()
        self.applied = AppliedForces.of(scene)
        self.joints = JointSet.of(scene)

    # -- forces ------------------------------------------------------------------------------

    def free(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """a0 at (q, v): gravity plus the applied forces' accelerations."""
        if self.applied is None:
            return self.gravity.copy()
        return self.gravity + self.applied.accelerations(q, v)

    def solve(self, problem: ForceProblem, rows: Rows, state=None) -> ForceSolution:
        """Accelerations and the contacts' forces at ``state`` = (q, v), the state of ``rows``."""
        q, v = state
        self.free_acceleration = self.free(q, v)
        if self.joints is None:
            return super().solve(problem, rows)
        m = len(rows.bias)
        every = _concat(rows, self.joints.rows(q, v, with_gaps=self.stabilisation is not None))
        bias = every.bias
        if self.stabilisation is not None:
            k = self.stabilisation
            bias = bias + k.damping * every.gap_velocity + k.stiffness * every.gap
        labels = contact_islands(
            body_islands(self.n, every.body1, every.body2, self.fixed),
            every.body1, every.body2, self.fixed,
        )  # fmt: skip
        order, offsets = grouped(labels)
        jac = np.ascontiguousarray(every.jacobian[order])
        b1, b2 = every.body1[order], every.body2[order]
        joint = order >= m
        rates = np.empty(order.size)
        assembly.free_rates(jac, b1, b2, bias[order], self.free_acceleration, rates)
        guess = np.concatenate([problem.guess, np.ones(every.bias.size - m, bool)])[order]
        forces = np.zeros(order.size)
        for g in range(offsets.size - 1):
            start, stop = int(offsets[g]), int(offsets[g + 1])
            A = np.empty((stop - start, stop - start))
            assembly.island_matrix(jac, b1, b2, self.inverse_mass, self.fixed, start, stop, A)
            try:
                f, clamped = lcp.solve_warm(
                    A, rates[start:stop], joint[start:stop], guess[start:stop]
                )
            except lcp.ContactSolverError as exc:
                raise self._named(exc, order[start + np.asarray(exc.rows, int)], m) from None
            forces[start:stop], guess[start:stop] = f, clamped
        acc = self.free_acceleration.copy()
        assembly.add_forces(jac, b1, b2, self.inverse_mass, forces, acc)
        out_forces, out_rates, out_guess = np.empty_like(forces), np.empty_like(rates), guess.copy()
        out_forces[order], out_rates[order], out_guess[order] = forces, rates, guess
        problem.guess[:] = out_guess[:m]
        return LinkedSolution(acc, out_forces[:m], out_rates[:m], out_forces[m:])

    def _named(self, exc: lcp.ContactSolverError, rows: np.ndarray, m: int):
        """The solver's failure with its joint rows named (its contact rows in problem order)."""
        joints = sorted({self.joints.names[r - m] for r in rows.tolist() if r >= m})
        named = f"{exc}; joints involved: {', '.join(joints) or 'none'}"
        return lcp.ContactSolverError(named, [r for r in rows.tolist() if r < m])

    # -- islands, impacts, presses -----------------------------------------------------------

    def joined(self, body1: np.ndarray, body2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The body pairs ``body1``, ``body2`` (of contacts) with the joints' pairs added: what
        joins bodies into islands."""
        if self.joints is None:
            return body1, body2
        return (np.concatenate([body1, self.joints.body1]),
                np.concatenate([body2, self.joints.body2]))  # fmt: skip

    def _dense(self, rows: Rows, columns: np.ndarray) -> np.ndarray:
        return rows.dense_jacobian(self.n)[:, columns]

    def impacts(
        self, joint_rows: Rows, bodies, velocities, rows: Rows, touching, keys, recent, limits
    ):
        """runtime.step.classify's impacts with the joints held: (impulse per contact, velocity
        change (n, 3)); ``joint_rows`` at the state of ``rows`` (see the module docstring)."""
        n = self.n
        b1, b2 = self.joined(rows.body1[touching], rows.body2[touching])
        body_label = body_islands(n, b1, b2, bodies.fixed)
        label = contact_islands(body_label, rows.body1, rows.body2, bodies.fixed)
        joint_label = body_label[joint_rows.body1]
        rate = rows.gap_velocity
        e = np.maximum(bodies.restitution[rows.body1], bodies.restitution[rows.body2])
        e[member(keys, recent) & (rate < -limits.resting_speed)] = 0.0
        weight = bodies.inverse_mass.ravel()
        p, dv = np.zeros(len(rate)), np.zeros(3 * n)
        for g in np.unique(label[touching]):
            island = touching[label[touching] == g]
            if not np.any(rate[island] < -limits.creep_speed):
                continue
            members = np.flatnonzero(body_label == g)
            columns = (3 * members[:, None] + np.arange(3)).ravel()
            w = weight[columns]
            jc = self._dense(rows.take(island), columns)
            held = np.flatnonzero(joint_label == g)
            jj = self._dense(joint_rows.take(held), columns)
            a_cc, a_cj, a_jj = (jc * w) @ jc.T, (jc * w) @ jj.T, (jj * w) @ jj.T
            inverse = np.linalg.pinv(a_jj, rcond=settings.JOINT_RANK, hermitian=True)
            A = a_cc - a_cj @ inverse @ a_cj.T
            A = 0.5 * (A + A.T)
            joint_rate = joint_rows.gap_velocity[held]
            outcome = impulses.resolve(
                A, rate[island] - a_cj @ inverse @ joint_rate, e[island],
                limits.resting_speed, limits.creep_speed,
            )  # fmt: skip
            held_impulse = -inverse @ (joint_rate + a_cj.T @ outcome.impulses)
            p[island] = outcome.impulses
            dv[columns] += w * (jc.T @ outcome.impulses + jj.T @ held_impulse)
        return p, dv.reshape(n, 3)

    def frame_impacts(self, q: np.ndarray, v: np.ndarray):
        """The ``impacts`` hook of runtime.step.classify.make_frame for a frame at (q, v)."""
        if self.joints is None:
            return None
        return partial(self.impacts, self.joints.rows(q, v))

    def hold_joints(self, q: np.ndarray, before, done, solve):
        """(frame, solution) ``done`` (runtime.step.resting.settle of the frame ``before``) with
        the change of the joints' d' that a press made undone (:meth:`held_velocities`), and
        the forces solved again; ``done`` itself if nothing was pressed. Never a drift
        correction: with a Stabilisation, which damps d' as well (d'' = -k_d d' - k_p d), it
        is left alone."""
        frame, _ = done
        pressed = frame.velocities is not before.velocities
        if self.joints is None or self.stabilisation is not None or not pressed:
            return done
        held = self.held_velocities(q, before.velocities, frame.velocities)
        if held is frame.velocities:
            return done
        dv = held - frame.velocities
        frame = replace(frame, velocities=held, rows=frame.rows.with_velocity_change(dv))
        return frame, solve(frame)

    def held_velocities(self, q: np.ndarray, v0: np.ndarray, v1: np.ndarray) -> np.ndarray:
        """``v1`` (velocities after a jump from ``v0`` that ignored the joints: a press, an
        impulse applied by hand) with the joints' part of the jump undone: the least-energy
        joint impulse (W J^T lambda) that gives the joints their d' at ``v0`` back. ``v1``
        itself when the jump did not move a joint."""
        if self.joints is None:
            return v1
        rows = self.joints.rows(q, v1, with_gaps=False)
        change = rows.rate_change(v1 - v0)
        if not np.any(np.abs(change) > settings.CREEP * settings.RESTING_SPEED):
            return v1
        jac = rows.dense_jacobian(self.n)
        weight = self.inverse_mass.ravel()
        a_jj = (jac * weight) @ jac.T
        impulse = -np.linalg.pinv(a_jj, rcond=settings.JOINT_RANK, hermitian=True) @ change
        return v1 + (weight * (jac.T @ impulse)).reshape(self.n, 3)
