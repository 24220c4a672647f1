"""The guards of runtime.step.world, checked for each copy of an ensemble on its own.

Why: a World checks the whole scene -- its energy, its deepest overlap -- and stops at the first
problem. In an ensemble each copy is its own scene: its energy is compared with its own start
and scale, an overlap or a tunnelled body fails only its copy, and every copy that fails in a
step is found at once (vectorised over the copies), with the message its own `simulate` run
would give (body names of the template; the checks in World.step's order: overlap left by the
last step, non-finite state, a centre of mass through a fixed edge, two bodies through each
other, energy growth).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from runtime.collide.broadphase import candidate_pairs
from runtime.model.scene import Scene
from runtime.step.copies import Copies, Layout
from runtime.step.guards import FixedEdges, Guards, inner_radius, pair_passed_through
from runtime.step.world import _TOO_LARGE


class CopyGuards:
    """Per-copy guards of :class:`~runtime.step.copies.Copies` (see the module docstring)."""

    def __init__(self, copies: Copies, guards: Guards, method: str) -> None:
        template = copies.template
        self.limits, self.method = guards, method
        self.names = template.names
        self.fixed = np.asarray(template.fixed, dtype=bool)
        self.moving = np.flatnonzero(~self.fixed)
        self.radii = np.array([s.bounding_radius for s in template.shapes], dtype=float)
        self.inner = np.array([inner_radius(s) for s in template.shapes])
        self.mass = np.zeros((copies.count, copies.n))
        self.inertia = np.zeros((copies.count, copies.n))
        for j, i in enumerate(copies.own.tolist()):
            if not self.fixed[i]:
                self.mass[:, i] = [own[j].mass for own in copies.bodies]
                self.inertia[:, i] = [own[j].inertia for own in copies.bodies]
        self.gravity = copies.gravity
        self.edges = []  # (fixed template body, its edges in its own frame)
        if guards.penetration is not None:
            for f in np.flatnonzero(self.fixed).tolist():
                body = template.bodies[f]
                alone = Scene("edges", [_at_origin(body)])
                self.edges.append((f, FixedEdges(alone)))
        closed = self.inner > 0
        self.pairs = int(np.sum(closed)) >= 2 and bool(np.any(closed & ~self.fixed))
        self.energy0 = self.scale = np.zeros(copies.count)

    # -- energy ----------------------------------------------------------------------------

    def _of(self, members: np.ndarray, table: np.ndarray) -> np.ndarray:
        """The moving bodies' columns of a per-copy table (N, n) for the members."""
        rows = table if len(members) == len(table) else table[members]  # all: in order
        return rows[:, self.moving]

    def kinetic(self, members: np.ndarray, v: np.ndarray) -> np.ndarray:
        """(M,) kinetic energy of each member copy; ``v`` (M, n, 3)."""
        v = v[:, self.moving]
        terms = 0.5 * self._of(members, self.mass) * (v[..., 0] ** 2 + v[..., 1] ** 2)
        terms += 0.5 * self._of(members, self.inertia) * v[..., 2] ** 2
        return np.sum(terms, axis=1)

    def energy(self, members: np.ndarray, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """(M,) mechanical energy (kinetic + gravitational) of each member copy (J)."""
        g, q = self.gravity[members], q[:, self.moving]
        height = g[:, None, 0] * q[..., 0] + g[:, None, 1] * q[..., 1]
        potential = np.sum(-self._of(members, self.mass) * height, axis=1)
        return self.kinetic(members, v) + potential

    def start(self, members: np.ndarray, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """Remember each copy's energy and energy scale at t = 0
        (runtime.step.guards.energy_scale); returns the energies."""
        with np.errstate(all="ignore"):
            energy = self.energy(members, q, v)
            g = np.hypot(self.gravity[members, 0], self.gravity[members, 1])
            y = q[..., 1]
            height = np.max(y + self.radii, axis=1) - np.min(y - self.radii, axis=1)
            r = self.radii[self.moving]
            weight = self._of(members, self.mass) * g[:, None] * (height[:, None] + 2.0 * r)
            scale = self.kinetic(members, v) + np.sum(weight, axis=1)
        self.energy0, self.scale = energy, scale
        if self.limits.energy_growth is None:
            self.scale = np.zeros_like(scale)
        return energy

    # -- the checks ------------------------------------------------------------------------

    def overlaps(self, layout: Layout, frame, step: int, t: float, before: float) -> dict:
        """{member: message} of the copies whose contacts at the start of ``step`` (at time t)
        overlap deeper than the penetration limit: left by step - 1 (begun at ``before``),
        or at step 0 the copy starts that way."""
        limit = self.limits.penetration
        rows = frame.rows
        if limit is None or not np.any(rows.gap < 0.0):
            return {}
        depth = -rows.gap
        radii = self.radii[layout.template]
        relative = depth / np.minimum(radii[rows.body1], radii[rows.body2])
        copy = self._copy_of(layout, rows.body1, rows.body2)
        failed = {}
        for m in np.unique(copy[(depth > 0) & (relative > limit)]).tolist():
            mine = np.flatnonzero((copy == m) & (depth > 0))
            k = int(mine[np.argmax(relative[mine])])
            pair = self.contact_names(layout, frame.contacts.take([k]))
            size = (
                f"{depth[k]:.3g} m, {relative[k]:.3g} of the smaller body's size (limit {limit:g})"
            )
            if step == 0:
                everything = frame.contacts.take(np.flatnonzero(copy == m))
                failed[m] = (
                    f"step 0 at t = {t:.6g} s starts with {pair} overlapping by {size}; "
                    f"contacts: {self.contact_names(layout, everything)}"
                )
            else:
                failed[m] = (
                    f"step {step - 1} at t = {before:.6g} s left {pair} overlapping by {size}: "
                    f"{_TOO_LARGE}"
                )
        return failed

    def after_step(self, layout: Layout, q, new_q, per_copy, energy, skip: set) -> dict:
        """{member: what went wrong} (World.step's words) of the copies other than ``skip``
        whose step from poses ``q`` to ``new_q`` (combined, (bodies, 3); ``per_copy``: the
        poses before, and the poses and velocities after, per copy (M, n, 3)) gave a
        non-finite state, a centre of mass through a fixed edge, two bodies through each other,
        or an energy ``energy`` (M,) too high."""
        failed: dict[int, str] = {}
        qc, new_qc, new_vc = per_copy
        finite = np.all(np.isfinite(new_qc) & np.isfinite(new_vc), axis=(1, 2))
        for m in np.flatnonzero(~finite).tolist():
            failed.setdefault(m, "produced a non-finite state")
        if self.limits.penetration is not None:
            self._tunnelled(qc, new_qc, failed, skip)
            if self.pairs:
                self._passed_through(layout, q, new_q, failed, skip)
        if self.limits.energy_growth is not None:
            growth = self.limits.energy_growth
            e0, scale = self.energy0[layout.members], self.scale[layout.members]
            with np.errstate(invalid="ignore"):
                high = (scale > 0) & (energy - e0 > growth * scale)
            for m in np.flatnonzero(high).tolist():
                failed.setdefault(
                    m,
                    f"raised the energy from {e0[m]:.6g} J at t = 0 to {energy[m]:.6g} J, more "
                    f"than {growth:g} x the scene's energy scale {scale[m]:.3g} J (no contact "
                    f"adds energy): the time step is too large for {self.method}",
                )
        return {m: what for m, what in failed.items() if m not in skip}

    def _tunnelled(self, qc, new_qc, failed: dict, skip: set) -> None:
        """A moving centre of mass whose straight path crosses an edge of a fixed body of its
        copy: checked in each fixed body's own frame, so one FixedEdges serves every copy."""
        moving, k = self.moving, len(self.moving)
        for f, edges in self.edges:
            pose = qc[:, f]
            p0 = _local(qc[:, moving, :2], pose).reshape(-1, 2)
            p1 = _local(new_qc[:, moving, :2], pose).reshape(-1, 2)
            for m in set(failed) | skip:  # copies already failed: as if they had not moved
                p1[m * k : (m + 1) * k] = p0[m * k : (m + 1) * k]
            while (hit := edges.crossing(p0, p1)) is not None:
                m, j = divmod(hit[0], k)
                failed[m] = (
                    f"moved the centre of mass of {self.names[moving[j]]} through "
                    f"{self.names[f]} (it tunnelled): {_TOO_LARGE}"
                )
                p1[m * k : (m + 1) * k] = p0[m * k : (m + 1) * k]

    def _passed_through(self, layout: Layout, q, new_q, failed: dict, skip: set) -> None:
        """Two bodies of one copy whose centres came inside each other's inscribed circle
        (World._moving_pairs and runtime.step.guards.passed_through, per copy)."""
        inner = self.inner[layout.template]
        mid = 0.5 * (q[:, :2] + new_q[:, :2])
        half = 0.5 * np.hypot(*(new_q[:, :2] - q[:, :2]).T)
        hollow = self.fixed[layout.template] | (inner == 0)
        groups = np.asarray(layout.scene.groups, dtype=np.int64)
        with np.errstate(invalid="ignore"):
            i, j = candidate_pairs(mid, half + inner, hollow, 0.0, groups)
        copy = self._copy_of(layout, i, j)
        keep = (inner[i] > 0) & (inner[j] > 0) & ~np.isin(copy, list(set(failed) | skip))
        i, j, copy = i[keep], j[keep], copy[keep]
        while (hit := pair_passed_through(q, new_q, inner, i, j)) is not None:
            m = int(copy[hit])
            a, b = self.names[layout.template[i[hit]]], self.names[layout.template[j[hit]]]
            failed[m] = (
                f"moved {a} and {b} through each other (a centre of mass came inside the other "
                f"body's inscribed circle): {_TOO_LARGE}"
            )
            rest = copy != m
            i, j, copy = i[rest], j[rest], copy[rest]

    # -- names -----------------------------------------------------------------------------

    @staticmethod
    def _copy_of(layout: Layout, body1: np.ndarray, body2: np.ndarray) -> np.ndarray:
        """Member position of each contact or pair (that of its body in a copy)."""
        one = layout.member[body1]
        return np.where(one >= 0, one, layout.member[body2])

    def contact_names(self, layout: Layout, contacts) -> str:
        """runtime.step.guards.contact_names with the template's body names."""
        t = layout.template
        pairs = zip(t[contacts.body1].tolist(), t[contacts.body2].tolist(), strict=True)
        return ", ".join(sorted({f"{self.names[i]}/{self.names[j]}" for i, j in pairs})) or "none"

    def copy_contacts(self, layout: Layout, contacts, m: int):
        """The contacts of member ``m``."""
        return contacts.take(
            np.flatnonzero(self._copy_of(layout, contacts.body1, contacts.body2) == m)
        )


def _at_origin(body):
    """The fixed body placed at (0, 0) with angle 0: its edges in its own frame."""
    return replace(body, position=(0.0, 0.0), angle=0.0)


def _local(points: np.ndarray, pose: np.ndarray) -> np.ndarray:
    """Points (M, k, 2) in the frame of the poses (M, 3) (one per copy)."""
    c, s = np.cos(pose[:, 2])[:, None], np.sin(pose[:, 2])[:, None]
    dx, dy = points[..., 0] - pose[:, None, 0], points[..., 1] - pose[:, None, 1]
    return np.stack([c * dx + s * dy, -s * dx + c * dy], axis=-1)
