"""Joint rows: d, d', the Jacobian rows and the bias of every joint row, from the generated joint
kernels (generated/compiled/pin_joint.py, distance_joint.py).

Why: a joint is a constraint with a d, d' and d'' exactly like a contact (derive/joints.py), so
the runtime uses it the same way -- rows of Baraff's problem, bilateral (a = 0, force of either
sign) -- and nothing of its geometry is typed here. A pin has two rows (x and y of p1 - p2), a
distance joint one. Only the kinds a scene uses are imported.

For assembly a joint to the world has its body 2 set to its body 1 with a zero Jacobian half (the
kernels' static2 rows), so A = J W J^T and W J^T f need no world body.
"""

from __future__ import annotations

import importlib

import numpy as np

import generated
import runtime.compiled  # noqa: F401  (sets numba's cache folder before the kernels compile)
from runtime.model.links import JOINT_KINDS, WORLD
from runtime.solve.rows import Rows

__all__ = ["JointSet"]


class JointSet:
    """The joints of one scene, grouped by kind, and their rows at a state."""

    def __init__(self, joints) -> None:
        self.groups = []  # (module, rows per joint, body1, body2, geometry, static2, members)
        body1, body2, self.names = [], [], []
        for kind in sorted(JOINT_KINDS.values()):
            mine = [j for j in joints if j.generated == kind]
            if not mine:
                continue
            if kind not in generated.JOINTS:
                raise RuntimeError(
                    f"no generated kernel for joint {kind!r}: run regenerate-equations"
                )
            module = importlib.import_module(f"generated.compiled.{kind}")
            columns = generated.JOINT_GEOMETRY_COLUMNS[kind]
            geometry = np.zeros((len(mine), 7))
            for k, j in enumerate(mine):
                values = {"px1": j.anchor1[0], "py1": j.anchor1[1], "px2": j.anchor2[0],
                          "py2": j.anchor2[1], "length": j.length}  # fmt: skip
                for name, c in columns.items():
                    geometry[k, c] = values[name]
            b1 = np.array([j.body1 for j in mine], dtype=np.int64)
            b2 = np.array([j.body2 for j in mine], dtype=np.int64)
            rows = generated.JOINT_ROWS[kind]
            self.groups.append(
                (module, rows, b1, b2, geometry, b2 == WORLD, np.arange(len(mine), dtype=np.int64))
            )
            self.names += [j.name for j in mine for _ in range(rows)]
            body1.append(np.repeat(b1, rows))
            body2.append(np.repeat(np.where(b2 == WORLD, b1, b2), rows))
        self.body1 = np.concatenate(body1) if body1 else np.zeros(0, np.int64)
        self.body2 = np.concatenate(body2) if body2 else np.zeros(0, np.int64)
        self.size = self.body1.size  # number of rows

    @classmethod
    def of(cls, scene) -> JointSet | None:
        return cls(scene.joints) if scene.joints else None

    def rows(self, q: np.ndarray, v: np.ndarray, with_gaps: bool = True) -> Rows:
        """Every joint row at (q, v), by kind (in sorted kind order), each joint's rows together
        (``names`` gives each row's joint); ``with_gaps=False`` leaves d and d' at 0."""
        gaps, rates, jacobians, biases = [], [], [], []
        for module, r, b1, b2, geometry, static2, members in self.groups:
            m = members.size
            gap, rate = np.zeros((m, r)), np.zeros((m, r))
            jac, bias = np.zeros((m, r, 6)), np.zeros((m, r))
            module.batch_rows(q, v, b1, b2, geometry, static2, members, jac, bias)
            if with_gaps:
                module.batch_gap(q, b1, b2, geometry, members, gap)
                module.batch_gap_velocity(q, v, b1, b2, geometry, static2, members, rate)
            gaps.append(gap.ravel())
            rates.append(rate.ravel())
            jacobians.append(jac.reshape(-1, 6))
            biases.append(bias.ravel())
        return Rows(
            np.concatenate(gaps),
            np.concatenate(rates),
            np.concatenate(jacobians),
            np.concatenate(biases),
            self.body1,
            self.body2,
        )
