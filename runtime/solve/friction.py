"""Contact forces with Coulomb friction: the modes (stick, slide +-) and the forces they give.

Why modes: a trial step must integrate a smooth right-hand side, and friction is smooth only
while no contact changes between sticking and sliding. So at a frame (the start of a step or
sub-step) each frictional resting contact gets a mode, kept for the whole trial:

* |v_t| > the stick speed: sliding against v_t (slide = sign v_t, f_t = -slide mu f_n); the stick
  speed is settings.STICK_SPEED, or the creep the integrator may leave in a step of the
  stepper's length (settings.STICK_DRIFT, :attr:`FrictionalForces.stick_speed`);
* otherwise sticking, unless the friction LCP (runtime.solve.friction_lcp) says it slips at once
  (its slack lambda > settings.SLIP_ONSET: the force needed to hold it exceeds mu f_n); then it
  slides the way it accelerates. Decided again until no sticking contact slips (a contact that
  slips can make its neighbour slip);
* if no forces obey Coulomb's law with these modes (a Painleve configuration, e.g. in a pile of
  discs), the contacts sliding slower than the resting speed are made to stick (their slip is
  then removed by runtime.step.friction_hold's impulse, as an approach slower than the resting
  speed is made plastic); if that does not help either, the island's sliding contacts jam:
  they are made to stick, their slip removed by the same impulse (the tangential impact that
  resolves Painleve's paradox: a falling 30-disc pile with mu = 1 met one); if that does not
  help either (no contact slides), the named error stands;
* where every contact of an island sticks and the forces found open or slip one of them, the
  island is held instead if forces in the cones can hold it (runtime.solve.friction_lcp._moves:
  the LCP with friction can have more than one solution). So where Lemke's first path (and its
  perturbed retries) finds no forces, the held linear program comes before the other covering
  vectors (runtime.solve.lemke.lemke_perturbed): were the island held, their solution would be
  held too, and a path of a packed 60-disc pile's 660 unknowns costs ~0.5 s; an island that
  large (settings.HELD_FIRST) with no remembered basis that solves it is tried held first.

The transitions inside a step (stick -> slip when |f_t| reaches mu f_n, slip -> stick when v_t
crosses 0) are located by runtime.step.friction_events and start a new frame there.

Islands without a frictional contact are solved as without friction (runtime.solve.forces),
bit for bit; the others by Lemke's method on the friction LCP, first tried from the basis each
contact had at its last solve (runtime.solve.friction_lcp).
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from runtime import settings
from runtime.collide.contact_keys import Guesses
from runtime.solve.forces import ContactForces, ForceProblem, ForceSolution
from runtime.solve.friction_lcp import (
    MOVES,
    FrictionInconsistent,
    island_slips,
    painleve,
    solve_held,
    solve_islands,
)
from runtime.solve.friction_rows import FrictionRows

_COVERS = settings.LEMKE_COVERS  # Lemke's covering vectors where a failure has an answer


@dataclass
class FrictionProblem(ForceProblem):
    """A ForceProblem with each contact's friction mode ``slide`` (0 stick or frictionless,
    +-1 sliding with v_t of that sign; None until the first solve decides it) and ``basis``,
    its basis flags in the friction LCP's last solve (runtime.solve.friction_lcp: the warm
    start of the next)."""

    slide: np.ndarray | None = None
    basis: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.basis is None:
            self.basis = np.zeros(len(self.keys), np.int8)

    def compiled_args(self, mu: np.ndarray, fixed: np.ndarray) -> tuple:
        """Its contacts as runtime.step.compiled_friction's step, friction_quiet and
        friction_state take them: (case, body1, body2, geometry, static2, ends, offsets, mu,
        slide, basis) -- ``mu`` each contact's coefficient, ``fixed`` the bodies'; the basis
        flags themselves (the compiled solves update them, as :meth:`FrictionalForces.solve`)."""
        c = self.contacts
        return (
            c.case, c.body1, c.body2, c.geometry, np.ascontiguousarray(fixed[c.body2]),
            np.ascontiguousarray(np.column_stack([c.body1, c.body2])), self.offsets, mu,
            self.slide.astype(float), self.basis,
        )  # fmt: skip

    def subset(self, keep: np.ndarray) -> FrictionProblem:
        base = ForceProblem.subset(self, keep)
        index = np.flatnonzero(keep)
        slide = None if self.slide is None else self.slide[index]
        return FrictionProblem(
            **{f.name: getattr(base, f.name) for f in fields(base)},
            slide=slide,
            basis=self.basis[index],
        )


@dataclass(frozen=True)
class FrictionSolution(ForceSolution):
    """Also the friction forces f_t (m,), the tangential accelerations a_t (m,) and ``slips``
    (m,): sticking contacts whose slack is above settings.SLIP_ONSET (the hold needs more than
    mu f_n: they start to slide) and whose normal force is not 0 (without it, sticking and
    sliding give the same force, 0: a contact lifting off is not a transition)."""

    tangent_forces: np.ndarray = None
    tangent_accelerations: np.ndarray = None
    slips: np.ndarray = None


class FrictionalForces(ContactForces):
    """ContactForces with Coulomb friction (see the module docstring). ``stick_speed``: the
    largest |v_t| that sticks, set by the stepper for its step length at each frame
    (runtime.step.classify.Limits)."""

    stick_speed = settings.STICK_SPEED

    def __init__(self, scene, stabilisation=None) -> None:
        super().__init__(scene, stabilisation)
        self.bases = Guesses(dtype=np.int8)  # contact key -> basis flags at its last solve

    def problem(self, contacts, island_of_contact, keys) -> FrictionProblem:
        base = super().problem(contacts, island_of_contact, keys)
        basis = self.bases.get(base.keys)
        return FrictionProblem(**{f.name: getattr(base, f.name) for f in fields(base)}, basis=basis)

    def remember(self, problem: FrictionProblem) -> None:
        super().remember(problem)
        self.bases.update(problem.keys, problem.basis)

    def solve(self, problem: FrictionProblem, rows: FrictionRows) -> FrictionSolution:
        """Forces and accelerations with each contact's mode; the modes are decided at the
        problem's first solve (its frame). With the modes decided a failure ends the run, so
        there Lemke's method tries settings.LEMKE_COVERS_LAST covering vectors before it."""
        if problem.slide is None:
            problem.slide = self._decide(problem, rows)
        return self._solve(problem, rows, problem.slide, final=True)

    def _decide(self, problem: FrictionProblem, rows: FrictionRows) -> np.ndarray:
        v_t = rows.tangent_velocity
        slide = np.where((rows.mu > 0) & (np.abs(v_t) > self.stick_speed), np.sign(v_t), 0.0)
        slow = (slide != 0) & (np.abs(v_t) <= settings.RESTING_SPEED)
        jammed = np.zeros_like(slow)
        final = False
        for _ in range(2 * len(slide) + 2):
            try:
                solution = self._solve(problem, rows, slide, final)
            except FrictionInconsistent as error:
                if slow.any():
                    slide, slow = np.where(slow, 0.0, slide), np.zeros_like(slow)
                    continue
                sliding = [r for r in error.rows if slide[r] != 0]
                if not sliding:
                    if final:
                        raise
                    # nothing left to stick: the failure would end the run, so the covering
                    # vectors of a final solve (a 38-contact island of a falling 20-disc pile
                    # with mu = 0.5, every contact sticking: not held, none of the first
                    # LEMKE_COVERS solved it, a later one did)
                    final = True
                    continue
                slide = slide.copy()
                slide[sliding], jammed[sliding] = 0.0, True
                continue
            slips = solution.slips & ~jammed
            if not slips.any():
                break
            slide = slide.copy()
            slide[slips] = np.sign(solution.tangent_accelerations[slips])
        return slide

    def _solve(
        self, problem, rows: FrictionRows, slide: np.ndarray, final: bool
    ) -> FrictionSolution:
        m = len(rows.bias)
        frictional = rows.mu > 0
        if not frictional.any():
            base = super().solve(problem, rows)
            return FrictionSolution(*_values(base), np.zeros(m), np.zeros(m), np.zeros(m, bool))
        offsets = problem.offsets
        island = np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))
        with_friction = np.zeros(len(offsets) - 1, dtype=bool)
        with_friction[island[frictional]] = True
        plain = ~with_friction[island]
        acc = self.free_acceleration.copy()
        forces, rates, tangent, a_t = np.zeros(m), np.zeros(m), np.zeros(m), np.zeros(m)
        slips = np.zeros(m, dtype=bool)
        if plain.any():
            sub = problem.subset(plain)
            base = super().solve(sub, rows.take(plain))
            problem.guess[plain] = sub.guess  # the warm starts the solve updated
            if problem.loaded is not None:
                problem.loaded[plain] = sub.loaded
            acc += base.accelerations - self.free_acceleration
            forces[plain], rates[plain] = base.forces, base.free_rates
        bias = rows.bias
        if self.stabilisation is not None:
            k = self.stabilisation
            bias = bias + k.damping * rows.gap_velocity + k.stiffness * rows.gap
        ends = np.ascontiguousarray(np.column_stack([rows.body1, rows.body2]))
        jac, tangent_jac = rows.jacobian, rows.tangent_jacobian
        slack = np.zeros(m)
        slide = slide.astype(float)
        args = (
            offsets, jac, tangent_jac, ends, bias, rows.tangent_bias, rows.mu, slide,
            self.inverse_mass, self.fixed, self.free_acceleration, forces, tangent, slack, a_t,
            rates, acc, problem.basis,
        )  # fmt: skip
        todo = np.flatnonzero(with_friction)
        while todo.size:
            failed, status = solve_islands(todo, *args, slips, True, 0)
            if failed < 0:
                break
            g = todo[failed]
            a, b = int(offsets[g]), int(offsets[g + 1])
            held = solve_held(
                jac[a:b], tangent_jac[a:b], ends[a:b], bias[a:b], rows.tangent_bias[a:b],
                rows.mu[a:b], slide[a:b], self.inverse_mass, self.fixed, self.free_acceleration,
                forces[a:b], tangent[a:b], slack[a:b], a_t[a:b], rates[a:b], acc,
                problem.basis[a:b],
            )  # fmt: skip
            if held:
                island_slips(forces[a:b], slack[a:b], rates[a:b], slips[a:b])
            else:  # Lemke's solution that moves, found again; Lemke's method where the held
                # program came first (HOLD_FIRST); other covering vectors, more where a failure
                # ends the run
                covers = settings.LEMKE_COVERS_LAST if final and status != MOVES else _COVERS
                one = todo[failed : failed + 1]
                if solve_islands(one, *args, slips, False, covers)[0] >= 0:
                    raise painleve(rows.mu[a:b], slide[a:b], a)
            todo = todo[failed + 1 :]
        return FrictionSolution(acc, forces, rates, tangent, a_t, slips)


def _values(solution: ForceSolution) -> tuple:
    return tuple(getattr(solution, f.name) for f in fields(ForceSolution))
