"""Symbolic proofs that the derived equations agree with the note, and where the note needs care.

Each proof returns a `Proof` (statement, holds). Tests assert every proof holds; the LaTeX document
prints them. The proofs work from the kinematics again, not from the derived expressions' code.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from derive.cases import CX1, CX2, CY1, CY2, EX2, EY2, NX2, NY2, PX1, PY1, R1, R2, SIGMA2
from derive.derivation import Derivatives, norm_second_derivative
from derive.kinematics import BODY1, BODY2, DX, DY, cross, dot, real, t, to_state

BETA = real("beta")  # direction angle of the edge normal in body 2: (nx2, ny2) = (cos, sin)
S_ALONG = real("s")  # position along the straight edge
U_OFF = real("u")  # offset of the note's p2 from the true contact point


@dataclass(frozen=True)
class Proof:
    statement: str
    holds: bool
    detail: str = ""


def _is_zero(expr: sp.Expr) -> bool:
    """Exact zero test: absolute positions, cos/sin as polynomial variables reduced by c^2 + s^2 = 1."""
    x1, y1, th1 = BODY1.pose_symbols()
    x2, y2, th2 = BODY2.pose_symbols()
    expr = expr.subs({DX: x1 - x2, DY: y1 - y2, sp.sign(R2): SIGMA2})
    trig = {}
    for angle in (th1, th2, BETA):
        c, s = sp.Dummy(), sp.Dummy()
        trig[angle] = (c, s)
        expr = expr.subs({sp.cos(angle): c, sp.sin(angle): s})
    numerator = sp.numer(sp.together(expr))
    numerator = sp.expand(numerator).replace(
        lambda e: e.is_Pow and e.base == SIGMA2, lambda e: SIGMA2 ** (e.exp % 2)
    )
    for c, s in trig.values():
        numerator = sp.rem(sp.expand(numerator), s**2 + c**2 - 1, s)
    return sp.expand(numerator) == 0


def _state(v) -> sp.Matrix:
    return v.applyfunc(to_state)


def _unit_normal() -> dict[sp.Symbol, sp.Expr]:
    return {NX2: sp.cos(BETA), NY2: sp.sin(BETA)}


def _vertex_at(body_point_world: sp.Matrix, px: sp.Symbol, py: sp.Symbol) -> dict:
    """Body-1 coordinates (px, py) that put body 1's point at `body_point_world` at time t."""
    x1, y1, th1 = BODY1.x, BODY1.y, BODY1.th
    rel = body_point_world - sp.Matrix([x1, y1])
    c, s = sp.cos(th1), sp.sin(th1)
    return {px: c * rel[0] + s * rel[1], py: -s * rel[0] + c * rel[1]}


def _full_d2(d: Derivatives) -> sp.Expr:
    return d.in_state_symbols(d.gap_acceleration)


def _edge_contact(d: Derivatives, feature_x, feature_y, radius) -> tuple[dict, sp.Matrix]:
    """State substitutions for a contact on body 2's straight edge at edge point q(s).

    Body 1's feature (vertex, or circle centre at distance `radius` along n) is placed so that
    d = 0 and it touches q. Returns (substitutions, world p2(t) of the material point q).
    """
    q = sp.Matrix([EX2 - S_ALONG * sp.sin(BETA), EY2 + S_ALONG * sp.cos(BETA)])
    p2 = BODY2.point(q[0], q[1])
    n = BODY2.rotate(sp.cos(BETA), sp.sin(BETA))
    place = _vertex_at(p2 + radius * n, feature_x, feature_y)
    return place, p2


def _at_instant(expr: sp.Expr, subs: dict) -> sp.Expr:
    """Substitute time-t geometry, then name the state (geometry depends on the pose at t)."""
    return to_state(expr.subs(subs))


def vertex_edge_note(d: Derivatives) -> list[Proof]:
    place, p2 = _edge_contact(d, PX1, PY1, 0)
    p1 = BODY1.point(PX1, PY1)
    n = BODY2.rotate(NX2, NY2)
    note = 2 * dot(sp.diff(n, t), sp.diff(p1 - p2, t)) + dot(n, sp.diff(p1 - p2, t, 2))
    # The geometry is fixed in the bodies: differentiate first, then place the vertex at the instant.
    note_state = _at_instant(note.subs(_unit_normal()), {})
    full = _full_d2(d).subs(_unit_normal())
    subs = {k: to_state(v) for k, v in place.items()}
    diff = full.subs(subs) - note_state.subs(subs)
    return [
        Proof(
            "vertex_edge: at a contact (d = 0, p1 = p2), d'' = 2 n'.(p1' - p2') + n.(p1'' - p2'')"
            " (note eq. 4), with p2 the material point of body 2 at the vertex",
            _is_zero(diff),
        )
    ]


def circle_edge_note(d: Derivatives) -> list[Proof]:
    place, p2 = _edge_contact(d, CX1, CY1, R1)
    c1 = BODY1.point(CX1, CY1)
    n = BODY2.rotate(NX2, NY2)
    w2 = sp.diff(BODY2.th, t)
    tangent = BODY2.rotate(-NY2, NX2)

    def note_eq11(p2_world):
        v = c1 - p2_world
        return 2 * dot(sp.diff(n, t), sp.diff(v, t)) + dot(n, sp.diff(v, t, 2)) - w2**2 * R1

    subs = {k: to_state(v) for k, v in place.items()}
    full = _full_d2(d).subs(_unit_normal()).subs(subs)
    exact = _at_instant(note_eq11(p2).subs(_unit_normal()), {}).subs(subs)
    shifted_p2 = p2 + U_OFF * tangent.subs(_unit_normal())
    off = _at_instant(note_eq11(shifted_p2).subs(_unit_normal()), {}).subs(subs)
    al2 = BODY2.acceleration_symbols()[2]
    return [
        Proof(
            "circle_edge: at a contact, with p2 the material point of body 2 under the centre c1,"
            " d'' = 2 n'.(c1' - p2') + n.(c1'' - p2'') - w2^2 r1 (note eq. 11)",
            _is_zero(full - exact),
        ),
        Proof(
            "circle_edge, hidden condition: if p2 is another point of the edge, a distance u along"
            " it, eq. 11 is off by al2*u (the note's n'' = -w2^2 n drops al2 (k x n))",
            _is_zero(full - off + al2 * U_OFF),
        ),
    ]


def _abstract_circle_note() -> Proof:
    """d'' = n'.v' + n.v'' (note eq. 8 and 12) for d = sigma|v| - r, n = sigma v/|v|, any v(t)."""
    vx, vy = sp.Function("Vx", real=True)(t), sp.Function("Vy", real=True)(t)
    v = sp.Matrix([vx, vy])
    length = sp.sqrt(vx**2 + vy**2)
    n = SIGMA2 * v / length
    ours = sp.diff(SIGMA2 * length, t, 2)
    note = dot(sp.diff(n, t), sp.diff(v, t)) + dot(n, sp.diff(v, t, 2))
    perp = sp.simplify(dot(n, sp.diff(n, t)).subs(SIGMA2**2, 1))
    return Proof(
        "circular edge: d'' = n'.v' + n.v'' exactly, for any motion (note eq. 8, 12), and n'.n = 0",
        sp.simplify(ours - note) == 0 and perp == 0,
    )


def stable_form(d: Derivatives) -> Proof:
    raw, stable = norm_second_derivative()
    return Proof(
        f"{d.case.name}: the kernel's d'' = sigma(v.v'' + v_tan^2)/|v|, v_tan = (v x v')/|v|, equals SymPy's"
        " second derivative of sigma|v| (no cancellation when v' is along v)",
        sp.simplify(raw - stable) == 0,
    )


def edge_normal_perpendicular() -> Proof:
    n = BODY2.rotate(NX2, NY2)
    return Proof(
        "straight edge: n' = w2 (k x n) is perpendicular to n (note appendix)",
        _is_zero(to_state(dot(n, sp.diff(n, t)))),
    )


def levers(d: Derivatives) -> Proof:
    """J equals the force directions: body 1 (n, R1 x n), body 2 -(n, R2 x n) at the contact point.

    Hence A = J M^-1 J^T is both symmetric and the physical 'effect of force j on d''_i', and the
    torque levers of a circular edge can use U (to its centre) in place of R (to the contact point).
    """
    case = d.case
    if case.kind == "line":
        n = BODY2.rotate(NX2, NY2)
        feature1 = case.v + BODY2.point(EX2, EY2)  # world position of body 1's vertex or centre
        contact = feature1 - R1 * n if case.name == "circle_edge" else feature1
    else:
        v = case.v
        sigma = sp.sign(R2)
        n = sigma * v / sp.sqrt(dot(v, v))
        contact = BODY2.point(CX2, CY2) + R2 * n
    x1 = sp.Matrix([BODY1.x, BODY1.y])
    x2 = sp.Matrix([BODY2.x, BODY2.y])
    expected = [n[0], n[1], cross(contact - x1, n), -n[0], -n[1], -cross(contact - x2, n)]
    ok = all(
        _is_zero(d.in_state_symbols(j) - to_state(e))
        for j, e in zip(d.jacobian, expected, strict=True)
    )
    lever = "U (to the centre of curvature)" if "circle" in case.name else "R"
    return Proof(
        f"{case.name}: J = (n, R1 x n, -n, -R2 x n) with R the levers to the contact point;"
        f" body 1 may use {case.lever1}1, body 2 {case.lever2}2 ({lever}), so A is symmetric",
        ok,
    )


def proofs_for(d: Derivatives) -> list[Proof]:
    out = [levers(d)]
    if d.case.name == "vertex_edge":
        out += vertex_edge_note(d) + [edge_normal_perpendicular()]
    elif d.case.name == "circle_edge":
        out += circle_edge_note(d)
    else:
        out += [stable_form(d), _abstract_circle_note()]
    return out
