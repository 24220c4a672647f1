"""The proofs' reference: each case's gap written again from the note, along an explicit motion.

derive/derivation.py differentiates through abstract functions of time (kinematics.py) and names
the results with state symbols. The reference shares none of that code, only the symbol names:
every body follows the explicit trajectory

    x(t) = x + vx t + ax t^2/2,   y(t) likewise,   th(t) = th + w t + al t^2/2,

a body point is X(t) + R(th(t)) p with the rotation matrix typed out, and the world vectors n(t),
v(t) and the gap are the note's definitions (eq. 1, 5-6, sections 4 and 5). Derivatives at t = 0
depend only on the position, velocity and acceleration at that instant, so this quadratic motion is
as general as any; they are SymPy's plain `diff` in t of explicit expressions.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import sympy as sp

TAU = sp.Symbol("tau", real=True)  # time t, measured from the instant considered


def sym(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)


def dot(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    return a[0] * b[0] + a[1] * b[1]


def cross(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    return a[0] * b[1] - a[1] * b[0]


@dataclass(frozen=True)
class Motion:
    """Body `i` along its quadratic trajectory in tau (state symbols as coefficients)."""

    i: int

    def coordinate(self, q: str, rate: str, acc: str) -> sp.Expr:
        i = self.i
        return sym(f"{q}{i}") + sym(f"{rate}{i}") * TAU + sym(f"{acc}{i}") * TAU**2 / 2

    @property
    def centre(self) -> sp.Matrix:
        return sp.Matrix([self.coordinate("x", "vx", "ax"), self.coordinate("y", "vy", "ay")])

    @property
    def angle(self) -> sp.Expr:
        return self.coordinate("th", "w", "al")

    def turn(self, px: sp.Expr, py: sp.Expr) -> sp.Matrix:
        c, s = sp.cos(self.angle), sp.sin(self.angle)
        return sp.Matrix([[c, -s], [s, c]]) * sp.Matrix([px, py])

    def point(self, px: sp.Expr, py: sp.Expr) -> sp.Matrix:
        return self.centre + self.turn(px, py)


B1, B2 = Motion(1), Motion(2)
POSE = tuple(sym(f"{q}{i}") for i in (1, 2) for q in ("x", "y", "th"))
VELOCITY = tuple(sym(f"{q}{i}") for i in (1, 2) for q in ("vx", "vy", "w"))
ACCELERATION = tuple(sym(f"{q}{i}") for i in (1, 2) for q in ("ax", "ay", "al"))
BODY2_MOTION = VELOCITY[3:] + ACCELERATION[3:]

_FEATURE1 = {"vertex": ("px1", "py1"), "circle": ("cx1", "cy1")}


@dataclass(frozen=True)
class Geometry:
    """A case's vector v(tau) from body 2's feature to body 1's, and its normal n(tau)."""

    v: sp.Matrix
    n: sp.Matrix
    offset: sp.Expr
    definition: str


@cache
def geometry(case: str) -> Geometry:
    """The note's definitions: straight edge n = R(th2) n2, d = n.v - r1 (section 2 and 4);
    circular edge n = sigma v/|v|, d = sigma |v| - r2 - r1 (eq. 5-6, section 5), sigma = sign(r2)."""
    first, second = case.split("_")
    p1 = B1.point(*map(sym, _FEATURE1[first]))
    r1 = sym("r1") if first == "circle" else sp.Integer(0)
    if second == "edge":
        v = p1 - B2.point(sym("ex2"), sym("ey2"))
        n = B2.turn(sym("nx2"), sym("ny2"))
        return Geometry(v, n, r1, "d = n.v - r1, n = R(th2) n2" if r1 else "d = n.v, n = R(th2) n2")
    v = p1 - B2.point(sym("cx2"), sym("cy2"))
    sigma = sp.sign(sym("r2"))
    n = sigma * v / sp.sqrt(dot(v, v))
    definition = "d = sigma |v| - r2" + (" - r1" if r1 else "") + ", sigma = sign(r2)"
    return Geometry(v, n, r1 + sym("r2"), definition)


def at_instant(expr: sp.Expr, order: int = 0) -> sp.Expr:
    """The order-th derivative in tau at tau = 0 (works on matrices too)."""
    return sp.diff(expr, TAU, order).subs(TAU, 0) if order else expr.subs(TAU, 0)


def gap(case: str) -> sp.Expr:
    """The gap d at the instant, in state symbols: the reference for d and the Jacobian dd/dq."""
    g = geometry(case)
    return at_instant(dot(g.n, g.v) - g.offset)


def _named(stem: str, c: str, order: int) -> sp.Symbol:
    """The derivation's name of a world-vector component or its time derivative (v_x_tt)."""
    return sym(f"{stem}_{c}{('', '_t', '_tt')[order]}")


@cache
def vector_derivatives(case: str) -> dict[sp.Symbol, sp.Expr]:
    """n, v and their first two time derivatives at the instant, keyed by the derivation's names
    (n_x, v_y_t, ...), in state symbols."""
    g = geometry(case)
    out = {}
    for stem, vector in (("v", g.v), ("n", g.n)):
        for order in range(3):
            value = at_instant(vector, order)
            out.update({_named(stem, c, order): value[k] for k, c in enumerate("xy")})
    return out


def vector_path(stem: str) -> sp.Matrix:
    """A vector along an arbitrary path, given by its named value and derivatives at t = 0."""
    return sp.Matrix(
        [_named(stem, c, 0) + _named(stem, c, 1) * TAU + _named(stem, c, 2) * TAU**2 / 2
         for c in "xy"]
    )  # fmt: skip


@cache
def gap_of_vectors(case: str) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """d, d', d'' at t = 0 of the note's gap as a function of the world vectors (straight edge
    n.v - r1, circular edge sigma|v| - r2 - r1), along an arbitrary path of the vectors."""
    v, offset = vector_path("v"), geometry(case).offset
    if case.endswith("edge"):
        d = dot(vector_path("n"), v) - offset
    else:
        d = sp.sign(sym("r2")) * sp.sqrt(dot(v, v)) - offset
    return tuple(at_instant(d, k) for k in range(3))
