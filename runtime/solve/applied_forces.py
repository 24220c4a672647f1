"""Applied forces of issue #16: springs, linear and angular damping, mutual gravitation.

Why they are a module of their own: unlike gravity they depend on the state (q, v), so they
enter the free accelerations a0 of Baraff's problem (b = J a0 + bias) at every integrator
stage, not once per scene (runtime.solve.linked_forces). None of them is a constraint: they
are explicit forces, each with its closed form:

* spring between anchors p1 (body 1) and p2 (body 2 or the world), s = p1 - p2, n = s/|s|:
  F1 = -(k (|s| - L) + c n.s') n on body 1 at p1, -F1 on body 2 at p2; energy k (|s| - L)^2 / 2;
* damping: force -k_lin m v and torque -k_ang I w (k in 1/s): accelerations -k_lin v, -k_ang w;
* mutual gravitation between every two moving bodies i, j at centres r apart:
  F_i = G m_i m_j (x_j - x_i) / r^3; energy -G m_i m_j / r.

A scene without any of them never builds this (:meth:`AppliedForces.of` gives None).
"""

from __future__ import annotations

import numpy as np

from runtime.model.links import WORLD

__all__ = ["AppliedForces", "applied_potential"]


class AppliedForces:
    """The applied forces of one scene, as accelerations (n, 3) at a state."""

    def __init__(self, scene) -> None:
        bodies = scene.bodies
        self.n = len(bodies)
        self.fixed = np.asarray(scene.fixed, dtype=bool)
        self.inverse_mass = scene.inverse_masses
        self.mass = np.array([0.0 if b.fixed else b.mass for b in bodies])
        self.damping = np.array(
            [(0.0, 0.0, 0.0) if b.fixed else (b.linear_damping,) * 2 + (b.angular_damping,)
             for b in bodies], dtype=float,
        ).reshape(-1, 3)  # fmt: skip
        springs = scene.springs
        self.body1 = np.array([s.body1 for s in springs], dtype=np.int64)
        self.body2 = np.array([s.body2 for s in springs], dtype=np.int64)
        self.anchor1 = np.array([s.anchor1 for s in springs], dtype=float).reshape(-1, 2)
        self.anchor2 = np.array([s.anchor2 for s in springs], dtype=float).reshape(-1, 2)
        self.rest_length = np.array([s.rest_length for s in springs], dtype=float)
        self.stiffness = np.array([s.stiffness for s in springs], dtype=float)
        self.spring_damping = np.array([s.damping for s in springs], dtype=float)
        self.gravitation = float(scene.mutual_gravity)
        self.moving = np.flatnonzero(~self.fixed)

    @classmethod
    def of(cls, scene) -> AppliedForces | None:
        """The scene's applied forces, or None when it has none."""
        if not (scene.springs or scene.mutual_gravity or scene.damped):
            return None
        return cls(scene)

    def accelerations(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """(n, 3) accelerations (force / m, torque / I) of the applied forces at (q, v)."""
        acc = -self.damping * v
        if self.body1.size:
            self._add_springs(q, v, acc)
        if self.gravitation and self.moving.size > 1:
            self._add_gravitation(q, acc)
        acc[self.fixed] = 0.0
        return acc

    def _ends(self, q: np.ndarray, v: np.ndarray, body: np.ndarray, anchor: np.ndarray):
        """World lever r (anchor minus centre; the anchor itself for the world), point and
        point velocity of each spring end."""
        world = body == WORLD
        safe = np.where(world, 0, body)
        th = np.where(world, 0.0, q[safe, 2])
        c, s = np.cos(th), np.sin(th)
        lever = np.column_stack([c * anchor[:, 0] - s * anchor[:, 1],
                                 s * anchor[:, 0] + c * anchor[:, 1]])  # fmt: skip
        centre = np.where(world[:, None], 0.0, q[safe, :2])
        w = np.where(world, 0.0, v[safe, 2])
        velocity = np.where(world[:, None], 0.0, v[safe, :2])
        velocity = velocity + w[:, None] * np.column_stack([-lever[:, 1], lever[:, 0]])
        return lever, centre + lever, velocity

    def _spring_state(self, q: np.ndarray, v: np.ndarray):
        r1, p1, u1 = self._ends(q, v, self.body1, self.anchor1)
        r2, p2, u2 = self._ends(q, v, self.body2, self.anchor2)
        s = p1 - p2
        length = np.hypot(s[:, 0], s[:, 1])
        return r1, r2, s, length, u1 - u2

    def _add_springs(self, q: np.ndarray, v: np.ndarray, acc: np.ndarray) -> None:
        r1, r2, s, length, rate = self._spring_state(q, v)
        with np.errstate(invalid="ignore", divide="ignore"):
            n = np.where(length[:, None] > 0.0, s / length[:, None], 0.0)
        stretch = self.stiffness * (length - self.rest_length)
        magnitude = stretch + self.spring_damping * np.einsum("kc,kc->k", n, rate)
        force = -magnitude[:, None] * n  # on body 1
        for body, lever, f in ((self.body1, r1, force), (self.body2, r2, -force)):
            on = body != WORLD
            b = body[on]
            torque = lever[on, 0] * f[on, 1] - lever[on, 1] * f[on, 0]
            np.add.at(acc, (b, 0), f[on, 0] * self.inverse_mass[b, 0])
            np.add.at(acc, (b, 1), f[on, 1] * self.inverse_mass[b, 1])
            np.add.at(acc, (b, 2), torque * self.inverse_mass[b, 2])

    def _pairs(self, q: np.ndarray):
        i, j = np.triu_indices(self.moving.size, 1)
        i, j = self.moving[i], self.moving[j]
        d = q[j, :2] - q[i, :2]
        return i, j, d, np.hypot(d[:, 0], d[:, 1])

    def _add_gravitation(self, q: np.ndarray, acc: np.ndarray) -> None:
        i, j, d, r = self._pairs(q)
        pull = (self.gravitation / r**3)[:, None] * d  # G (x_j - x_i) / r^3
        np.add.at(acc, (i, slice(0, 2)), self.mass[j, None] * pull)
        np.add.at(acc, (j, slice(0, 2)), -self.mass[i, None] * pull)

    def potential(self, q: np.ndarray) -> float:
        """Energy stored in the springs plus the mutual gravitational energy at ``q`` (J)."""
        energy = 0.0
        if self.body1.size:
            _, _, _, length, _ = self._spring_state(q, np.zeros_like(q))
            energy += float(np.sum(0.5 * self.stiffness * (length - self.rest_length) ** 2))
        if self.gravitation and self.moving.size > 1:
            i, j, _, r = self._pairs(q)
            energy -= float(np.sum(self.gravitation * self.mass[i] * self.mass[j] / r))
        return energy


def applied_potential(scene, poses: np.ndarray) -> float:
    """The springs' and the mutual gravitation's energy of ``scene`` at ``poses`` (J)."""
    forces = AppliedForces.of(scene)
    return 0.0 if forces is None else forces.potential(poses)
