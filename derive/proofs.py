"""Symbolic proofs that the derived equations are right, and agree with the note under its conditions.

Each proof returns a `Proof` (statement, holds). The reference (derive/reference.py) is the note's
gap along an explicit motion of both bodies; it shares no code with the derivation. Every emitted
expression is covered: d, d', d'' (velocity terms included), the Jacobian, the bias and the
body-2-fixed variants. `is_zero` decides each identity exactly; when a proof fails,
`regenerate-equations` names it and writes nothing.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from derive import reference as ref
from derive.cases import SIGMA2
from derive.derivation import Derivatives, Hypot, UnitSign
from derive.kinematics import DX, DY
from derive.reference import B1, B2, at_instant, cross, dot, sym

BETA = sym("beta")  # direction angle of the edge normal in body 2: (nx2, ny2) = (cos, sin)
S_ALONG = sym("s")  # position of the contact along the straight edge, from e2
U_OFF = sym("u")  # offset of the note's p2 from the true contact point


@dataclass(frozen=True)
class Proof:
    statement: str
    holds: bool


def _half_powers(expr: sp.Expr) -> list[sp.Pow]:
    return [p for p in expr.atoms(sp.Pow) if p.exp.is_Rational and p.exp.q == 2]


def is_zero(expr: sp.Expr) -> bool:
    """Exact zero test over the state symbols.

    Angles become polynomial variables (c, s) reduced by c^2 + s^2 = 1; each square root sqrt(B)
    becomes a positive variable L reduced by L^2 = B (B in that reduced form, its content taken
    out, so equal radicands written differently share one L); sign(r2)^2 = 1. These relations
    have pairwise coprime leading terms (s^2 per angle, L^2), so they form a Groebner basis and
    the remainder is a normal form: zero exactly when the numerator is in the ideal they span.
    """
    x1, y1, th1, x2, y2, th2 = ref.POSE
    # xreplace (exact nodes, no pattern matching) is several times faster than subs here; a
    # node it missed would stay an independent variable, which can only make a proof fail
    expr = sp.sympify(expr).xreplace({DX: x1 - x2, DY: y1 - y2, sp.sign(sym("r2")): SIGMA2})
    trig = []
    for angle in (th1, th2, BETA):
        c, s = sp.Dummy(), sp.Dummy()
        trig.append((c, s))
        expr = expr.xreplace({sp.cos(angle): c, sp.sin(angle): s})

    def canonical(e: sp.Expr) -> sp.Expr:
        e = sp.expand(e).replace(
            lambda p: p.is_Pow and p.base == SIGMA2, lambda p: SIGMA2 ** (p.exp % 2)
        )
        for c, s in trig:
            e = _reduce_square(e, s, 1 - c**2)
        return e

    roots: dict[sp.Expr, sp.Symbol] = {}
    for power in sorted(_half_powers(expr), key=sp.default_sort_key):
        content, base = canonical(power.base).as_content_primitive()  # sqrt(4 B) = 2 sqrt(B)
        root = roots.setdefault(base, sp.Dummy(positive=True))
        expr = expr.xreplace({power: content**power.exp * root ** int(2 * power.exp)})
    if _half_powers(expr):
        raise ValueError(f"is_zero: nested square roots are not supported: {_half_powers(expr)}")
    numerator = sp.expand(sp.numer(sp.together(expr)))
    for base, root in roots.items():
        numerator = _reduce_square(numerator, root, base)
    return canonical(numerator) == 0


def _reduce_square(polynomial: sp.Expr, x: sp.Symbol, square: sp.Expr) -> sp.Expr:
    """The remainder of an expanded polynomial modulo x^2 - square (x^k -> x^(k%2) square^(k//2)),
    expanded: of degree at most 1 in x."""
    powers = {p for p in polynomial.atoms(sp.Pow) if p.base == x and p.exp >= 2}
    return sp.expand(
        polynomial.xreplace({p: x ** (p.exp % 2) * square ** (p.exp // 2) for p in powers})
    )


def all_zero(pairs) -> bool:
    return all(is_zero(a - b) for a, b in pairs)


def _ours(d: Derivatives, expr: sp.Expr) -> sp.Expr:
    return d.in_state_symbols(expr)


def _motion_zero(symbols) -> dict:
    return {s: 0 for s in symbols}


# ------------------------------------------------------------------------------------------
# every case: the emitted expressions against the reference
# ------------------------------------------------------------------------------------------

RESTRICTIONS = {
    "full": {},
    "bias": _motion_zero(ref.ACCELERATION),
    "static2": _motion_zero(ref.BODY2_MOTION),
    "static2 bias": _motion_zero(ref.ACCELERATION + ref.BODY2_MOTION),
}


def _variants(d: Derivatives) -> dict[str, Derivatives]:
    return {"full": d, "bias": d.bias, "static2": d.static2, "static2 bias": d.static2.bias}


def inline_scalars(d, expr: sp.Expr, vectors) -> sp.Expr:
    """`expr` with the intermediates that are not named world vectors (|v|, v_tan, sigma, dx,
    dy) replaced by their definitions."""
    for s, value in reversed(d.intermediates):
        if s not in vectors:
            expr = expr.xreplace({s: value})
    return expr.replace(Hypot, lambda a, b: sp.sqrt(a**2 + b**2)).replace(
        UnitSign, lambda r: sp.sign(r)
    )


def exact_derivatives(d: Derivatives) -> list[Proof]:
    """In two steps, each an exact identity: (1) every named world vector of the derivation
    equals the reference's n(t), v(t) and derivatives at t = 0; (2) d, d', d'' written in those
    vectors equal the derivatives of the note's gap along any path of the vectors. Together:
    the derivatives of the note's gap along the reference motion, for every state. The same for
    the bias (accelerations zero) and the body-2-fixed variants."""
    name = d.case.name
    references = ref.vector_derivatives(name)
    formula = ref.gap_of_vectors(name)
    held = {}
    for variant, dv in _variants(d).items():
        still = RESTRICTIONS[variant]
        wanted = {s: value.subs(still) for s, value in references.items()}
        ok = all_zero((value, wanted[s]) for s, value in dv.intermediates if s in wanted)
        defined = {s for s, _ in dv.intermediates}
        folded = {s: value for s, value in wanted.items() if s not in defined}
        ours = (dv.gap, dv.gap_velocity, dv.gap_acceleration)
        ok = ok and all_zero(
            (inline_scalars(dv, a, wanted), b.subs(folded))
            for a, b in zip(ours, formula, strict=True)
        )
        held[variant] = ok
    definition = ref.geometry(name).definition
    return [
        Proof(
            f"{name}: d, d' and the whole d'' (velocity terms included) equal the derivatives at"
            f" t = 0 of the note's gap ({definition}) along an arbitrary motion"
            " q(t) = q + q' t + q'' t^2/2 of both bodies, for every state (not only at a contact)",
            held["full"],
        ),
        Proof(
            f"{name}: the bias (b term) equals that d'' with every acceleration zero, and the"
            " *_static2 d', d'' and bias equal it with body 2's velocity and acceleration zero",
            held["bias"] and held["static2"] and held["static2 bias"],
        ),
    ]


def jacobian_row(d: Derivatives) -> Proof:
    """J (the A-matrix row) is the gradient of the reference gap. Along the reference motion
    dd(t)/da_k = (t^2/2) dd/dq_k(t), whose second derivative at t = 0 is dd/dq_k: so the
    reference d'' is linear in the accelerations with J as coefficients, and with the bias proof
    d'' = J.a + bias holds exactly."""
    d0 = ref.gap(d.case.name)
    rows = ((d, d.jacobian, ref.POSE), (d.static2, d.static2.jacobian[:3], ref.POSE[:3]))
    pairs = [
        (_ours(dv, j), sp.diff(d0, q))
        for dv, jac, poses in rows
        for j, q in zip(jac, poses, strict=True)
    ]
    return Proof(
        f"{d.case.name}: the Jacobian row J (and the *_static2 row) equals dd/dq, hence the"
        " acceleration coefficients of the reference d'' (there dd/da = (t^2/2) dd/dq), so"
        " d'' = J.a + bias exactly",
        all_zero(pairs),
    )


def levers(d: Derivatives) -> Proof:
    """J equals the force directions: body 1 (n, R1 x n), body 2 -(n, R2 x n) at the contact point.

    Hence A = J M^-1 J^T is both symmetric and the physical 'effect of force j on d''_i', and the
    torque levers of a circular edge can use U (to its centre) in place of R (to the contact point).
    """
    case = d.case
    g = ref.geometry(case.name)
    n, v = at_instant(g.n), at_instant(g.v)
    feature1 = v + at_instant(B2.point(*_feature2(case.name)))
    radius1 = sym("r1") if case.name.startswith("circle") else 0
    contact = feature1 - radius1 * n
    x1, x2 = at_instant(B1.centre), at_instant(B2.centre)
    expected = [n[0], n[1], cross(contact - x1, n), -n[0], -n[1], -cross(contact - x2, n)]
    return Proof(
        f"{case.name}: J = (n, R1 x n, -n, -R2 x n) with R the levers from each centre of mass to"
        " the contact point, so A = J M^-1 J^T is symmetric; the kernels use"
        f" {case.lever1}1 and {case.lever2}2 (U, to a centre of curvature, has the same cross"
        " product with n: U - R is along n)",
        all_zero((_ours(d, j), e) for j, e in zip(d.jacobian, expected, strict=True)),
    )


def _feature2(name: str) -> tuple[sp.Symbol, sp.Symbol]:
    return (sym("ex2"), sym("ey2")) if name.endswith("edge") else (sym("cx2"), sym("cy2"))


# ------------------------------------------------------------------------------------------
# the note's formulas under the note's conditions
# ------------------------------------------------------------------------------------------


def _edge_contact(radius1: sp.Expr) -> tuple[dict, sp.Matrix]:
    """A contact at the edge point q = e2 + s t2 (t2 the edge direction), with n2 = (cos, sin)
    beta: body 1's feature placed at q + radius1 n at the instant (so d = 0). Returns the
    substitutions (n2, and the feature's body-1 coordinates) and q in body 2's coordinates."""
    n2 = {sym("nx2"): sp.cos(BETA), sym("ny2"): sp.sin(BETA)}
    q = sp.Matrix([sym("ex2") - S_ALONG * sp.sin(BETA), sym("ey2") + S_ALONG * sp.cos(BETA)])
    world = at_instant(B2.point(*q) + radius1 * B2.turn(sp.cos(BETA), sp.sin(BETA)))
    rel = world - at_instant(B1.centre)
    th1 = ref.POSE[2]
    c, s = sp.cos(th1), sp.sin(th1)
    fx, fy = (sym("px1"), sym("py1")) if radius1 == 0 else (sym("cx1"), sym("cy1"))
    return {**n2, fx: c * rel[0] + s * rel[1], fy: -s * rel[0] + c * rel[1]}, q


def vertex_edge_note(d: Derivatives) -> list[Proof]:
    place, q = _edge_contact(sp.Integer(0))
    p1, p2 = B1.point(sym("px1"), sym("py1")), B2.point(*q)
    n = B2.turn(sym("nx2"), sym("ny2"))
    note = 2 * dot(at_instant(n, 1), at_instant(p1 - p2, 1)) + dot(
        at_instant(n), at_instant(p1 - p2, 2)
    )
    full = _ours(d, d.gap_acceleration)
    n_beta = B2.turn(sp.cos(BETA), sp.sin(BETA))
    return [
        Proof(
            "vertex_edge: at a contact (d = 0, p1 = p2), d'' = 2 n'.(p1' - p2') + n.(p1'' - p2'')"
            " (note eq. 4), with p2 the material point of body 2 at the vertex",
            is_zero(full.subs(place) - note.subs(place)),
        ),
        Proof(
            "straight edge: n' = w2 (k x n) is perpendicular to n for any motion (note appendix)",
            is_zero(dot(at_instant(n_beta), at_instant(n_beta, 1))),
        ),
    ]


def circle_edge_note(d: Derivatives) -> list[Proof]:
    place, q = _edge_contact(sym("r1"))
    c1 = B1.point(sym("cx1"), sym("cy1"))
    n = B2.turn(sym("nx2"), sym("ny2"))
    w2, al2, r1 = ref.VELOCITY[5], ref.ACCELERATION[5], sym("r1")
    tangent = sp.Matrix([-sp.sin(BETA), sp.cos(BETA)])

    def note_eq11(q_body2: sp.Matrix) -> sp.Expr:
        v = c1 - B2.point(*q_body2)
        eq = 2 * dot(at_instant(n, 1), at_instant(v, 1)) + dot(at_instant(n), at_instant(v, 2))
        return (eq - w2**2 * r1).subs(place)

    full = _ours(d, d.gap_acceleration).subs(place)
    return [
        Proof(
            "circle_edge: at a contact, with p2 the material point of body 2 under the centre c1,"
            " d'' = 2 n'.(c1' - p2') + n.(c1'' - p2'') - w2^2 r1 (note eq. 11)",
            is_zero(full - note_eq11(q)),
        ),
        Proof(
            "circle_edge, hidden condition: if p2 is another point of the edge, a distance u along"
            " it, eq. 11 is off by al2*u (the note's n'' = -w2^2 n drops al2 (k x n))",
            is_zero(full - note_eq11(q + U_OFF * tangent) + al2 * U_OFF),
        ),
    ]


def circle_note(d: Derivatives) -> Proof:
    """Eq. 8 (vertex) and 12 (circle), in the derivation's named vectors (proved equal to the
    reference's by `exact_derivatives`): exact for any state, no contact condition needed."""
    name = d.case.name
    v = ref.vector_path("v")
    n = sp.sign(sym("r2")) * v / sp.sqrt(dot(v, v))
    n1 = at_instant(n, 1)
    note = dot(n1, at_instant(v, 1)) + dot(at_instant(n), at_instant(v, 2))
    vectors = ref.vector_derivatives(name)
    ours = inline_scalars(d, d.gap_acceleration, vectors)
    q = "p1" if name.startswith("vertex") else "c1"
    eq = "8" if name.startswith("vertex") else "12"
    return Proof(
        f"{name}: the kernels' d'' = sigma(v.v'' + v_tan^2)/|v| with v_tan = (v x v')/|v| (a form"
        " that does not cancel when v' is along v) equals"
        f" n'.({q}' - c2') + n.({q}'' - c2'') (note eq. {eq}), n = sigma v/|v|, for every state"
        " (not only at a contact), and n'.n = 0 (note appendix)",
        is_zero(ours - note) and is_zero(dot(at_instant(n), n1)),
    )


def proofs_for(d: Derivatives) -> list[Proof]:
    out = [*exact_derivatives(d), jacobian_row(d), levers(d)]
    if d.case.name == "vertex_edge":
        return out + vertex_edge_note(d)
    if d.case.name == "circle_edge":
        return out + circle_edge_note(d)
    return [*out, circle_note(d)]
