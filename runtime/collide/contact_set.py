"""A set of contacts as flat arrays: what the narrow phase gives and every later stage reads.

Why arrays, not an object per contact: the step evaluates, classifies, solves and watches all
contacts together (compiled loops and vectorised NumPy), and a pile has hundreds of them; one
Python object each cost more than the physics computed for it.

Row k is one contact between the features of two bodies, as one of the generated cases:

- ``case``: the case id of generated.CASE_ID (vertex_edge, vertex_circle, circle_edge,
  circle_circle);
- ``body1``, ``body2``: body indices; body 2 owns the normal (docs/conventions.md);
- ``geometry`` (m, 7): the kernel's geometry arguments in body coordinates, in the columns of
  generated.GEOMETRY_COLUMNS (body 1's feature from column 0, body 2's from column 3; unused
  columns are 0);
- ``feature`` (m, 4): (kind 1, index 1, kind 2, index 2), kinds VERTEX (index into
  Shape.vertices), EDGE (index into Shape.edges), END (where edge k runs smoothly into the
  next); stable from step to step, so with the bodies it identifies the contact (:meth:`keys`);
- ``gap``: the generated kernel's gap d at the state the set was found for;
- ``point`` (m, 2): world point of body 1's feature nearest body 2;
- ``normal`` (m, 2): world unit normal, from body 2 toward body 1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import generated

VERTEX, EDGE, END = 0, 1, 2
KIND_NAMES = ("vertex", "edge", "end")
CASE_NAMES = {number: name for name, number in generated.CASE_ID.items()}


@dataclass(frozen=True)
class Contacts:
    """m contacts as arrays (see the module docstring)."""

    case: np.ndarray  # (m,) int64
    body1: np.ndarray  # (m,) int64
    body2: np.ndarray  # (m,) int64
    geometry: np.ndarray  # (m, 7) float64
    feature: np.ndarray  # (m, 4) int64
    gap: np.ndarray  # (m,) float64
    point: np.ndarray  # (m, 2) float64
    normal: np.ndarray  # (m, 2) float64

    @classmethod
    def empty(cls) -> Contacts:
        return cls(
            np.zeros(0, np.int64),
            np.zeros(0, np.int64),
            np.zeros(0, np.int64),
            np.zeros((0, 7)),
            np.zeros((0, 4), np.int64),
            np.zeros(0),
            np.zeros((0, 2)),
            np.zeros((0, 2)),
        )

    def __len__(self) -> int:
        return len(self.case)

    def take(self, index) -> Contacts:
        """The contacts ``index`` (an index array or a boolean mask), in that order."""
        return Contacts(
            self.case[index],
            self.body1[index],
            self.body2[index],
            self.geometry[index],
            self.feature[index],
            self.gap[index],
            self.point[index],
            self.normal[index],
        )

    def keys(self) -> np.ndarray:
        """(m, 6) int64 rows (body1, body2, kind1, index1, kind2, index2): what identifies a
        contact from one step to the next."""
        return np.column_stack([self.body1, self.body2, self.feature])

    def case_name(self, k: int) -> str:
        return CASE_NAMES[int(self.case[k])]

    def describe(self, k: int) -> str:
        """'vertex 2 of body 1 on edge 0 of body 3 (vertex_edge)': one contact in words."""
        kind1, index1, kind2, index2 = (int(v) for v in self.feature[k])
        return (
            f"{KIND_NAMES[kind1]} {index1} of body {int(self.body1[k])} on {KIND_NAMES[kind2]} "
            f"{index2} of body {int(self.body2[k])} ({self.case_name(k)})"
        )


def concatenate(sets: list[Contacts]) -> Contacts:
    """One set with the rows of ``sets`` in order."""
    sets = [s for s in sets if len(s)]
    if not sets:
        return Contacts.empty()
    if len(sets) == 1:
        return sets[0]
    return Contacts(
        *(
            np.concatenate([getattr(s, name) for s in sets])
            for name in ("case", "body1", "body2", "geometry", "feature", "gap", "point", "normal")
        )
    )
