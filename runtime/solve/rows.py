"""Kernel rows: gap d, its rate d', the Jacobian row and the bias of every contact, from the
generated kernels.

Why: everything the step decides about a contact comes from these four numbers: d and d'
classify it (runtime.step.classify) and watch it for impacts (runtime.step.events), the
Jacobian rows J give A = J M^-1 J^T for forces and impulses, and the bias is the velocity part
of d'' in b (note eq. 4, 8, 11, 12). They are evaluated by the compiled batch loops of
generated/compiled/<case>.py, one call per case present; only the cases a scene can produce are
imported (a scene of discs and walls never loads a vertex kernel). Nothing of the derivation is
typed here.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from types import ModuleType

import numpy as np

import generated
import runtime.compiled  # noqa: F401  (sets numba's cache folder before the kernels compile)
from runtime.collide.contact_set import Contacts


def load_compiled_cases(cases: Iterable[str]) -> dict[int, ModuleType]:
    """generated/compiled/<case>.py for each case, by case id; nothing else is imported."""
    modules = {}
    for case in sorted(cases):
        if case not in generated.CASES:
            raise RuntimeError(
                f"no generated kernel for contact case {case!r}: run "
                f"`regenerate-equations --cases {case}`"
            )
        modules[generated.CASE_ID[case]] = importlib.import_module(f"generated.compiled.{case}")
    return modules


@dataclass(frozen=True)
class Rows:
    """Kernel rows of m contacts: d, d' (m,), Jacobian (m, 6: body 1 x, y, th, body 2 x, y, th),
    bias (m,), and the contacts' bodies (for assembling A)."""

    gap: np.ndarray
    gap_velocity: np.ndarray
    jacobian: np.ndarray
    bias: np.ndarray
    body1: np.ndarray
    body2: np.ndarray

    def take(self, index) -> Rows:
        return Rows(
            self.gap[index],
            self.gap_velocity[index],
            self.jacobian[index],
            self.bias[index],
            self.body1[index],
            self.body2[index],
        )

    def dense_jacobian(self, n_bodies: int) -> np.ndarray:
        """J as an (m, 3n) matrix: d' = J v and d'' = J acc + bias."""
        m = len(self.gap)
        jac = np.zeros((m, 3 * n_bodies))
        rows = np.arange(m)[:, None]
        jac[rows, 3 * self.body1[:, None] + np.arange(3)] += self.jacobian[:, :3]
        jac[rows, 3 * self.body2[:, None] + np.arange(3)] += self.jacobian[:, 3:]
        return jac

    def rate_change(self, dv: np.ndarray) -> np.ndarray:
        """J dv: the change of d' when the velocities change by dv ((n, 3))."""
        return np.einsum("kc,kc->k", self.jacobian[:, :3], dv[self.body1]) + np.einsum(
            "kc,kc->k", self.jacobian[:, 3:], dv[self.body2]
        )

    def with_velocity_change(self, dv: np.ndarray) -> Rows:
        return replace(self, gap_velocity=self.gap_velocity + self.rate_change(dv))


class RowEvaluator:
    """The kernel rows of one scene's contacts, by the compiled batch loops of its cases."""

    def __init__(self, cases: Iterable[str], fixed: np.ndarray) -> None:
        self.modules = load_compiled_cases(cases)
        self.fixed = np.asarray(fixed, dtype=bool)

    def _groups(self, contacts: Contacts) -> list[tuple[ModuleType, np.ndarray]]:
        case = contacts.case
        if len(case) and case.min() == case.max():  # one case (a pile of discs): no np.unique
            return [(self._module(int(case[0])), np.arange(len(contacts)))]
        present = np.unique(case)
        return [(self._module(int(c)), np.flatnonzero(contacts.case == c)) for c in present]

    def _module(self, case: int) -> ModuleType:
        module = self.modules.get(case)
        if module is None:
            name = next(k for k, v in generated.CASE_ID.items() if v == case)
            raise RuntimeError(f"contact case {name!r} was not loaded for this scene")
        return module

    def gaps(self, contacts: Contacts, poses: np.ndarray) -> np.ndarray:
        """d of every contact at ``poses``."""
        out = np.zeros(len(contacts))
        for module, members in self._groups(contacts):
            module.batch_gap(poses, contacts.body1, contacts.body2, contacts.geometry, members, out)
        return out

    def rows(
        self, contacts: Contacts, poses: np.ndarray, velocities: np.ndarray, with_gaps: bool = True
    ) -> Rows:
        """All four rows at the state; ``with_gaps=False`` skips d and d' (left 0), for the
        integrator stages, which need only J and the bias."""
        m = len(contacts)
        gap, rate, bias = np.zeros(m), np.zeros(m), np.zeros(m)
        jacobian = np.zeros((m, 6))
        if m:
            b1, b2, geometry = contacts.body1, contacts.body2, contacts.geometry
            static2 = self.fixed[b2]
            for module, members in self._groups(contacts):
                module.batch_rows(
                    poses, velocities, b1, b2, geometry, static2, members, jacobian, bias
                )
                if with_gaps:
                    module.batch_gap(poses, b1, b2, geometry, members, gap)
                    module.batch_gap_velocity(
                        poses, velocities, b1, b2, geometry, static2, members, rate
                    )
            _check_finite(jacobian, bias, velocities)
        return Rows(gap, rate, jacobian, bias, contacts.body1, contacts.body2)

    def gap_and_rate(
        self, contacts: Contacts, poses: np.ndarray, velocities: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """d and d' of every contact at the state (for watching contacts over a step)."""
        m = len(contacts)
        gap, rate = np.zeros(m), np.zeros(m)
        if m:
            b1, b2, geometry = contacts.body1, contacts.body2, contacts.geometry
            static2 = self.fixed[b2]
            for module, members in self._groups(contacts):
                module.batch_gap(poses, b1, b2, geometry, members, gap)
                module.batch_gap_velocity(
                    poses, velocities, b1, b2, geometry, static2, members, rate
                )
        return gap, rate

    def watch(self, contacts: Contacts, k: int) -> Callable[[np.ndarray, np.ndarray], tuple]:
        """(poses, velocities) -> (d, d') of contact k alone, the same numbers as gap_and_rate's
        for it. Why: the event search asks for one contact at many instants, and taking it out
        of the set first (eight fancy indexings) and grouping it by case cost 25 us a call, more
        than the kernels (a landing 50-disc pile made 8,000 such calls per 100 steps)."""
        module = self._module(int(contacts.case[k]))
        b1, b2, geometry = contacts.body1, contacts.body2, contacts.geometry
        static2 = self.fixed[b2]
        members = np.array([k])
        gap, rate = np.zeros(len(contacts)), np.zeros(len(contacts))

        def at(poses: np.ndarray, velocities: np.ndarray) -> tuple[float, float]:
            module.batch_gap(poses, b1, b2, geometry, members, gap)
            module.batch_gap_velocity(poses, velocities, b1, b2, geometry, static2, members, rate)
            return float(gap[k]), float(rate[k])

        return at


def _check_finite(jacobian: np.ndarray, bias: np.ndarray, velocities: np.ndarray) -> None:
    """A state that overflows float64 shows first in the contact terms: say so, not NaN."""
    if np.all(np.isfinite(jacobian)) and np.all(np.isfinite(bias)):
        return
    with np.errstate(all="ignore"):
        fastest = float(np.max(np.abs(velocities)))
    raise FloatingPointError(
        f"the contact terms of {len(bias)} contact(s) are not finite: the state overflows "
        f"float64 (largest velocity component {fastest:.3g})"
    )
