"""Planar rigid-body kinematics in SymPy.

Each body i has a centre-of-mass position X_i(t) = (x_i(t), y_i(t)) and an angle th_i(t). A point or
direction fixed in the body is rotated by R(th_i). Time derivatives are left to SymPy; `to_state`
then names them with the flat state symbols the generated kernels take (vx1, ax1, w1, al1, ...).
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

t = sp.Symbol("t", real=True)


def real(name: str) -> sp.Symbol:
    return sp.Symbol(name, real=True)


@dataclass(frozen=True)
class PlanarBody:
    """Body `index` as functions of time, plus the state symbols that replace them."""

    index: int

    def _f(self, stem: str) -> sp.Expr:
        return sp.Function(f"{stem}{self.index}", real=True)(t)

    @property
    def x(self) -> sp.Expr:
        return self._f("x")

    @property
    def y(self) -> sp.Expr:
        return self._f("y")

    @property
    def th(self) -> sp.Expr:
        return self._f("th")

    def rotate(self, vx: sp.Expr, vy: sp.Expr) -> sp.Matrix:
        """A body-fixed direction in world coordinates: R(th) (vx, vy)."""
        c, s = sp.cos(self.th), sp.sin(self.th)
        return sp.Matrix([c * vx - s * vy, s * vx + c * vy])

    def point(self, px: sp.Expr, py: sp.Expr) -> sp.Matrix:
        """A body-fixed point in world coordinates: X + R(th) p."""
        return sp.Matrix([self.x, self.y]) + self.rotate(px, py)

    def pose_symbols(self) -> tuple[sp.Symbol, ...]:
        i = self.index
        return real(f"x{i}"), real(f"y{i}"), real(f"th{i}")

    def velocity_symbols(self) -> tuple[sp.Symbol, ...]:
        i = self.index
        return real(f"vx{i}"), real(f"vy{i}"), real(f"w{i}")

    def acceleration_symbols(self) -> tuple[sp.Symbol, ...]:
        i = self.index
        return real(f"ax{i}"), real(f"ay{i}"), real(f"al{i}")

    def state_replacements(self) -> dict[sp.Expr, sp.Symbol]:
        """Map q(t), q'(t), q''(t) to the state symbols (second derivatives first)."""
        out: dict[sp.Expr, sp.Symbol] = {}
        coords = (self.x, self.y, self.th)
        for q, a in zip(coords, self.acceleration_symbols(), strict=True):
            out[sp.Derivative(q, (t, 2))] = a
        for q, v in zip(coords, self.velocity_symbols(), strict=True):
            out[sp.Derivative(q, t)] = v
        for q, p in zip(coords, self.pose_symbols(), strict=True):
            out[q] = p
        return out


BODY1 = PlanarBody(1)
BODY2 = PlanarBody(2)
BODIES = (BODY1, BODY2)

# Gap functions are invariant under a common translation, so after naming the state they depend on
# x1 and x2 only through dx = x1 - x2; computing dx first keeps digits for scenes far from the origin.
DX, DY = real("dx"), real("dy")


def to_state(expr: sp.Expr) -> sp.Expr:
    """Replace derivatives and functions of t by state symbols, and x1, y1 by x2 + dx, y2 + dy."""
    for body in BODIES:
        reps = body.state_replacements()
        # Derivatives must go before the bare functions they contain.
        expr = expr.subs({k: v for k, v in reps.items() if isinstance(k, sp.Derivative)})
        expr = expr.subs({k: v for k, v in reps.items() if not isinstance(k, sp.Derivative)})
    x1, y1, _ = BODY1.pose_symbols()
    x2, y2, _ = BODY2.pose_symbols()
    return expr.subs({x1: x2 + DX, y1: y2 + DY})


def dot(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    return a[0] * b[0] + a[1] * b[1]


def cross(a: sp.Matrix, b: sp.Matrix) -> sp.Expr:
    """z-component of the 3-D cross product of two plane vectors."""
    return a[0] * b[1] - a[1] * b[0]
