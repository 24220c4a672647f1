"""Proofs of the tangential (friction) rows against the independent reference (derive/reference.py).

The reference finds the contact points from the note's geometry (p1 = f1 - r1 n, p2 = p1 - d n),
follows each as a material point of its body (carried rigidly for a moment and differentiated),
and differentiates v_t = (u1(p1) - u2(p2)).t along the explicit motion q(t) = q + q' t + q'' t^2/2.
It shares no code with derive/friction.py (which writes v_t with levers and differentiates through
abstract vectors). Every identity is decided exactly by derive.proofs.is_zero.

The kernels are written in the levers L_i = R(th_i) f_i and the normal n, n'. The proofs identify
those first (1: the levers and their rates are the reference's; 2: so are n and n'), then prove
each claim for arbitrary lever paths and an arbitrary unit normal n = (cos, sin)(beta + omega t)
(3). Steps 1-2 make 3 hold along the reference motion; 3 has no square root and no trigonometry
of the body angles, which keeps it fast.
"""

from __future__ import annotations

import sympy as sp

from derive import reference as ref
from derive.cases import CaseDefinition
from derive.derivation import vector_names
from derive.proofs import BETA, RESTRICTIONS, Proof, all_zero, inline_scalars
from derive.reference import B1, B2, OMEGA_N, at_instant, cross, dot, sym
from derive.rows import Derived

UNIT = "unit normal"
(NX, NX_T, _), (NY, NY_T, _) = vector_names("n")
GENERIC_NORMAL = {
    NX: sp.cos(BETA),
    NY: sp.sin(BETA),
    NX_T: -OMEGA_N * sp.sin(BETA),
    NY_T: OMEGA_N * sp.cos(BETA),
}


def _variants(f: Derived) -> dict[str, Derived]:
    return {"full": f, "bias": f.bias, "static2": f.static2, "static2 bias": f.static2.bias}


def _unit_edge(case: CaseDefinition) -> dict:
    """A straight edge's normal is a unit vector: (nx2, ny2) = (cos, sin) beta."""
    return {sym("nx2"): sp.cos(BETA), sym("ny2"): sp.sin(BETA)} if case.kind == "line" else {}


def _identify(case: CaseDefinition, fv: Derived, still: dict) -> tuple[bool, dict]:
    """Steps 1 and 2 for one variant: the derivation's levers, n and n' equal the reference's
    (with the state restriction `still`). Returns whether they do, and the substitutions that
    step 3's reference needs for what the derivation folded away (body 2 fixed: L2' = 0, and
    n' = 0 on a straight edge)."""
    defined = dict(fv.intermediates)
    levers = {s: v.xreplace(still) for s, v in ref.lever_values(case.name).items()}
    ok = all_zero((defined[s], v) for s, v in levers.items() if s in defined)
    folded = {s: v for s, v in levers.items() if s not in defined}
    n = ref.geometry(case.name, levers=True).n
    wanted = {NX: n[0], NY: n[1], NX_T: n[0].diff(ref.TAU), NY_T: n[1].diff(ref.TAU)}
    unit = _unit_edge(case)
    for s, value in wanted.items():
        want = at_instant(value).xreplace(still).xreplace(folded).xreplace(unit)
        ours = inline_scalars(fv, defined.get(s, sp.Integer(0)), levers).xreplace(unit)
        ok = ok and all_zero([(ours, want)])
    if NX_T not in defined:
        folded[OMEGA_N] = 0
    return ok, folded


def _ours(fv: Derived, expr: sp.Expr, case: CaseDefinition) -> sp.Expr:
    """`expr` in the levers, with the normal an arbitrary unit vector (step 3)."""
    kept = {**ref.lever_values(case.name), **GENERIC_NORMAL}
    return inline_scalars(fv, expr, kept).xreplace(GENERIC_NORMAL)


def exact_rates(case: CaseDefinition, f: Derived) -> list[Proof]:
    """v_t and d/dt v_t (and the bias, and the body-2-fixed variants) equal the reference's."""
    vt, at = ref.tangent_velocity(case.name, UNIT)
    held = {}
    for variant, fv in _variants(f).items():
        still = RESTRICTIONS[variant]
        ok, folded = _identify(case, fv, still)
        pairs = [("tangent_acceleration", at)]
        pairs += [] if "bias" in variant else [("tangent_velocity", vt)]
        held[variant] = ok and all_zero(
            (_ours(fv, fv.values[name][0], case), want.xreplace(still).xreplace(folded))
            for name, want in pairs
        )
    return [
        Proof(
            f"{case.name}: v_t and d/dt v_t equal those of the reference, v_t = (u1(p1) -"
            " u2(p2)).t with p1 = f1 - r1 n, p2 = p1 - d n followed as material points of their"
            " bodies, along an arbitrary motion of both bodies, for every state (not only at a"
            " contact)",
            held["full"],
        ),
        Proof(
            f"{case.name}: the tangential bias equals that d/dt v_t with every acceleration zero,"
            " and the *_static2 v_t, d/dt v_t and bias equal it with body 2's velocity and"
            " acceleration zero",
            held["bias"] and held["static2"] and held["static2 bias"],
        ),
    ]


def jacobian_row(case: CaseDefinition, f: Derived) -> Proof:
    """J_t = d(tangential displacement)/dq = dv_t/d(velocities) = the acceleration coefficients
    of d/dt v_t, so d/dt v_t = J_t . a + bias exactly."""
    vt, at = ref.tangent_velocity(case.name, UNIT)
    slip = ref.tangential_displacement_gradient(case.name, UNIT)
    ok, _ = _identify(case, f, {})
    pairs = []
    for k, j in enumerate(f.jacobian[0]):
        wanted = (slip[k], sp.diff(vt, ref.VELOCITY[k]), sp.diff(at, ref.ACCELERATION[k]))
        pairs += [(_ours(f, j, case), w) for w in wanted]
    fixed = f.static2
    still = RESTRICTIONS["static2"]
    fixed_ok, folded = _identify(case, fixed, still)
    at_fixed = at.xreplace(still).xreplace(folded)
    pairs += [
        (_ours(fixed, j, case), sp.diff(at_fixed, ref.ACCELERATION[k]))
        for k, j in enumerate(fixed.jacobian[0][:3])
    ]
    return Proof(
        f"{case.name}: the tangential Jacobian row J_t (and the *_static2 row) is the derivative"
        " of the tangential displacement t.(P1 - P2) of the two material contact points with"
        " respect to the coordinates; it equals dv_t/d(velocities) and the coefficients of the"
        " accelerations in the reference d/dt v_t, so d/dt v_t = J_t.a + bias exactly",
        ok and fixed_ok and all_zero(pairs),
    )


def levers(case: CaseDefinition, f: Derived) -> Proof:
    """J_t^T is the generalized force of a unit friction force t on body 1 at p1 and -t on body 2
    at p2, so [J_n; J_t] M^-1 [J_n; J_t]^T is the effect of the forces and symmetric."""
    _, p1, p2 = (at_instant(p) for p in ref.contact_frame(case.name, UNIT))
    t = at_instant(ref.tangent(case.name, UNIT))
    x1, x2 = at_instant(B1.centre), at_instant(B2.centre)
    expected = [t[0], t[1], cross(p1 - x1, t), -t[0], -t[1], -cross(p2 - x2, t)]
    ok, _ = _identify(case, f, {})
    ours = [_ours(f, j, case) for j in f.jacobian[0]]
    return Proof(
        f"{case.name}: J_t = (t, R1 x t, -t, -R2 x t) with R the levers from each centre of mass"
        " to the contact points p1, p2 (not to a centre of curvature: U x t differs), so a"
        " friction force f_t t at p1 (and -f_t t at p2) has the generalized force J_t^T f_t and"
        " A = J M^-1 J^T with the normal and tangential rows together stays symmetric",
        ok and all_zero(zip(ours, expected, strict=True)),
    )


def rolling(case: CaseDefinition, f: Derived) -> Proof:
    """For a circle on a straight edge or on a circle, v_t = 0 is the textbook rolling condition
    (in the bodies' own form: the centres' velocities need the rigid lever rates)."""
    r1, r2 = sym("r1"), sym("r2")
    w1, w2 = ref.VELOCITY[2], ref.VELOCITY[5]
    t = at_instant(ref.tangent(case.name, "bodies"))
    f1, f2 = (at_instant(p, 1) for p in ref.features(case.name))
    if case.name == "circle_edge":
        _, _, p2 = ref.contact_frame(case.name, "bodies")
        textbook = dot(f1 - at_instant(ref.material_velocity(B2, p2)), t) - w1 * r1
        statement = (
            "circle_edge: v_t = (v_c1 - v_e).t - w1 r1, with v_c1 the velocity of the circle's"
            " centre and v_e that of the edge's material point under it: v_t = 0 is the rolling"
            " condition (on a fixed floor with n = +y, t = -x: v_c = -w1 r1)"
        )
    else:
        textbook = dot(f1 - f2, t) - w1 * r1 - w2 * r2
        statement = (
            "circle_circle: v_t = (v_c1 - v_c2).t - w1 r1 - w2 r2 (r2 < 0 in a bowl), with v_c"
            " the velocities of the circles' centres: v_t = 0 is the rolling condition (two"
            " discs at rest turn with w1 r1 = -w2 r2; a disc in a fixed bowl has v_c1.t = w1 r1)"
        )
    ours = f.in_state_symbols(f.values["tangent_velocity"][0]).xreplace(_unit_edge(case))
    return Proof(statement, all_zero([(ours, textbook.xreplace(_unit_edge(case)))]))


def friction_proofs(case: CaseDefinition, f: Derived) -> list[Proof]:
    out = [*exact_rates(case, f), jacobian_row(case, f), levers(case, f)]
    return out + [rolling(case, f)] if case.name.startswith("circle") else out
