"""Proofs of the joint rows against the independent reference (derive/reference.py).

The reference writes each joint's constraint from its definition (pin: the anchors' separation
s = p1 - p2; distance: |s| - length) along the explicit motion q(t) = q + q' t + q'' t^2/2 of both
bodies and differentiates it in t; it shares no code with derive/joints.py.
"""

from __future__ import annotations

import sympy as sp

from derive import reference as ref
from derive.joints import JointDefinition
from derive.proofs import RESTRICTIONS, Proof, all_zero, inline_scalars
from derive.reference import B1, B2, at_instant, cross, sym
from derive.rows import Derived


def _variants(j: Derived) -> dict[str, Derived]:
    return {"full": j, "bias": j.bias, "static2": j.static2, "static2 bias": j.static2.bias}


def _in_levers(j: Derived, expr: sp.Expr, levers: dict) -> sp.Expr:
    return inline_scalars(j, expr, levers)


def exact_rows(joint: JointDefinition, j: Derived) -> list[Proof]:
    """In two steps, each an exact identity: (1) the anchors' levers L_i = R(th_i) a_i and their
    rates equal the reference's; (2) d, d', d'' of every row written in the levers equal the
    reference's along an arbitrary path of the levers. The same for the bias and the
    body-2-fixed variants."""
    rows = ref.joint_rows(joint.name, levers=True)
    order = {"gap": 0, "gap_velocity": 1, "gap_acceleration": 2}
    held = {}
    for variant, jv in _variants(j).items():
        still = RESTRICTIONS[variant]
        levers = {s: v.xreplace(still) for s, v in ref.lever_values(joint.name, 3).items()}
        defined = dict(jv.intermediates)
        ok = all_zero((defined[s], v) for s, v in levers.items() if s in defined)
        folded = {s: v for s, v in levers.items() if s not in defined}
        outputs = ("gap_acceleration",) if "bias" in variant else tuple(jv.values)
        held[variant] = ok and all_zero(
            (
                _in_levers(jv, ours, levers),
                at_instant(row, order[name]).xreplace(still).xreplace(folded),
            )
            for name in outputs
            for ours, row in zip(jv.values[name], rows, strict=True)
        )
    return [
        Proof(
            f"{joint.name}: d, d' and the whole d'' of every row equal the derivatives at t = 0 of"
            f" the joint's definition ({joint.definition}, anchors p_i = X_i + R(th_i) a_i) along"
            " an arbitrary motion of both bodies, for every state",
            held["full"],
        ),
        Proof(
            f"{joint.name}: the bias equals that d'' with every acceleration zero, and the"
            " *_static2 d', d'' and bias equal it with body 2's velocity and acceleration zero (a"
            " joint to the world: body 2 at the origin with angle 0)",
            held["bias"] and held["static2"] and held["static2 bias"],
        ),
    ]


def jacobian_rows(joint: JointDefinition, j: Derived) -> Proof:
    """J = dd/dq per row: the acceleration coefficients of the reference d'', so d'' = J.a + bias."""
    rows = ref.joint_rows(joint.name)
    pairs = []
    for row, jac, jac_fixed in zip(rows, j.jacobian, j.static2.jacobian, strict=True):
        pairs += [
            (j.in_state_symbols(e), sp.diff(at_instant(row), q))
            for e, q in zip(jac, ref.POSE, strict=True)
        ]
        pairs += [
            (j.static2.in_state_symbols(e), sp.diff(at_instant(row), q))
            for e, q in zip(jac_fixed[:3], ref.POSE[:3], strict=True)
        ]
    return Proof(
        f"{joint.name}: each Jacobian row (and *_static2 row) equals dd/dq of the reference, hence"
        " the coefficients of the accelerations in its d'' (along the motion dd/da = (t^2/2)"
        " dd/dq), so d'' = J.a + bias exactly",
        all_zero(pairs),
    )


def levers(joint: JointDefinition, j: Derived) -> Proof:
    """Each row is (e, R1 x e, -e, -R2 x e) with R_i the anchors' levers and e the row's direction
    (x, y for a pin; n = s/|s| for a distance joint): the generalized force of a joint force along
    e at the anchors, so A = J M^-1 J^T is symmetric."""
    s = at_instant(ref.joint_separation())
    r1 = at_instant(B1.point(sym("px1"), sym("py1")) - B1.centre)
    r2 = at_instant(B2.point(sym("px2"), sym("py2")) - B2.centre)
    if joint.rows == 2:
        directions = [sp.Matrix([1, 0]), sp.Matrix([0, 1])]
    else:
        directions = [s / sp.sqrt(s[0] ** 2 + s[1] ** 2)]
    pairs = []
    for e, jac in zip(directions, j.jacobian, strict=True):
        expected = [e[0], e[1], cross(r1, e), -e[0], -e[1], -cross(r2, e)]
        pairs += [(j.in_state_symbols(a), b) for a, b in zip(jac, expected, strict=True)]
    what = "e = x and y" if joint.rows == 2 else "e = n = s/|s|"
    return Proof(
        f"{joint.name}: J = (e, R1 x e, -e, -R2 x e) per row ({what}) with R_i the levers from each"
        " centre of mass to its anchor: the generalized force of a joint force along e at the"
        " anchors, so A = J M^-1 J^T is symmetric",
        all_zero(pairs),
    )


def joint_proofs(joint: JointDefinition, j: Derived) -> list[Proof]:
    return [*exact_rows(joint, j), jacobian_rows(joint, j), levers(joint, j)]
