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


def _in_levers(a: AppliedDerived, expr: sp.Expr, levers) -> sp.Expr:
    return inline_scalars(a, expr, levers).replace(InverseOrZero, lambda x: 1 / x)


def textbook(a: AppliedDerived) -> Proof:
    """In two steps for a spring (as for the joints): its levers L_i = R(th_i) a_i and their
    rates equal the reference's, and the forces written in the levers equal the textbook form
    along an arbitrary path of the levers (no trigonometry: seconds, not minutes)."""
    variants = {"full": a}
    if a.definition.bodies == 2 and a.dissipation != 0:
        variants["static2"] = a.static2
    held = True
    for variant, av in variants.items():
        still = RESTRICTIONS[variant]
        levers = {}
        if a.name == "spring":
            levers = {s: v.xreplace(still) for s, v in ref.spring_levers().items()}
        defined = dict(av.intermediates)
        held &= all_zero((defined[s], v) for s, v in levers.items() if s in defined)
        folded = {s: v for s, v in levers.items() if s not in defined}
        forces, _, _ = ref.applied(a.name, levers=bool(levers))
        count = 3 if variant == "static2" else len(forces)
        held &= all_zero(
            (_in_levers(av, f, levers), g.xreplace(still).xreplace(folded))
            for f, g in zip(av.forces[:count], forces[:count], strict=True)
        )
    what = " (and the *_static2 force on body 1 with body 2 at rest)" if len(variants) > 1 else ""
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
