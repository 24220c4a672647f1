"""The tangential (friction) row of every contact case: v_t and its rate, by SymPy differentiation.

t is the normal turned by +90 degrees, t = (-n_y, n_x). The contact points are material points of
the two bodies on the common normal line:

    p1 = f1 - r1 n   body 1's feature f1 itself (a vertex, r1 = 0) or the point of its circle
                     that faces body 2;
    p2 = p1 - d n    the point of body 2's edge nearest p1: the foot of the perpendicular on a
                     straight edge, c2 + r2 n on a circular edge (r2 signed).

At a contact (d = 0) they coincide. The tangential relative velocity is v_t = (u1(p1) - u2(p2)).t
with u_i(p) = V_i + w_i k x (p - X_i) the velocity of body i's material point at p. Since
(k x r).t = r.n,

    v_t = t.(V1 - V2) + w1 l1 - w2 l2,   l_i = (p_i - X_i).n   (the tangential levers),

l1 = L1.n - r1 with L1 = R(th1) f1 (body 1's feature from its centre of mass), and l2 = L2.n + r2
for a circular edge (p2 = c2 + r2 n), L2.n for a straight edge (p2 - e2 runs along the edge).
SymPy differentiates v_t once along an arbitrary motion, through abstract world vectors n(t),
L1(t), L2(t) (the chain rule) named like the gap's intermediates; the normal's rate is n' = w2 t
on a straight edge (kinematics) and n' = (v_tan/|v|) t on a circular edge (checked here against
SymPy's derivative of sigma v/|v|). d/dt v_t is linear in the accelerations: the coefficients are
the row J_t (v_t = J_t . velocities), the rest is the bias. derive/friction_proofs.py proves all of
it against an independent reference.
"""

from __future__ import annotations

import sympy as sp

from derive.cases import CX1, CX2, CY1, CY2, EX2, EY2, PX1, PY1, R1, R2, SIGMA2, CaseDefinition
from derive.derivation import (
    V_LEN,
    V_TAN,
    Hypot,
    UnitSign,
    abstract_vector,
    needed,
    rename,
    translation,
    vector_intermediates,
    vector_names,
)
from derive.kinematics import BODY1, BODY2, t, to_state
from derive.rows import Derived

OUTPUTS = ("tangent_velocity", "tangent_acceleration")


def features(case: CaseDefinition) -> tuple[tuple[sp.Symbol, sp.Symbol], sp.Expr, tuple, sp.Expr]:
    """(body 1's feature point, r1, body 2's feature point, r2 of a circular edge or 0)."""
    first, second = case.name.split("_")
    f1, r1 = ((PX1, PY1), sp.Integer(0)) if first == "vertex" else ((CX1, CY1), R1)
    f2, r2 = ((EX2, EY2), sp.Integer(0)) if second == "edge" else ((CX2, CY2), R2)
    return f1, r1, f2, r2


def _circle_normal() -> list[tuple[sp.Symbol, sp.Expr]]:
    """v = X1 + L1 - X2 - L2 (centre or vertex of body 1 from the centre of body 2's edge) and v',
    by SymPy; |v|, v_tan = (v x v')/|v|, n = sigma v/|v| and n' = (v_tan/|v|) t, after checking n'
    against SymPy's derivative of sigma v/|v|."""
    (l1x, l1y), l1_names = abstract_vector("l1")
    (l2x, l2y), l2_names = abstract_vector("l2")
    v = (BODY1.x + l1x - BODY2.x - l2x, BODY1.y + l1y - BODY2.y - l2y)
    (sx, sx_t, _), (sy, sy_t, _) = vector_names("v")
    inter = [
        (name, to_state(rename(sp.diff(v[k], t, order), {**l1_names, **l2_names})))
        for order, names in ((0, (sx, sy)), (1, (sx_t, sy_t)))
        for k, name in enumerate(names)
    ]
    inter.insert(2, (V_LEN, Hypot(sx, sy)))
    inter.append((V_TAN, (sx * sy_t - sy * sx_t) / V_LEN))
    (vx, vy), names = abstract_vector("v")
    length = sp.sqrt(sx**2 + sy**2)
    rate = (sx * sy_t - sy * sx_t) / length**2
    for k, f in enumerate((vx, vy)):
        raw = rename(sp.diff(SIGMA2 * f / sp.sqrt(vx**2 + vy**2), t), names)
        stable = rate * (-SIGMA2 * sy / length if k == 0 else SIGMA2 * sx / length)
        if sp.simplify(raw - stable) != 0:
            raise AssertionError("n' = (v_tan/|v|) t differs from SymPy's derivative of n")
    (nx, nx_t, _), (ny, ny_t, _) = vector_names("n")
    return inter + [
        (nx, SIGMA2 * sx / V_LEN),
        (ny, SIGMA2 * sy / V_LEN),
        (nx_t, -V_TAN * ny / V_LEN),
        (ny_t, V_TAN * nx / V_LEN),
    ]


def tangential(case: CaseDefinition) -> Derived:
    """v_t and d/dt v_t of one contact case (exact for any state, not only at a contact)."""
    f1, r1, f2, r2 = features(case)
    (nx, ny), n_names = abstract_vector("n")
    (l1x, l1y), l1_names = abstract_vector("l1")
    (l2x, l2y), l2_names = abstract_vector("l2")
    names = {**n_names, **l1_names, **l2_names}
    lever1 = l1x * nx + l1y * ny - r1
    lever2 = l2x * nx + l2y * ny + r2
    vt = (
        -ny * sp.diff(BODY1.x - BODY2.x, t)
        + nx * sp.diff(BODY1.y - BODY2.y, t)
        + sp.diff(BODY1.th, t) * lever1
        - sp.diff(BODY2.th, t) * lever2
    )
    velocity, acceleration = (to_state(rename(sp.diff(vt, t, k), names)) for k in (0, 1))
    inter = vector_intermediates("l1", BODY1.rotate(*f1), orders=2)
    inter += vector_intermediates("l2", BODY2.rotate(*f2), orders=2)
    if case.kind == "line":
        inter += vector_intermediates("n", case.normal, orders=2)
    else:
        inter = translation() + [(SIGMA2, UnitSign(case.geometry[-1]))] + inter + _circle_normal()
    return Derived(
        f"{case.name}_friction",
        needed(tuple(inter), (velocity, acceleration)),
        {"tangent_velocity": (velocity,), "tangent_acceleration": (acceleration,)},
        "tangent_acceleration",
    )


FORMULAS = {
    "tangent_velocity": "v_t = t.(V1 - V2) + w1 l1 - w2 l2,  t = (-n_y, n_x),  l_i = (p_i - X_i).n",
    "tangent_acceleration": "d/dt v_t = t'.(V1 - V2) + t.(A1 - A2)"
    " + al1 l1 + w1 l1' - al2 l2 - w2 l2'",
    "tangent_jacobian": "(t_x, t_y, l1, -t_x, -t_y, -l2) = d v_t / d(vx1, vy1, w1, vx2, vy2, w2)"
    " = the coefficients of the accelerations in d/dt v_t",
}

CONTACT_POINTS = {
    "vertex_edge": "p1 = the vertex; p2 = p1 - d n, the foot of the perpendicular from p1 on the"
    " edge's line",
    "vertex_circle": "p1 = the vertex; p2 = p1 - d n = c2 + r2 n, the point of the circular edge"
    " on the ray from c2 through p1",
    "circle_edge": "p1 = c1 - r1 n, the point of body 1's circle nearest the edge's line;"
    " p2 = p1 - d n, the foot of the perpendicular from c1 on that line",
    "circle_circle": "p1 = c1 - r1 n, the point of body 1's circle facing body 2; p2 = p1 - d n"
    " = c2 + r2 n, the point of body 2's circular edge on the line of the centres",
}
