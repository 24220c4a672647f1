"""d, d', d'' of every case by SymPy differentiation, and their split into A-matrix and b-vector parts.

The gap is a function of world vectors (the normal n(t) of a straight edge, the vector v(t) from the
edge to body 1's feature). SymPy differentiates it through abstract vector functions (the chain
rule), then those vectors and their derivatives are named intermediates, each itself differentiated
by SymPy from the bodies' kinematics. The generated code computes the intermediates once.

The derivatives are exact for any state (no contact assumption): the runtime evaluates them at
resting contacts (d = 0) and off contact (to locate impacts). d'' is linear in the accelerations; its
coefficients form the Jacobian row J (equal to dd/dq and dd'/dv) and the rest is the bias. With
contact forces f along the normals, A = J M^-1 J^T and b = J M^-1 F_ext + bias.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from derive.cases import SIGMA2, CaseDefinition
from derive.kinematics import BODY1, BODY2, DX, DY, real, t, to_state

POSE = BODY1.pose_symbols() + BODY2.pose_symbols()
VELOCITY = BODY1.velocity_symbols() + BODY2.velocity_symbols()
ACCELERATION = BODY1.acceleration_symbols() + BODY2.acceleration_symbols()
BODY2_MOTION = BODY2.velocity_symbols() + BODY2.acceleration_symbols()
V_LEN = sp.Symbol("v_len", positive=True)
V_TAN = real("v_tan")  # tangential relative speed (v x v')/|v|
_SPINS = (VELOCITY[2], VELOCITY[5])  # w1, w2: grouping by them lets CSE share the lever vectors
_SPIN_RATES = (ACCELERATION[2], ACCELERATION[5])


class Hypot(sp.Function):
    """|(a, b)|, printed as sqrt(a*a + b*b).

    numpy.hypot guards against overflow and underflow beyond 1e+-154, far outside any scene (radii
    1e-6 to 1e6), and costs 5x the square root (bench/README.md), so the kernels use the root.
    """

    nargs = 2

    def fdiff(self, argindex: int = 1) -> sp.Expr:
        """d|(a, b)|/da = a/|(a, b)|: the chain rule through a length (derive/applied.py)."""
        return self.args[argindex - 1] / self

    def _numpycode(self, printer) -> str:
        a, b = (printer._print(arg) for arg in self.args)
        return f"{printer._module_format('numpy.sqrt')}({a} * {a} + {b} * {b})"

    def _latex(self, printer) -> str:
        a, b = (printer._print(arg) for arg in self.args)
        return rf"\sqrt{{{a}^2 + {b}^2}}"


class UnitSign(sp.Function):
    """sign(r) with sign(0) = +1, printed as numpy.copysign(1.0, r): a zero radius is a vertex."""

    nargs = 1

    def _numpycode(self, printer) -> str:
        return f"{printer._module_format('numpy.copysign')}(1.0, {printer._print(self.args[0])})"

    def _latex(self, printer) -> str:
        return rf"\operatorname{{sign}}({printer._print(self.args[0])})"


Intermediates = tuple[tuple[sp.Symbol, sp.Expr], ...]


def total_derivative(intermediates: Intermediates, expr: sp.Expr, symbol: sp.Symbol) -> sp.Expr:
    """d expr / d symbol, following the chain rule through the intermediates (each depends only
    on earlier ones)."""
    inner: dict[sp.Symbol, sp.Expr] = {}
    for s, value in intermediates:
        inner[s] = sp.diff(value, symbol) + sum(
            (sp.diff(value, u) * du for u, du in inner.items()), sp.Integer(0)
        )
    total = sp.diff(expr, symbol) + sum(
        (sp.diff(expr, s) * ds for s, ds in inner.items()), sp.Integer(0)
    )
    return sp.factor_terms(sp.simplify(total))


def fold_state(
    intermediates: Intermediates, values: dict[sp.Symbol, sp.Expr]
) -> tuple[Intermediates, dict[sp.Symbol, sp.Expr]]:
    """The intermediates with some state symbols fixed, and the substitutions for the rest.

    Intermediates that become constants (n' = 0 for a fixed body) are folded into the
    substitutions, so the specialised kernels do not compute terms that are known to vanish.
    """
    folded = dict(values)
    inter = []
    for s, e in intermediates:
        value = e.subs(folded)
        if value.is_number:
            folded[s] = value
        else:
            inter.append((s, value))
    return tuple(inter), folded


def needed(intermediates: Intermediates, outputs) -> Intermediates:
    """The intermediates the outputs use, directly or through each other, in order."""
    used: set[sp.Symbol] = set().union(*(o.free_symbols for o in outputs))
    for s, value in reversed(intermediates):
        if s in used:
            used |= value.free_symbols
    return tuple((s, v) for s, v in intermediates if s in used)


def inline(intermediates: Intermediates, expr: sp.Expr) -> sp.Expr:
    """`expr` with every intermediate replaced by its definition (proofs, lambdify)."""
    for s, value in reversed(intermediates):
        expr = expr.subs(s, value)
    return expr.replace(Hypot, lambda a, b: sp.sqrt(a**2 + b**2)).replace(
        UnitSign, lambda r: sp.sign(r)
    )


def vector_names(stem: str) -> list[tuple[sp.Symbol, sp.Symbol, sp.Symbol]]:
    """Symbols for a world vector and its first two time derivatives, per component."""
    return [
        (real(f"{stem}_{c}"), real(f"{stem}_{c}_t"), real(f"{stem}_{c}_tt")) for c in ("x", "y")
    ]


@dataclass(frozen=True)
class Derivatives:
    """Exact d, d', d'' of one case, written in named intermediates over the state symbols."""

    case: CaseDefinition
    intermediates: tuple[tuple[sp.Symbol, sp.Expr], ...]
    gap: sp.Expr
    gap_velocity: sp.Expr
    gap_acceleration: sp.Expr

    def total_derivative(self, expr: sp.Expr, symbol: sp.Symbol) -> sp.Expr:
        """d expr / d symbol, following the chain rule through the intermediates."""
        return total_derivative(self.intermediates, expr, symbol)

    @cached_property
    def jacobian(self) -> tuple[sp.Expr, ...]:
        """Coefficients of (ax1, ay1, al1, ax2, ay2, al2) in d'': dd/d(x1, y1, th1, x2, y2, th2)."""
        return tuple(self.total_derivative(self.gap_acceleration, a) for a in ACCELERATION)

    def with_state(self, values: dict[sp.Symbol, sp.Expr]) -> Derivatives:
        """The same derivatives with some state symbols fixed (e.g. zero accelerations)."""
        inter, folded = fold_state(self.intermediates, values)
        return Derivatives(
            self.case,
            inter,
            self.gap.subs(folded),
            self.gap_velocity.subs(folded),
            self.gap_acceleration.subs(folded),
        )

    @cached_property
    def bias(self) -> Derivatives:
        """d'' with every acceleration zero: the velocity-dependent b term."""
        return self.with_state({a: 0 for a in ACCELERATION})

    @cached_property
    def static2(self) -> Derivatives:
        """Body 2 fixed: its velocity and acceleration are zero."""
        return self.with_state({m: 0 for m in BODY2_MOTION})

    def in_state_symbols(self, expr: sp.Expr) -> sp.Expr:
        """`expr` with every intermediate replaced by its definition (proofs, lambdify)."""
        return inline(self.intermediates, expr)


def vector_intermediates(
    stem: str, world: sp.Matrix, orders: int = 3
) -> list[tuple[sp.Symbol, sp.Expr]]:
    """A world vector and its time derivatives, in state symbols, ordered v_x, v_y, v_x_t, ..."""
    names = vector_names(stem)
    rates = [w**2 for w in _SPINS] + list(_SPINS) + list(_SPIN_RATES)
    return [
        (names[k][order], sp.collect(to_state(sp.diff(world[k], t, order)), rates))
        for order in range(orders)
        for k in range(2)
    ]


def abstract_vector(stem: str) -> tuple[list[sp.Expr], dict[sp.Expr, sp.Symbol]]:
    """Abstract functions for a vector, and the map from their derivatives to intermediate names."""
    funcs, names = [], {}
    for c, (s0, s1, s2) in zip(("x", "y"), vector_names(stem), strict=True):
        f = sp.Function(f"{stem.upper()}{c}", real=True)(t)
        funcs.append(f)
        names.update({sp.Derivative(f, (t, 2)): s2, sp.Derivative(f, t): s1})
        names[f] = s0
    return funcs, names


def rename(expr: sp.Expr, names: dict[sp.Expr, sp.Symbol]) -> sp.Expr:
    derivs = {k: v for k, v in names.items() if isinstance(k, sp.Derivative)}
    return expr.subs(derivs).subs({k: v for k, v in names.items() if k not in derivs})


def translation() -> list[tuple[sp.Symbol, sp.Expr]]:
    x1, y1, _ = BODY1.pose_symbols()
    x2, y2, _ = BODY2.pose_symbols()
    return [(DX, x1 - x2), (DY, y1 - y2)]


def _line_case(case: CaseDefinition) -> Derivatives:
    """d = n(t).v(t) - offset, n rigidly attached to body 2."""
    (nx, ny), n_names = abstract_vector("n")
    (vx, vy), v_names = abstract_vector("v")
    d = nx * vx + ny * vy - case.offset
    names = {**n_names, **v_names}
    d0, d1, d2 = (rename(sp.diff(d, t, k), names) for k in range(3))
    inter = translation() + vector_intermediates("n", case.normal)
    inter += vector_intermediates("v", case.v)
    return Derivatives(case, tuple(inter), d0, d1, d2)


def norm_second_derivative() -> tuple[sp.Expr, sp.Expr]:
    """SymPy's d''/sigma of |v| and the stable form the kernels use, both over v_x, v_y, v_x_t, ...

    SymPy's second derivative is (|v'|^2 + v.v'')/|v| - (v.v')^2/|v|^3, whose velocity terms cancel
    when v' is along v. The kernels use the equal form v.v''/|v| + v_tan^2/|v| with the tangential
    relative speed v_tan = (v x v')/|v| (Lagrange's identity): no cancellation, and no |v|^3 to
    underflow. `_circle_case` has SymPy prove the two equal every time it derives.
    """
    (vx, vy), names = abstract_vector("v")
    raw = rename(sp.diff(sp.sqrt(vx**2 + vy**2), t, 2), names)
    (sx, sx_t, sx_tt), (sy, sy_t, sy_tt) = vector_names("v")
    stable = (sx * sx_tt + sy * sy_tt) / V_LEN + V_TAN**2 / V_LEN
    length = sp.sqrt(sx**2 + sy**2)
    return raw, stable.subs(V_TAN, (sx * sy_t - sy * sx_t) / V_LEN).subs(V_LEN, length)


def _circle_case(case: CaseDefinition) -> Derivatives:
    """d = sigma |v(t)| - offset, normal n = sigma v/|v|."""
    raw, stable = norm_second_derivative()
    if sp.simplify(raw - stable) != 0:
        raise AssertionError("the stable form of d'' for |v| differs from SymPy's derivative")
    (vx, vy), names = abstract_vector("v")
    (sx, sx_t, sx_tt), (sy, sy_t, sy_tt) = vector_names("v")
    length = sp.sqrt(sx**2 + sy**2)
    d0, d1 = (rename(SIGMA2 * sp.diff(sp.sqrt(vx**2 + vy**2), t, k), names) for k in (0, 1))
    d0, d1 = (e.subs(length, V_LEN) for e in (d0, d1))
    d2 = SIGMA2 * ((sx * sx_tt + sy * sy_tt) / V_LEN + V_TAN**2 / V_LEN)
    radius2 = case.geometry[-1]
    inter = translation() + [(SIGMA2, UnitSign(radius2))]
    inter += vector_intermediates("v", case.v)
    inter.insert(5, (V_LEN, Hypot(sx, sy)))  # right after v_x, v_y
    inter.insert(8, (V_TAN, (sx * sy_t - sy * sx_t) / V_LEN))  # right after v_x_t, v_y_t
    return Derivatives(case, tuple(inter), d0 - case.offset, d1, d2)


def derive(case: CaseDefinition) -> Derivatives:
    """Differentiate the case's gap twice along an arbitrary motion of both bodies."""
    return _line_case(case) if case.kind == "line" else _circle_case(case)
