"""Contact forces of the resting contacts and the accelerations they give (Baraff's method).

For the resting contacts, d'' = J acc + bias with acc = M^-1 (F_ext + J^T f), so d'' = A f + b
with A = J M^-1 J^T and b = J M^-1 F_ext + bias; the LCP (runtime.solve.lcp) gives forces
f >= 0 with d'' >= 0 and f.d'' = 0. The contacts come grouped by island (runtime.step.islands):
A is block diagonal, so each island is its own small problem. Small islands are assembled and
solved in one compiled call (runtime.solve.assembly), first with the clamped set of the last
solve (the set of contacts that carry a force almost never changes from one integrator stage
or step to the next, so that guess is usually the answer: one Cholesky factorization); an
island whose guess fails, or that is large, goes to the pivoting solver, and its clamped set is
remembered for the next solve (runtime.solve.lcp: the compiled dense solver, warm-started,
for small islands; the sparse path for large ones). An island of settings.LOADED_ISLAND or more
contacts whose guess has dependent rows (a packed or landing pile) keeps its loaded set as its
guess, and solves from it in body space before the dense solver. An island too large for the
compiled call is first tried with the contacts that carried a force at its last solve (its
loaded set, also remembered): its least-norm forces then take one sparse factorization in body
space (runtime.solve.lcp_loaded) instead of the pivoting solver's least-norm stage, 28 ms a
solve for a packed 200-disc pile.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import sparse

from runtime import settings
from runtime.collide.contact_keys import Guesses
from runtime.collide.contact_set import Contacts
from runtime.solve import assembly, lcp, lcp_loaded
from runtime.solve.islands import grouped
from runtime.solve.rows import Rows


@dataclass(frozen=True)
class Stabilisation:
    """Baumgarte drift control for resting contacts: d'' is asked to be -k_d d' - k_p d instead of 0.

    Off by default (accuracy benchmarks run without it). Critical damping for a time scale T is
    k_p = (1/T)^2, k_d = 2/T; T of about 10 time steps is a safe choice.
    """

    stiffness: float  # k_p, 1/s^2
    damping: float  # k_d, 1/s

    @classmethod
    def critically_damped(cls, time_scale: float) -> Stabilisation:
        return cls(1.0 / time_scale**2, 2.0 / time_scale)


@dataclass
class ForceProblem:
    """Resting contacts grouped by island: ``order`` puts the contacts given to
    :meth:`ContactForces.problem` in island order, island g is ``offsets[g]:offsets[g + 1]``
    of that order; ``guess`` is each contact's clamped state (the warm start, updated by
    every solve; a large island's loaded set, runtime.solve.assembly), ``labels`` its island;
    ``loaded`` whether it carried a force at its last solve (the second warm start of islands
    too large for the compiled call, runtime.solve.lcp_loaded; None: not used)."""

    contacts: Contacts
    order: np.ndarray
    offsets: np.ndarray
    guess: np.ndarray
    labels: np.ndarray
    keys: np.ndarray  # of the contacts (runtime.collide.contact_keys)
    loaded: np.ndarray | None = None

    def subset(self, keep: np.ndarray) -> ForceProblem:
        """The problem of the contacts ``keep`` (a bool mask over the problem's rows), whole
        islands only; its guess is a copy."""
        index = np.flatnonzero(keep)
        _, offsets = grouped(self.labels[index])
        return ForceProblem(
            self.contacts.take(index),
            self.order[index],
            offsets,
            self.guess[index].copy(),
            self.labels[index],
            self.keys[index],
            None if self.loaded is None else self.loaded[index].copy(),
        )


@dataclass(frozen=True)
class ForceSolution:
    accelerations: np.ndarray  # (n, 3)
    forces: np.ndarray  # (m,), in the problem's contact order
    free_rates: np.ndarray  # b: d'' of each contact if no contact pushed


class ContactForces:
    """Contact forces of one scene's resting contacts (see the module docstring)."""

    def __init__(self, scene, stabilisation: Stabilisation | None = None) -> None:
        self.fixed = np.asarray(scene.fixed, dtype=bool)
        self.inverse_mass = scene.inverse_masses
        self.free_acceleration = np.zeros((len(self.fixed), 3))
        self.free_acceleration[~self.fixed, :2] = scene.gravity
        self.stabilisation = stabilisation
        self.memory = Guesses(loaded=Guesses())  # contact key -> clamped (loaded) at its last solve

    def problem(
        self, contacts: Contacts, island_of_contact: np.ndarray, keys: np.ndarray
    ) -> ForceProblem:
        """The resting set ``contacts`` (with the island label and the key of each:
        runtime.collide.contact_keys) ordered by island."""
        order, offsets = grouped(island_of_contact)
        ordered = contacts.take(order)
        keys = keys[order]
        guess = self.memory.get(keys)
        loaded = None if self.memory.loaded is None else self.memory.loaded.get(keys)
        return ForceProblem(ordered, order, offsets, guess, island_of_contact[order], keys, loaded)

    def remember(self, problem: ForceProblem) -> None:
        """Keep the problem's clamped (and loaded) sets as the guesses of later problems."""
        self.memory.update(problem.keys, problem.guess)
        if problem.loaded is not None and self.memory.loaded is not None:
            self.memory.loaded.update(problem.keys, problem.loaded)

    def solve(self, problem: ForceProblem, rows: Rows) -> ForceSolution:
        """Accelerations and forces for the problem's contacts with kernel ``rows`` (in the
        problem's order; with gaps when stabilised)."""
        acc = self.free_acceleration.copy()
        m = len(rows.bias)
        if m == 0:
            return ForceSolution(acc, np.zeros(0), np.zeros(0))
        bias = rows.bias
        if self.stabilisation is not None:
            k = self.stabilisation
            bias = bias + k.damping * rows.gap_velocity + k.stiffness * rows.gap
        jac, b1, b2 = rows.jacobian, rows.body1, rows.body2
        forces, rates = np.zeros(m), np.zeros(m)
        offsets = problem.offsets
        solved = np.zeros(len(offsets) - 1, dtype=bool)
        assembly.solve_small_islands(
            jac, b1, b2, bias, self.inverse_mass, self.fixed, self.free_acceleration, offsets,
            problem.guess, settings.LCP_TOL, settings.DENSE_ISLAND, forces, rates, solved,
        )  # fmt: skip
        for g in np.flatnonzero(~solved):  # large islands (sparse), or no solution (named)
            start, stop = int(offsets[g]), int(offsets[g + 1])
            K = stop - start
            A = assembly.island_csr(jac, b1, b2, self.inverse_mass, self.fixed, start, stop)
            found = self._from_loaded_set(problem, rows, A, rates[start:stop], start, stop)
            try:
                f, clamped = found or lcp.solve_warm(
                    sparse.csr_array(A, shape=(K, K)), rates[start:stop],
                    guess=problem.guess[start:stop],
                )  # fmt: skip
            except lcp.ContactSolverError as exc:
                rows_named = [start + r for r in exc.rows]
                raise lcp.ContactSolverError(str(exc), rows_named) from None
            forces[start:stop] = f
            problem.guess[start:stop] = clamped
            if problem.loaded is not None:
                problem.loaded[start:stop] = f > 0.0
        assembly.add_forces(jac, b1, b2, self.inverse_mass, forces, acc)
        return ForceSolution(acc, forces, rates)

    def _from_loaded_set(self, problem: ForceProblem, rows: Rows, A, b, start: int, stop: int):
        """(f, clamped) of a large island from the loaded set of its last solve, or None
        (never solved, or the set has changed): runtime.solve.lcp_loaded."""
        loaded = None if problem.loaded is None else problem.loaded[start:stop]
        if loaded is None or not loaded.any():
            return None
        *B, columns = assembly.island_scaled_jacobian(
            rows.jacobian, rows.body1, rows.body2, self.inverse_mass, self.fixed, start, stop
        )
        return lcp_loaded.solve_loaded(tuple(B), columns, A, b, loaded)
