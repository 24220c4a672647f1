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


_FEATURE2 = {"edge": ("ex2", "ey2"), "circle": ("cx2", "cy2")}


@cache
def geometry(case: str, levers: bool = False) -> Geometry:
    """The note's definitions: straight edge n = R(th2) n2, d = n.v - r1 (section 2 and 4);
    circular edge n = sigma v/|v|, d = sigma |v| - r2 - r1 (eq. 5-6, section 5), sigma = sign(r2).

    levers: the features are X_i(t) + L_i(t) with the levers L_i an arbitrary path of named
    vectors (l1_x, l1_x_t, ...) in place of R(th_i(t)) f_i (`lever_values` gives those), so the
    expression holds no trigonometry of the body angles."""
    first, second = case.split("_")
    f1, f2 = features(case, levers)
    r1 = sym("r1") if first == "circle" else sp.Integer(0)
    v = f1 - f2
    if second == "edge":
        n = B2.turn(sym("nx2"), sym("ny2"))
        return Geometry(v, n, r1, "d = n.v - r1, n = R(th2) n2" if r1 else "d = n.v, n = R(th2) n2")
    sigma = sp.sign(sym("r2"))
    n = sigma * v / sp.sqrt(dot(v, v))
    definition = "d = sigma |v| - r2" + (" - r1" if r1 else "") + ", sigma = sign(r2)"
    return Geometry(v, n, r1 + sym("r2"), definition)


def features(case: str, levers: bool = False) -> tuple[sp.Matrix, sp.Matrix]:
    """Body 1's feature point (vertex or circle centre) and body 2's (edge point or centre) along
    the motion: X_i + R(th_i) f_i, or X_i + L_i with L_i an arbitrary path (levers)."""
    if levers:
        return B1.centre + vector_path("l1"), B2.centre + vector_path("l2")
    first, second = case.split("_")
    return B1.point(*map(sym, _FEATURE1[first])), B2.point(*map(sym, _FEATURE2[second]))


def lever_values(name: str, orders: int = 2) -> dict[sp.Symbol, sp.Expr]:
    """The levers L_i = R(th_i) f_i to the features (a contact case) or anchors (a joint) and
    their rates at the instant, keyed by the names of the lever paths (l1_x, l1_x_t, ...)."""
    first, second = name.split("_")
    if second == "joint":
        points = (("px1", "py1"), ("px2", "py2"))
    else:
        points = (_FEATURE1[first], _FEATURE2[second])
    out = {}
    for body, point in zip((B1, B2), points, strict=True):
        lever = body.turn(*map(sym, point))
        for order in range(orders):
            value = at_instant(lever, order)
            out.update({_named(f"l{body.i}", c, order): value[k] for k, c in enumerate("xy")})
    return out


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


# ------------------------------------------------------------------------------------------
# friction: the contact points' tangential relative velocity
# ------------------------------------------------------------------------------------------

H = sp.Symbol("h", real=True)  # a short time after tau, to follow a material point


def material_velocity(body: Motion, p: sp.Matrix) -> sp.Matrix:
    """Velocity of the material point of `body` at the world point p at time tau: that point,
    carried rigidly with the body from tau to tau + h, differentiated in h at h = 0."""
    later = Motion(body.i)
    turn = later.angle.subs(TAU, TAU + H) - body.angle
    c, s = sp.cos(turn), sp.sin(turn)
    carried = later.centre.subs(TAU, TAU + H) + sp.Matrix([[c, -s], [s, c]]) * (p - body.centre)
    return sp.diff(carried, H).subs(H, 0)


OMEGA_N = sym("omega_n")  # the rate of turn of an arbitrary unit normal (form "unit normal")
FORMS = ("bodies", "levers", "unit normal")


def unit_normal_path() -> sp.Matrix:
    """An arbitrary unit vector along the motion, to first order: angle beta + omega_n t."""
    angle = sym("beta") + OMEGA_N * TAU
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


@cache
def contact_frame(case: str, form: str) -> tuple[sp.Matrix, sp.Matrix, sp.Matrix]:
    """(n, p1, p2) along the motion: p1 = f1 - r1 n (body 1's feature, or its circle's point
    facing body 2) and p2 = p1 - d n with d = n.v - offset (body 2's edge point on the same
    normal). Forms: "bodies" (the features R(th_i) f_i), "levers" (the levers an arbitrary path,
    see `geometry`), "unit normal" (levers, and n any unit vector in place of the case's)."""
    g = geometry(case, levers=form != "bodies")
    n = unit_normal_path() if form == "unit normal" else g.n
    radius1 = sym("r1") if case.startswith("circle") else 0
    p1 = features(case, levers=form != "bodies")[0] - radius1 * n
    return n, p1, p1 - (dot(n, g.v) - g.offset) * n


def tangent(case: str, form: str) -> sp.Matrix:
    """t = n turned by +90 degrees, along the motion."""
    n = contact_frame(case, form)[0]
    return sp.Matrix([-n[1], n[0]])


@cache
def tangent_velocity(case: str, form: str) -> tuple[sp.Expr, sp.Expr]:
    """v_t = (u1(p1) - u2(p2)).t and d/dt v_t at the instant."""
    _, p1, p2 = contact_frame(case, form)
    vt = dot(material_velocity(B1, p1) - material_velocity(B2, p2), tangent(case, form))
    return at_instant(vt), at_instant(vt, 1)


def tangential_displacement_gradient(case: str, form: str) -> tuple[sp.Expr, ...]:
    """d/dq of t.(P1 - P2) where P_i are the material points at p1, p2 displaced with their
    bodies by (dx_i, dy_i, dth_i) and t is held: the tangential row of the displacement."""
    _, p1, p2 = (at_instant(p) for p in contact_frame(case, form))
    t0 = at_instant(tangent(case, form))
    shifts = [sym(f"delta_{k}") for k in range(6)]

    def displaced(p, body: Motion, k: int) -> sp.Matrix:
        c, s = sp.cos(shifts[k + 2]), sp.sin(shifts[k + 2])
        lever = p - at_instant(body.centre)
        return p + sp.Matrix(shifts[k : k + 2]) + (sp.Matrix([[c, -s], [s, c]]) - sp.eye(2)) * lever

    slip = dot(t0, displaced(p1, B1, 0) - displaced(p2, B2, 3))
    return tuple(sp.diff(slip, q).subs({q: 0 for q in shifts}) for q in shifts)


# ------------------------------------------------------------------------------------------
# joints: anchors of both bodies held together (pin) or at a distance (distance joint)
# ------------------------------------------------------------------------------------------


def joint_separation(levers: bool = False) -> sp.Matrix:
    """s = p1 - p2, the anchors' separation along the motion (levers: X_i + L_i with the levers
    L_i an arbitrary path, see `lever_values`)."""
    if levers:
        return B1.centre + vector_path("l1") - B2.centre - vector_path("l2")
    return B1.point(sym("px1"), sym("py1")) - B2.point(sym("px2"), sym("py2"))


@cache
def joint_rows(joint: str, levers: bool = False) -> tuple[sp.Expr, ...]:
    """The constraint of each row along the motion: pin (s_x, s_y), distance |s| - length."""
    s = joint_separation(levers)
    if joint == "pin_joint":
        return (s[0], s[1])
    return (sp.sqrt(dot(s, s)) - sym("length"),)


# ------------------------------------------------------------------------------------------
# applied forces: the textbook forms (Hooke, Newton, viscous damping) and V, R by definition
# ------------------------------------------------------------------------------------------


def on_bodies(force: sp.Matrix, r1: sp.Matrix, r2: sp.Matrix) -> tuple[sp.Expr, ...]:
    """A force on body 1 at lever r1 and its opposite on body 2 at lever r2, with torques r x F."""
    return (force[0], force[1], cross(r1, force), -force[0], -force[1], -cross(r2, force))


@cache
def applied(name: str, levers: bool = False) -> tuple[tuple[sp.Expr, ...], sp.Expr, sp.Expr]:
    """(force and torque on each body, V, R) of an applied force at the instant, in state
    symbols: a spring's Hooke force -(k (|s| - L) + c n.s') n along n = s/|s| at the anchors;
    Newton's G m1 m2 / r^2 between the centres; -k_lin m v and -k_ang I w of a damped body.

    levers: a spring's anchors are X_i + L_i with the levers L_i an arbitrary path (l1_x, l1_x_t,
    ...; `spring_levers` gives their values), so the forces hold no trigonometry."""
    if name == "spring":
        if levers:
            p1, p2 = B1.centre + vector_path("l1"), B2.centre + vector_path("l2")
        else:
            p1, p2 = B1.point(sym("px1"), sym("py1")), B2.point(sym("px2"), sym("py2"))
        s = p1 - p2
        length = sp.sqrt(dot(s, s))
        rate = at_instant(sp.diff(length, TAU))
        n = at_instant(s / length)
        stretch = at_instant(length) - sym("rest_length")
        force = -(sym("stiffness") * stretch + sym("damping") * dot(n, at_instant(s, 1))) * n
        arms = (at_instant(p1 - B1.centre), at_instant(p2 - B2.centre))
        potential = sym("stiffness") / 2 * stretch**2
        return on_bodies(force, *arms), potential, sym("damping") / 2 * rate**2
    if name == "mutual_gravity":
        apart = at_instant(B2.centre - B1.centre)
        r = sp.sqrt(dot(apart, apart))
        strength = sym("G") * sym("m1") * sym("m2")
        force = strength / r**2 * apart / r
        return on_bodies(force, sp.zeros(2, 1), sp.zeros(2, 1)), -strength / r, sp.Integer(0)
    if name == "body_damping":
        vx, vy, w = VELOCITY[:3]
        k_lin, k_ang, m, inertia = sym("k_lin"), sym("k_ang"), sym("m1"), sym("i1")
        dissipation = (k_lin * m * (vx**2 + vy**2) + k_ang * inertia * w**2) / 2
        return (-k_lin * m * vx, -k_lin * m * vy, -k_ang * inertia * w), sp.Integer(0), dissipation
    raise ValueError(f"no reference for applied force {name!r}")


def spring_levers() -> dict[sp.Symbol, sp.Expr]:
    """A spring's levers L_i = R(th_i) a_i to its anchors and their rates at the instant."""
    out = {}
    for body in (B1, B2):
        lever = body.turn(sym(f"px{body.i}"), sym(f"py{body.i}"))
        for order in range(2):
            value = at_instant(lever, order)
            out.update({_named(f"l{body.i}", c, order): value[k] for k, c in enumerate("xy")})
    return out
