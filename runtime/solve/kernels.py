"""Contact rows from the generated kernels: gap, d', Jacobian row and bias for every contact.

Only the kernel modules of the cases a scene can produce are imported (`load_cases`), so a scene of
discs and walls never loads a vertex kernel. Contacts are grouped by (case, body 2 fixed) and each
group is one vectorised kernel call; a fixed body 2 uses the `*_static2` specialisations.
"""

from __future__ import annotations

import importlib
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from types import ModuleType

import numpy as np

_POSE = ("x", "y", "th")
_VELOCITY = ("vx", "vy", "w")


def load_cases(cases: Iterable[str]) -> dict[str, ModuleType]:
    """Import generated/<case>.py for each case, and nothing else."""
    modules = {}
    for case in sorted(cases):
        try:
            modules[case] = importlib.import_module(f"generated.{case}")
        except ModuleNotFoundError as exc:
            raise RuntimeError(
                f"no generated kernel for contact case {case!r}: run "
                f"`regenerate-equations --cases {case}`"
            ) from exc
    return modules


@dataclass(frozen=True)
class ContactRows:
    """Per-contact numbers for m contacts among n bodies.

    jacobian is (m, 6): (j1x, j1y, j1th, j2x, j2y, j2th); body1/body2 are (m,) body indices.
    """

    gap: np.ndarray
    gap_velocity: np.ndarray
    jacobian: np.ndarray
    bias: np.ndarray
    body1: np.ndarray
    body2: np.ndarray

    def dense_jacobian(self, n_bodies: int) -> np.ndarray:
        """J as an (m, 3n) matrix: d'' = J acc + bias."""
        m = len(self.gap)
        jac = np.zeros((m, 3 * n_bodies))
        rows = np.arange(m)[:, None]
        jac[rows, 3 * self.body1[:, None] + np.arange(3)] += self.jacobian[:, :3]
        jac[rows, 3 * self.body2[:, None] + np.arange(3)] += self.jacobian[:, 3:]
        return jac


def _call(module: ModuleType, name: str, values: dict[str, np.ndarray]):
    return getattr(module, name)(**{a: values[a] for a in module.ARGUMENTS[name]})


def evaluate(
    contacts: Sequence,
    modules: dict[str, ModuleType],
    poses: np.ndarray,
    velocities: np.ndarray,
    fixed: Sequence[bool],
    with_gaps: bool = True,
) -> ContactRows:
    """Evaluate every contact's kernels at the given state ((n, 3) poses and velocities).

    with_gaps=False skips d and d' (zeros), for the integrator stages that need only J and bias.
    """
    m = len(contacts)
    out = {k: np.zeros(m) for k in ("gap", "gap_velocity", "bias")}
    jac = np.zeros((m, 6))
    body1 = np.array([c.body1 for c in contacts], dtype=int)
    body2 = np.array([c.body2 for c in contacts], dtype=int)
    groups: dict[tuple[str, bool], list[int]] = {}
    for k, c in enumerate(contacts):
        groups.setdefault((c.case, bool(fixed[c.body2])), []).append(k)
    for (case, static2), members in groups.items():
        module = modules.get(case)
        if module is None:
            raise RuntimeError(f"contact case {case!r} was not loaded for this scene")
        idx = np.asarray(members)
        values = _single(contacts[members[0]], poses, velocities) if len(members) == 1 else None
        if values is None:
            values = {}
            for i, bodies in (("1", body1[idx]), ("2", body2[idx])):
                for j, name in enumerate(_POSE):
                    values[name + i] = poses[bodies, j]
                for j, name in enumerate(_VELOCITY):
                    values[name + i] = velocities[bodies, j]
            for key in contacts[members[0]].geometry:
                values[key] = np.array([contacts[k].geometry[key] for k in members])
        suffix = "_static2" if static2 else ""
        if with_gaps:
            out["gap"][idx] = _call(module, "gap", values)
            out["gap_velocity"][idx] = _call(module, "gap_velocity" + suffix, values)
        out["bias"][idx] = _call(module, "bias" + suffix, values)
        rows = _call(module, "jacobian" + suffix, values)
        jac[idx, : len(rows)] = np.column_stack([np.broadcast_to(r, idx.shape) for r in rows])
    return ContactRows(out["gap"], out["gap_velocity"], jac, out["bias"], body1, body2)


def _single(contact, poses: np.ndarray, velocities: np.ndarray) -> dict[str, float]:
    """The kernel arguments of one contact as Python floats: a kernel call on floats costs a
    fifth of one on 1-element arrays (bench/README.md), and the results are the same bits."""
    values = {}
    for i, body in (("1", contact.body1), ("2", contact.body2)):
        pose, velocity = poses[body].tolist(), velocities[body].tolist()
        for j, name in enumerate(_POSE):
            values[name + i] = pose[j]
        for j, name in enumerate(_VELOCITY):
            values[name + i] = velocity[j]
    values.update({key: float(v) for key, v in contact.geometry.items()})
    return values
