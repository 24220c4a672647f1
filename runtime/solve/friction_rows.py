"""Tangential (friction) rows beside the normal ones, from generated/compiled/<case>_friction.py.

Why: Coulomb friction acts along t = n turned by +90 degrees at the contact point; its force
enters the accelerations like a normal force with the tangential Jacobian row J_t, and a
sticking contact keeps d/dt v_t = J_t acc + tangent bias at 0 (docs/conventions.md,
"Tangential (friction) rows"). Nothing of the derivation is typed here: the rows come from the
generated batch loops, and only for the cases a scene can produce. A scene whose contacts all
have mu = 0 never builds this evaluator (runtime.step.friction_stage), so it never imports a
friction kernel.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterable
from dataclasses import dataclass, replace
from types import ModuleType

import numpy as np

import generated
from runtime.collide.contact_set import Contacts
from runtime.solve.rows import RowEvaluator, Rows


def load_friction_cases(cases: Iterable[str]) -> dict[int, ModuleType]:
    """generated/compiled/<case>_friction.py for each case, by case id."""
    modules = {}
    for case in sorted(cases):
        if case not in generated.FRICTION_CASES:
            raise RuntimeError(
                f"no generated friction row for contact case {case!r}: run "
                f"`regenerate-equations --cases {case}_friction`"
            )
        module = importlib.import_module(f"generated.compiled.{case}_friction")
        modules[generated.CASE_ID[case]] = module
    return modules


def contact_friction(friction: np.ndarray, contacts: Contacts) -> np.ndarray:
    """mu of each contact: sqrt(mu1 mu2) of its bodies' coefficients (issue #15)."""
    return np.sqrt(friction[contacts.body1] * friction[contacts.body2])


@dataclass(frozen=True)
class FrictionRows(Rows):
    """Rows with each contact's friction coefficient ``mu`` (m,), tangential speed
    ``tangent_velocity`` v_t (m,), row ``tangent_jacobian`` (m, 6) and ``tangent_bias`` (m,)."""

    mu: np.ndarray = None
    tangent_velocity: np.ndarray = None
    tangent_jacobian: np.ndarray = None
    tangent_bias: np.ndarray = None

    def take(self, index) -> FrictionRows:
        normal = Rows.take(self, index)
        return FrictionRows(
            *(getattr(normal, f) for f in Rows.__dataclass_fields__),
            mu=self.mu[index],
            tangent_velocity=self.tangent_velocity[index],
            tangent_jacobian=self.tangent_jacobian[index],
            tangent_bias=self.tangent_bias[index],
        )

    def with_velocity_change(self, dv: np.ndarray) -> FrictionRows:
        shifted = np.einsum("kc,kc->k", self.tangent_jacobian[:, :3], dv[self.body1])
        shifted += np.einsum("kc,kc->k", self.tangent_jacobian[:, 3:], dv[self.body2])
        return replace(
            self,
            gap_velocity=self.gap_velocity + self.rate_change(dv),
            tangent_velocity=self.tangent_velocity + shifted,
        )


class FrictionRowEvaluator(RowEvaluator):
    """The normal rows (RowEvaluator) and the tangential rows of one scene's contacts."""

    def __init__(self, cases: Iterable[str], fixed: np.ndarray, friction: np.ndarray) -> None:
        cases = list(cases)
        super().__init__(cases, fixed)
        self.friction_modules = load_friction_cases(cases)
        self.friction = np.asarray(friction, dtype=float)

    def mu(self, contacts: Contacts) -> np.ndarray:
        """Each contact's friction coefficient (:func:`contact_friction`)."""
        return contact_friction(self.friction, contacts)

    def rows(
        self, contacts: Contacts, poses: np.ndarray, velocities: np.ndarray, with_gaps: bool = True
    ) -> FrictionRows:
        normal = super().rows(contacts, poses, velocities, with_gaps)
        m = len(contacts)
        rate, bias, jacobian = np.zeros(m), np.zeros(m), np.zeros((m, 6))
        if m:
            static2 = self.fixed[contacts.body2]
            for _, members in self._groups(contacts):
                module = self.friction_modules[int(contacts.case[members[0]])]
                module.batch_tangent_all(
                    poses, velocities, contacts.body1, contacts.body2, contacts.geometry,
                    static2, members, rate, jacobian, bias,
                )  # fmt: skip
        return FrictionRows(
            *(getattr(normal, f) for f in Rows.__dataclass_fields__),
            mu=self.mu(contacts),
            tangent_velocity=rate,
            tangent_jacobian=jacobian,
            tangent_bias=bias,
        )

    def tangent_velocity(
        self, contacts: Contacts, poses: np.ndarray, velocities: np.ndarray
    ) -> np.ndarray:
        """v_t of every contact at the state (for watching sliding contacts over a step)."""
        out = np.zeros(len(contacts))
        if len(contacts):
            static2 = self.fixed[contacts.body2]
            for _, members in self._groups(contacts):
                module = self.friction_modules[int(contacts.case[members[0]])]
                module.batch_tangent_velocity(
                    poses, velocities, contacts.body1, contacts.body2, contacts.geometry,
                    static2, members, out,
                )  # fmt: skip
        return out


def island_bodies(body1: np.ndarray, body2: np.ndarray, fixed: np.ndarray):
    """(moving bodies of these rows, sorted; each body's index among them) for dense rows."""
    ends = np.concatenate([body1, body2])
    moving = np.unique(ends[~fixed[ends]])
    local = np.zeros(len(fixed), dtype=np.int64)
    local[moving] = np.arange(moving.size)
    return moving, local


def dense_rows(rows6, body1, body2, local, fixed, count: int) -> np.ndarray:
    """(K, 6) rows over each pair's bodies as (K, 3 count) over the ``count`` moving bodies
    (``local``: :func:`island_bodies`), for the small dense solves of impacts and holds."""
    out = np.zeros((len(rows6), 3 * count))
    for side, bodies in ((0, body1), (3, body2)):
        keep = np.flatnonzero(~fixed[bodies])
        cols = 3 * local[bodies[keep]][:, None] + np.arange(3)
        out[keep[:, None], cols] += rows6[keep, side : side + 3]
    return out
