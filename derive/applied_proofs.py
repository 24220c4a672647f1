"""Proofs of the applied forces (derive/applied.py) against the independent reference.

The reference (derive/reference.applied) writes each force in its textbook form -- Hooke's force
along the spring at the anchors with torques r x F, Newton's G m1 m2 / r^2, viscous -k m v -- and
V and R from their definitions along the explicit motion of both bodies; it shares no code with
the derivation. Proven exactly (derive/proofs.is_zero), for every state:

* each emitted generalized force equals the textbook form (and the spring's *_static2 with body
  2 at rest);
* at rest the forces are minus the gradient of the emitted V (so V is the energy they store);
* the power of the forces is -dV/dt - 2R with R the definition's: run.energy (kinetic + V) is
  conserved without dissipation and loses 2R per second with it.
"""

from __future__ import annotations

import sympy as sp

from derive import reference as ref
from derive.applied import AppliedDerived, InverseOrZero
from derive.proofs import RESTRICTIONS, Proof, all_zero, inline_scalars
from derive.reference import TAU, at_instant


def _along_motion(expr: sp.Expr) -> sp.Expr:
    """`expr` (state symbols) along the reference motion, as a function of tau."""
    path = {}
    for body in (ref.B1, ref.B2):
        i = body.i
        path.update({ref.sym(f"x{i}"): body.centre[0], ref.sym(f"y{i}"): body.centre[1]})
        path[ref.sym(f"th{i}")] = body.angle
    return expr.xreplace(path)


def _in_levers(a: AppliedDerived, expr: sp.Expr, levers: dict) -> sp.Expr:
    return inline_scalars(a, expr, levers).replace(InverseOrZero, lambda x: 1 / x)


def textbook(a: AppliedDerived) -> Proof:
    """For a spring in three steps: its levers L_i = R(th_i) a_i and their rates equal the
    reference's (as for the joints); its force on body 1 written in the levers equals Hooke's
    along an arbitrary path of the levers (no trigonometry: seconds, not minutes); and the
    other outputs are that force's torque L1 x F, its opposite -F and torque -(L2 x F) on body
    2, identically in the intermediates. The *_static2 forces equal the full ones with body 2
    at rest, which is a special state."""
    forces, _, _ = ref.applied(a.name, levers=a.name == "spring")
    if a.name == "spring":
        levers = ref.spring_levers()
        defined = dict(a.intermediates)
        held = all_zero((defined[s], v) for s, v in levers.items() if s in defined)
        held = held and all_zero(
            (_in_levers(a, f, levers), g) for f, g in zip(a.forces[:2], forces[:2], strict=True)
        )
        arms = [sp.Matrix([ref.sym(f"l{i}_x"), ref.sym(f"l{i}_y")]) for i in (1, 2)]
        on_bodies = ref.on_bodies(sp.Matrix(a.forces[:2]), *arms)
        held = held and all_zero(zip(a.forces, on_bodies, strict=True))
    else:
        pairs = zip(a.forces, forces, strict=True)
        held = all_zero((a.in_state_symbols(f), g) for f, g in pairs)
    what = ""
    if a.definition.world_end:
        still = RESTRICTIONS["static2"]
        held = held and all_zero(
            (a.static2.in_state_symbols(f2), a.in_state_symbols(f).xreplace(still))
            for f, f2 in zip(a.forces[:3], a.static2.forces[:3], strict=True)
        )
        what = " (and the *_static2 force on body 1 with body 2 at rest)"
    return Proof(
        f"{a.name}: the generalized forces Q = -dV/dq - dR/dq' equal the textbook form,"
        f" {a.definition.textbook}{what}, for every state",
        held,
    )


def gradient(a: AppliedDerived) -> Proof:
    """Q at zero velocity + dV/dq = 0 for the emitted V; and that V is the definition's."""
    _, potential, _ = ref.applied(a.name)
    ours = a.in_state_symbols(a.potential)
    at_rest = {v: 0 for v in ref.VELOCITY}
    pairs = [(ours, potential)]
    pairs += [
        (a.in_state_symbols(f).xreplace(at_rest), -sp.diff(ours, q))
        for f, q in zip(a.forces, a.definition.coordinates, strict=True)
    ]
    return Proof(
        f"{a.name}: the emitted potential is {a.definition.potential}, and at rest the forces are"
        " minus its gradient, -dV/dq",
        all_zero(pairs),
    )


def power(a: AppliedDerived) -> Proof:
    """Q.q' = -dV/dt - 2R along the reference motion, V the emitted potential, R the
    definition's."""
    _, _, dissipation = ref.applied(a.name)
    potential = a.in_state_symbols(a.potential)
    work = sum(
        (a.in_state_symbols(f) * v for f, v in zip(a.forces, a.definition.rates, strict=True)),
        sp.Integer(0),
    )
    change = at_instant(sp.diff(_along_motion(potential), TAU))
    return Proof(
        f"{a.name}: the power of the forces is -dV/dt - 2R with {a.definition.dissipation}: the"
        " energy (kinetic + V) is kept without dissipation and loses 2R per second with it",
        all_zero([(work, -change - 2 * dissipation)]),
    )


def applied_proofs(a: AppliedDerived) -> list[Proof]:
    return [textbook(a), gradient(a), power(a)]
