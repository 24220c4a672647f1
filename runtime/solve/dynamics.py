"""Accelerations of all bodies under gravity and contact forces (Baraff's method).

For the resting contacts, d'' = J acc + bias with acc = M^-1 (F_ext + J^T f), so
d'' = A f + b with A = J M^-1 J^T and b = J M^-1 F_ext + bias; the LCP (runtime.solve.lcp) gives the
forces f >= 0 with d'' >= 0 and f.d'' = 0. Every term of J and bias comes from the generated
kernels (runtime.solve.kernels); nothing of the derivation is typed here.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from runtime.solve import lcp
from runtime.solve.kernels import ContactRows, evaluate, load_cases


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


@dataclass(frozen=True)
class ContactSolution:
    accelerations: np.ndarray  # (n, 3)
    forces: np.ndarray  # (m,)
    rows: ContactRows | None
    free_gap_acceleration: np.ndarray  # b: d'' of each contact if its force were zero


class ContactDynamics:
    """The right-hand side of the equations of motion of one scene."""

    def __init__(
        self,
        scene,
        stabilisation: Stabilisation | None = None,
        solver: Callable[..., np.ndarray] = lcp.solve,
    ) -> None:
        self.scene = scene
        self.modules = load_cases(scene.contact_cases())
        self.fixed = list(scene.fixed)
        self.inverse_mass = scene.inverse_masses  # (n, 3)
        moving = ~np.asarray(self.fixed, dtype=bool)
        self.free_acceleration = np.zeros((len(self.fixed), 3))
        self.free_acceleration[moving, :2] = scene.gravity
        self.stabilisation = stabilisation
        self.solver = solver

    def rows(
        self, contacts: Sequence, poses: np.ndarray, velocities: np.ndarray, with_gaps: bool = True
    ) -> ContactRows:
        return evaluate(contacts, self.modules, poses, velocities, self.fixed, with_gaps)

    def effective_mass_matrix(self, rows: ContactRows) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(A, J, J M^-1) for the rows, with A = J M^-1 J^T ((m, m), symmetric PSD)."""
        jac = rows.dense_jacobian(len(self.fixed))
        jm = jac * self.inverse_mass.ravel()
        return jm @ jac.T, jac, jm

    def solve(
        self, contacts: Sequence, poses: np.ndarray, velocities: np.ndarray
    ) -> ContactSolution:
        """Accelerations with the contact forces of `contacts` (the resting set)."""
        if not contacts:
            return ContactSolution(self.free_acceleration.copy(), np.zeros(0), None, np.zeros(0))
        rows = self.rows(contacts, poses, velocities, with_gaps=self.stabilisation is not None)
        a_matrix, jac, jm = self.effective_mass_matrix(rows)
        b = jac @ self.free_acceleration.ravel() + rows.bias
        if self.stabilisation is not None:
            b = b + self.stabilisation.damping * rows.gap_velocity
            b = b + self.stabilisation.stiffness * rows.gap
        if not (np.all(np.isfinite(a_matrix)) and np.all(np.isfinite(b))):
            with np.errstate(all="ignore"):
                fastest = float(np.max(np.abs(velocities)))
            raise FloatingPointError(
                f"the contact terms of {len(contacts)} contact(s) are not finite: the state "
                f"overflows float64 (largest velocity component {fastest:.3g})"
            )
        forces = self.solver(a_matrix, b)
        acc = self.free_acceleration.ravel() + jm.T @ forces
        return ContactSolution(acc.reshape(-1, 3), forces, rows, b)
