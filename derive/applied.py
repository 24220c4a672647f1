"""Applied forces of issue #16 (springs, body damping, mutual gravitation) by SymPy, from their
potential V and Rayleigh dissipation function R: the generalized forces

    Q_k = -dV/dq_k - dR/dq'_k,    q = (x1, y1, th1, x2, y2, th2)

(force and torque on each body), and V itself, which run.energy adds to the kinetic and the
gravitational energy. Unlike a joint they are no constraint: the runtime adds Q / m to the free
accelerations at every stage (runtime/solve/applied_forces.py).

    spring          V = k/2 (|s| - L)^2,  R = c/2 (d|s|/dt)^2,  s = p1 - p2 between the anchors
                    p_i = X_i + R(th_i) a_i (body 2 may be the world: the *_static2 kernel)
    mutual_gravity  V = -G m1 m2 / |X1 - X2|
    body_damping    R = (k_lin m |v|^2 + k_ang I w^2)/2 of one body (k in 1/s)

SymPy differentiates V and R through the named intermediates (s, |s|, d|s|/dt) by the chain rule
(derive/derivation.total_derivative). The spring's direction s/|s| is undefined when its anchors
coincide: the kernels take 1/|s| as 0 there (no force along no direction; for L = 0 the exact
force -k s is 0 there too).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from derive.derivation import (
    POSE,
    VELOCITY,
    Hypot,
    Intermediates,
    abstract_vector,
    fold_state,
    inline,
    rename,
    total_derivative,
    translation,
    vector_intermediates,
    vector_names,
)
from derive.kinematics import BODY1, BODY2, DX, DY, real, t, to_state

PX1, PY1, PX2, PY2 = real("px1"), real("py1"), real("px2"), real("py2")
STIFFNESS, REST_LENGTH, DAMPING = real("stiffness"), real("rest_length"), real("damping")
G, M1, M2, I1 = real("G"), real("m1"), real("m2"), real("i1")
K_LIN, K_ANG = real("k_lin"), real("k_ang")
S_LEN = sp.Symbol("s_len", positive=True)  # |s|
S_INV = real("s_inv")  # 1/|s|, 0 when the anchors coincide
S_RATE = real("s_rate")  # d|s|/dt
DISTANCE = sp.Symbol("r", positive=True)  # |X1 - X2|


class InverseOrZero(sp.Function):
    """1/x for x > 0, and 0 at x = 0, printed as 1 / np.where(x > 0, x, np.inf) (no warning)."""

    nargs = 1

    def _numpycode(self, printer) -> str:
        x = printer._print(self.args[0])
        where, inf = printer._module_format("numpy.where"), printer._module_format("numpy.inf")
        return f"1 / {where}({x} > 0, {x}, {inf})"

    def _latex(self, printer) -> str:
        return rf"\frac{{1}}{{{printer._print(self.args[0])}}}"


@dataclass(frozen=True)
class AppliedDefinition:
    """An applied force: what it acts on, its parameters and its V and R in words."""

    name: str
    title: str
    bodies: int  # 2, or 1 for a force of one body on itself (damping)
    world_end: bool  # body 2 may be the world (a *_static2 kernel)
    parameters: tuple[sp.Symbol, ...]
    potential: str
    dissipation: str
    textbook: str  # the closed form the proofs compare with
    notes: str  # for the generated module's docstring
    derive: Callable[[], tuple[Intermediates, sp.Expr, sp.Expr]]

    @property
    def coordinates(self) -> tuple[sp.Symbol, ...]:
        return POSE[: 3 * self.bodies]

    @property
    def rates(self) -> tuple[sp.Symbol, ...]:
        return VELOCITY[: 3 * self.bodies]


@dataclass(frozen=True, eq=False)
class AppliedDerived:
    """V, R and Q = -dV/dq - dR/dq' of one applied force, in named intermediates."""

    definition: AppliedDefinition
    intermediates: Intermediates
    potential: sp.Expr
    dissipation: sp.Expr
    forces: tuple[sp.Expr, ...]

    @property
    def name(self) -> str:
        return self.definition.name

    @cached_property
    def static2(self) -> AppliedDerived:
        """Body 2 at rest (the world, or a fixed body): its velocity zero."""
        inter, folded = fold_state(self.intermediates, {v: 0 for v in VELOCITY[3:]})
        return AppliedDerived(
            self.definition,
            inter,
            self.potential.subs(folded),
            self.dissipation.subs(folded),
            tuple(f.subs(folded) for f in self.forces),
        )

    def in_state_symbols(self, expr: sp.Expr) -> sp.Expr:
        """`expr` in state symbols and parameters only (proofs): 1/|s| as 1/|s|."""
        return inline(self.intermediates, expr).replace(InverseOrZero, lambda x: 1 / x)


def _spring() -> tuple[Intermediates, sp.Expr, sp.Expr]:
    (l1x, l1y), l1_names = abstract_vector("l1")
    (l2x, l2y), l2_names = abstract_vector("l2")
    s = (BODY1.x + l1x - BODY2.x - l2x, BODY1.y + l1y - BODY2.y - l2y)
    names = {**l1_names, **l2_names}
    (sx, sx_t, _), (sy, sy_t, _) = vector_names("s")
    inter = translation() + vector_intermediates("l1", BODY1.rotate(PX1, PY1), orders=2)
    inter += vector_intermediates("l2", BODY2.rotate(PX2, PY2), orders=2)
    for order, pair in enumerate(((sx, sy), (sx_t, sy_t))):
        inter += [(pair[k], to_state(rename(sp.diff(s[k], t, order), names))) for k in range(2)]
        if order == 0:
            inter.append((S_LEN, Hypot(sx, sy)))
    inter.append((S_RATE, (sx * sx_t + sy * sy_t) / S_LEN))
    potential = STIFFNESS / 2 * (S_LEN - REST_LENGTH) ** 2
    return tuple(inter), potential, DAMPING / 2 * S_RATE**2


def _mutual_gravity() -> tuple[Intermediates, sp.Expr, sp.Expr]:
    inter = (*translation(), (DISTANCE, Hypot(DX, DY)))
    return inter, -G * M1 * M2 / DISTANCE, sp.Integer(0)


def _body_damping() -> tuple[Intermediates, sp.Expr, sp.Expr]:
    vx, vy, w = BODY1.velocity_symbols()
    return (), sp.Integer(0), (K_LIN * M1 * (vx**2 + vy**2) + K_ANG * I1 * w**2) / 2


def spring() -> AppliedDefinition:
    return AppliedDefinition(
        name="spring",
        title="Spring with a dashpot",
        bodies=2,
        world_end=True,
        parameters=(PX1, PY1, PX2, PY2, REST_LENGTH, STIFFNESS, DAMPING),
        potential="V = stiffness/2 (|s| - rest_length)^2,  s = p1 - p2 = X1 + R(th1) a1 - X2 - R(th2) a2",
        dissipation="R = damping/2 (d|s|/dt)^2",
        textbook="Hooke's force F = -(k (|s| - L) + c n.s') n on body 1 at p1, n = s/|s|, and -F"
        " on body 2 at p2; torques r_i x F about each centre",
        notes="A spring to the world: `force_static2` and `potential` with x2 = y2 = th2 = 0"
        " and anchor 2 in world coordinates. Where the anchors coincide the direction s/|s| is"
        " taken as 0.",
        derive=_spring,
    )


def mutual_gravity() -> AppliedDefinition:
    return AppliedDefinition(
        name="mutual_gravity",
        title="Mutual gravitation",
        bodies=2,
        world_end=False,
        parameters=(G, M1, M2),
        potential="V = -G m1 m2 / r,  r = |X1 - X2|",
        dissipation="R = 0",
        textbook="Newton's attraction G m1 m2 / r^2 along X2 - X1 on body 1 (and the opposite on"
        " body 2), no torque",
        notes="One pair of bodies: the runtime sums it over every pair of moving bodies.",
        derive=_mutual_gravity,
    )


def body_damping() -> AppliedDefinition:
    return AppliedDefinition(
        name="body_damping",
        title="Linear and angular damping of a body",
        bodies=1,
        world_end=False,
        parameters=(M1, I1, K_LIN, K_ANG),
        potential="V = 0",
        dissipation="R = (k_lin m1 (vx1^2 + vy1^2) + k_ang i1 w1^2)/2",
        textbook="force -k_lin m v and torque -k_ang I w",
        notes="One body (k_lin, k_ang in 1/s): v(t) = v0 exp(-k_lin t) when nothing else acts.",
        derive=_body_damping,
    )


ALL_APPLIED = {a().name: a for a in (spring, mutual_gravity, body_damping)}


def _guarded(expr: sp.Expr) -> sp.Expr:
    """`expr` with 1/|s| as the guarded s_inv."""
    return expr.replace(
        lambda p: p.is_Pow and p.base == S_LEN and p.exp.is_negative,
        lambda p: S_INV ** (-p.exp),
    )


def _named(inter: Intermediates, expr: sp.Expr) -> sp.Expr:
    """`expr` with each intermediate's value written as its name (a lever's r_y, a length)."""
    return _guarded(expr.xreplace({value: s for s, value in inter}))


def derive_applied(definition: AppliedDefinition) -> AppliedDerived:
    """Q_k = -dV/dq_k - dR/dq'_k by SymPy through the intermediates, exact for any state."""
    inter, potential, dissipation = definition.derive()
    forces = tuple(
        _named(
            inter,
            -total_derivative(inter, potential, q) - total_derivative(inter, dissipation, v),
        )
        for q, v in zip(definition.coordinates, definition.rates, strict=True)
    )
    symbols = [s for s, _ in inter]
    if S_LEN in symbols:  # the guarded 1/|s| right after |s|, and d|s|/dt written with it
        inter = tuple((s, _guarded(v) if s == S_RATE else v) for s, v in inter)
        k = symbols.index(S_LEN) + 1
        inter = (*inter[:k], (S_INV, InverseOrZero(S_LEN)), *inter[k:])
    return AppliedDerived(definition, inter, potential, dissipation, forces)
