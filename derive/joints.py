"""Joint constraints (issue #16) as generated "cases": d, d', d'' of each row, by SymPy.

A joint holds an anchor point of body 1, p1 = X1 + R(th1) (px1, py1), to an anchor of body 2,
p2 = X2 + R(th2) (px2, py2); the world is a fixed body 2 at the origin with angle 0, so its anchor
is in world coordinates. With the separation s = p1 - p2:

    pin joint        two bilateral rows, d = (s_x, s_y): the anchors coincide;
    distance joint   one row, d = |s| - length: a massless rod between the anchors.

Like a contact gap, each row is differentiated twice along an arbitrary motion of both bodies
(exact for any state), and d'' is linear in the accelerations: the coefficients are the Jacobian
rows, the rest is the bias. The distance joint uses the circular edge's stable form
d'' = (s.s'' + s_tan^2)/|s| with s_tan = (s x s')/|s| (proven equal to SymPy's derivative in
derive/derivation.py); it needs |s| > 0 (length > 0: a zero length is a pin joint).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from derive.derivation import (
    Hypot,
    abstract_vector,
    rename,
    translation,
    vector_intermediates,
    vector_names,
)
from derive.kinematics import BODY1, BODY2, real, t, to_state
from derive.rows import Derived

PX1, PY1, PX2, PY2 = real("px1"), real("py1"), real("px2"), real("py2")
LENGTH = real("length")
S_LEN = sp.Symbol("s_len", positive=True)
S_TAN = real("s_tan")


@dataclass(frozen=True)
class JointDefinition:
    """A joint: its rows (one output name per row) and its geometry arguments."""

    name: str
    title: str
    row_names: tuple[str, ...]  # "" for a one-row joint, else a suffix per row
    geometry: tuple[sp.Symbol, ...]
    definition: str
    formulas: dict[str, str]

    @property
    def rows(self) -> int:
        return len(self.row_names)


def pin_joint() -> JointDefinition:
    return JointDefinition(
        name="pin_joint",
        title="Pin joint",
        row_names=("x", "y"),
        geometry=(PX1, PY1, PX2, PY2),
        definition="d = s = p1 - p2 (two rows: x and y in world axes)",
        formulas={
            "gap": "d = (s_x, s_y),  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2",
            "gap_velocity": "d' = s'",
            "gap_acceleration": "d'' = s''",
        },
    )


def distance_joint() -> JointDefinition:
    return JointDefinition(
        name="distance_joint",
        title="Distance joint",
        row_names=("",),
        geometry=(PX1, PY1, PX2, PY2, LENGTH),
        definition="d = |p1 - p2| - length",
        formulas={
            "gap": "d = |s| - length,  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2",
            "gap_velocity": "d' = n . s',  n = s/|s|",
            "gap_acceleration": "d'' = (s . s'' + s_tan^2)/|s|,  s_tan = (s x s')/|s|",
        },
    )


ALL_JOINTS = {j().name: j for j in (pin_joint, distance_joint)}


def derive_joint(joint: JointDefinition) -> Derived:
    """d, d', d'' of every row of the joint, exact for any state.

    The anchors' levers L_i = R(th_i) a_i and their rates are named intermediates (l1_x, ...);
    s = X1 + L1 - X2 - L2 and its derivatives follow by SymPy through abstract levers."""
    (l1x, l1y), l1_names = abstract_vector("l1")
    (l2x, l2y), l2_names = abstract_vector("l2")
    s = (BODY1.x + l1x - BODY2.x - l2x, BODY1.y + l1y - BODY2.y - l2y)
    (sx, sx_t, sx_tt), (sy, sy_t, sy_tt) = vector_names("s")
    inter = translation() + vector_intermediates("l1", BODY1.rotate(PX1, PY1))
    inter += vector_intermediates("l2", BODY2.rotate(PX2, PY2))
    names = {**l1_names, **l2_names}
    for order, pair in enumerate(((sx, sy), (sx_t, sy_t), (sx_tt, sy_tt))):
        inter += [(pair[k], to_state(rename(sp.diff(s[k], t, order), names))) for k in range(2)]
        if joint.name == "distance_joint" and order == 0:
            inter.append((S_LEN, Hypot(sx, sy)))
        if joint.name == "distance_joint" and order == 1:
            inter.append((S_TAN, (sx * sy_t - sy * sx_t) / S_LEN))
    if joint.name == "pin_joint":
        values = {"gap": (sx, sy), "gap_velocity": (sx_t, sy_t), "gap_acceleration": (sx_tt, sy_tt)}
    else:
        values = {
            "gap": (S_LEN - LENGTH,),
            "gap_velocity": ((sx * sx_t + sy * sy_t) / S_LEN,),
            "gap_acceleration": ((sx * sx_tt + sy * sy_tt + S_TAN**2) / S_LEN,),
        }
    return Derived(joint.name, tuple(inter), values, "gap_acceleration")
