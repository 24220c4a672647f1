"""Applied forces of issue #16: springs, linear and angular damping, mutual gravitation.

Why they are a module of their own: unlike gravity they depend on the state (q, v), so they
enter the free accelerations a0 of Baraff's problem (b = J a0 + bias) at every integrator
stage, not once per scene (runtime.solve.linked_forces). None of them is a constraint: they
are explicit forces.

Their forces and energies are the generated kernels (generated/spring.py, mutual_gravity.py,
body_damping.py): the generalized forces Q = -dV/dq - dR/dq' that SymPy takes of each one's
potential V and Rayleigh function R (derive/applied.py), and V. Nothing of them is typed here:
this module gathers each kernel's arguments from the state, by the kernel's ARGUMENTS, and adds
Q / m and Q / I to the bodies' accelerations. Only the kernels a scene uses are imported, and a
scene without any of them never builds this (:meth:`AppliedForces.of` gives None).
"""

from __future__ import annotations

import importlib
from types import ModuleType

import numpy as np

import generated
from runtime.model.links import WORLD

__all__ = ["AppliedForces", "applied_potential"]

_POSE, _VELOCITY = ("x", "y", "th"), ("vx", "vy", "w")


def _kernels(name: str) -> ModuleType:
    if name not in generated.APPLIED:
        raise RuntimeError(f"no generated kernel for {name!r}: run regenerate-equations")
    return importlib.import_module(f"generated.{name}")


def _call(module: ModuleType, function: str, values: dict) -> tuple:
    """The kernel's outputs (arrays, or a constant float such as a zero torque)."""
    out = getattr(module, function)(**{a: values[a] for a in module.ARGUMENTS[function]})
    return out if isinstance(out, tuple) else (out,)


def _add(out: np.ndarray, body: np.ndarray, forces) -> None:
    """out[body[k]] += forces[:, k] for (n, 3) ``out``, bodies repeated or not (one bincount:
    np.add.at costs ~10x)."""
    f = np.column_stack(np.broadcast_arrays(*forces))
    flat = (3 * body[:, None] + np.arange(3)).ravel()
    out += np.bincount(flat, weights=f.ravel(), minlength=out.size).reshape(out.shape)


def _state(q: np.ndarray, v: np.ndarray, body: np.ndarray, end: str) -> dict[str, np.ndarray]:
    """The pose and velocity arguments of end "1" or "2" for bodies ``body``."""
    values = {f"{n}{end}": q[body, k] for k, n in enumerate(_POSE)}
    values.update({f"{n}{end}": v[body, k] for k, n in enumerate(_VELOCITY)})
    return values


def _world(size: int) -> dict[str, np.ndarray]:
    """Body 2 as the world: at the origin with angle 0 (anchor 2 is in world coordinates)."""
    return {f"{n}2": np.zeros(size) for n in _POSE}


class AppliedForces:
    """The applied forces of one scene, as accelerations (n, 3) at a state, and their energy."""

    def __init__(self, scene) -> None:
        bodies = scene.bodies
        self.n = len(bodies)
        self.fixed = np.asarray(scene.fixed, dtype=bool)
        self.inverse_mass = scene.inverse_masses
        moving = np.flatnonzero(~self.fixed)
        mass = np.array([b.mass for b in bodies], dtype=float)
        inertia = np.array([b.inertia for b in bodies], dtype=float)
        lin = np.array([b.linear_damping for b in bodies], dtype=float)
        ang = np.array([b.angular_damping for b in bodies], dtype=float)
        self.damped = moving[(lin[moving] != 0.0) | (ang[moving] != 0.0)]
        d = self.damped
        self.damping = {"m1": mass[d], "i1": inertia[d], "k_lin": lin[d], "k_ang": ang[d]}
        springs = scene.springs
        body1 = np.array([s.body1 for s in springs], dtype=np.int64)
        body2 = np.array([s.body2 for s in springs], dtype=np.int64)
        anchor1 = np.array([s.anchor1 for s in springs], dtype=float).reshape(-1, 2)
        anchor2 = np.array([s.anchor2 for s in springs], dtype=float).reshape(-1, 2)
        parameters = {
            "px1": anchor1[:, 0], "py1": anchor1[:, 1], "px2": anchor2[:, 0],
            "py2": anchor2[:, 1],
            "rest_length": np.array([s.rest_length for s in springs], dtype=float),
            "stiffness": np.array([s.stiffness for s in springs], dtype=float),
            "damping": np.array([s.damping for s in springs], dtype=float),
        }  # fmt: skip
        # (body 1, body 2 or None for the world, parameters) of the springs between two bodies
        # and of those to the world
        self.springs = []
        for to_world in (False, True):
            k = np.flatnonzero((body2 == WORLD) == to_world)
            if k.size:
                ends = (body1[k], None if to_world else body2[k])
                self.springs.append((*ends, {a: p[k] for a, p in parameters.items()}))
        # every two moving bodies attract (O(n^2) pairs: only when asked)
        i, j = np.triu_indices(moving.size if scene.mutual_gravity else 0, 1)
        self.pairs = (moving[i], moving[j])
        self.gravitation = {"G": float(scene.mutual_gravity), "m1": mass[moving[i]],
                            "m2": mass[moving[j]]}  # fmt: skip
        self.body_damping = _kernels("body_damping") if d.size else None
        self.spring = _kernels("spring") if self.springs else None
        self.mutual_gravity = _kernels("mutual_gravity") if i.size else None

    @classmethod
    def of(cls, scene) -> AppliedForces | None:
        """The scene's applied forces, or None when it has none."""
        if not (scene.springs or scene.mutual_gravity or scene.damped):
            return None
        return cls(scene)

    def _spring_values(self, q: np.ndarray, v: np.ndarray, body1, body2, parameters) -> dict:
        values = {**parameters, **_state(q, v, body1, "1")}
        values.update(_world(body1.size) if body2 is None else _state(q, v, body2, "2"))
        return values

    def generalized_forces(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """(n, 3) force and torque on each body at (q, v), summed over the applied forces."""
        out = np.zeros((self.n, 3))
        if self.body_damping is not None:
            d = self.damped
            values = {**self.damping, **_state(q, v, d, "1")}
            out[d] += np.column_stack(_call(self.body_damping, "force", values))  # d unique
        for body1, body2, parameters in self.springs:
            values = self._spring_values(q, v, body1, body2, parameters)
            if body2 is None:
                _add(out, body1, _call(self.spring, "force_static2", values))
            else:
                f = _call(self.spring, "force", values)
                _add(out, body1, f[:3])
                _add(out, body2, f[3:])
        if self.mutual_gravity is not None:
            i, j = self.pairs
            values = {**self.gravitation, **_state(q, v, i, "1"), **_state(q, v, j, "2")}
            f = _call(self.mutual_gravity, "force", values)
            _add(out, i, f[:3])
            _add(out, j, f[3:])
        return out

    def accelerations(self, q: np.ndarray, v: np.ndarray) -> np.ndarray:
        """(n, 3) accelerations (force / m, torque / I) of the applied forces at (q, v)."""
        acc = self.generalized_forces(q, v) * self.inverse_mass
        acc[self.fixed] = 0.0
        return acc

    def potential(self, q: np.ndarray) -> float:
        """Energy stored in the springs plus the mutual gravitational energy at ``q`` (J)."""
        v = np.zeros_like(q)
        energy = 0.0
        for body1, body2, parameters in self.springs:
            values = self._spring_values(q, v, body1, body2, parameters)
            energy += float(np.sum(_call(self.spring, "potential", values)))
        if self.mutual_gravity is not None:
            i, j = self.pairs
            values = {**self.gravitation, **_state(q, v, i, "1"), **_state(q, v, j, "2")}
            energy += float(np.sum(_call(self.mutual_gravity, "potential", values)))
        return energy


def applied_potential(scene, poses: np.ndarray) -> float:
    """The springs' and the mutual gravitation's energy of ``scene`` at ``poses`` (J)."""
    forces = AppliedForces.of(scene)
    return 0.0 if forces is None else forces.potential(poses)
