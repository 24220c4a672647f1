"""Kernel specs: for each case, the named functions the runtime calls and what each computes.

A spec is pure data (name, docstring, ordered arguments, intermediates, outputs); the emitter turns it
into NumPy code. This is the case -> functions table in docs/conventions.md.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from derive.derivation import ACCELERATION, POSE, VELOCITY, Derivatives, needed
from derive.rows import Derived

_STATE_ORDER = (
    POSE[:3] + VELOCITY[:3] + ACCELERATION[:3] + POSE[3:] + VELOCITY[3:] + ACCELERATION[3:]
)


@dataclass(frozen=True)
class KernelSpec:
    """One generated function: returns `outputs` (a tuple if more than one) of `arguments`."""

    name: str
    summary: str
    formula: str
    intermediates: tuple[tuple[sp.Symbol, sp.Expr], ...]
    outputs: tuple[sp.Expr, ...]
    output_names: tuple[str, ...]

    def needed_intermediates(self) -> tuple[tuple[sp.Symbol, sp.Expr], ...]:
        """The intermediates the outputs use, directly or through each other, in order."""
        return needed(self.intermediates, self.outputs)

    def arguments(self, geometry: tuple[sp.Symbol, ...]) -> tuple[sp.Symbol, ...]:
        free: set[sp.Symbol] = set().union(*(o.free_symbols for o in self.outputs))
        for _, value in self.needed_intermediates():
            free |= value.free_symbols
        return tuple(s for s in _STATE_ORDER + geometry if s in free)


def kernel_specs(d: Derivatives) -> list[KernelSpec]:
    """The public functions of one case's module, full-state and body-2-static variants."""
    f = d.case.formulas
    jac_names = ("j1x", "j1y", "j1th", "j2x", "j2y", "j2th")
    jac_formula = (
        "(dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2) = the coefficients of the accelerations"
        f" in d''; body 1: (n, {d.case.lever1}1 x n), body 2: -(n, {d.case.lever2}2 x n)"
    )
    bias_formula = f"{f['gap_acceleration']}  with ax1 = ay1 = al1 = ax2 = ay2 = al2 = 0"
    s2 = d.static2
    static_note = "  [body 2 fixed: v2 = w2 = a2 = al2 = 0]"
    return [
        KernelSpec("gap", "Gap d (> 0 separated).", f["gap"], d.intermediates, (d.gap,), ("d",)),
        KernelSpec(
            "gap_velocity",
            "Exact d' for any state.",
            f["gap_velocity"],
            d.intermediates,
            (d.gap_velocity,),
            ("d1",),
        ),
        KernelSpec(
            "gap_acceleration",
            "Exact d'' for any state.",
            f["gap_acceleration"],
            d.intermediates,
            (d.gap_acceleration,),
            ("d2",),
        ),
        KernelSpec(
            "jacobian",
            "Jacobian row of the gap: the A-matrix lever terms.",
            jac_formula,
            d.intermediates,
            d.jacobian,
            jac_names,
        ),
        KernelSpec(
            "bias",
            "Velocity-dependent part of d'': the b-vector term.",
            bias_formula,
            d.bias.intermediates,
            (d.bias.gap_acceleration,),
            ("b",),
        ),
        KernelSpec(
            "gap_velocity_static2",
            "Exact d' with body 2 fixed.",
            f["gap_velocity"] + static_note,
            s2.intermediates,
            (s2.gap_velocity,),
            ("d1",),
        ),
        KernelSpec(
            "gap_acceleration_static2",
            "Exact d'' with body 2 fixed.",
            f["gap_acceleration"] + static_note,
            s2.intermediates,
            (s2.gap_acceleration,),
            ("d2",),
        ),
        KernelSpec(
            "jacobian_static2",
            "Body-1 Jacobian row with body 2 fixed.",
            "(dd/dx1, dd/dy1, dd/dth1) = (n, " + d.case.lever1 + "1 x n)",
            s2.intermediates,
            s2.jacobian[:3],
            jac_names[:3],
        ),
        KernelSpec(
            "bias_static2",
            "b-vector term with body 2 fixed.",
            bias_formula + static_note,
            s2.bias.intermediates,
            (s2.bias.gap_acceleration,),
            ("b",),
        ),
    ]


# ------------------------------------------------------------------------------------------
# rows beyond the normal: friction (one tangential row per contact) and joints (1 or 2 rows)
# ------------------------------------------------------------------------------------------

FORCE_NAMES = ("fx1", "fy1", "tau1", "fx2", "fy2", "tau2")
JACOBIAN_NAMES = ("j1x", "j1y", "j1th", "j2x", "j2y", "j2th")
STATIC_NOTE = "  [body 2 fixed: v2 = w2 = a2 = al2 = 0]"


def _row_spec(name, summary, formula, source: Derived, output: str, names) -> KernelSpec:
    return KernelSpec(name, summary, formula, source.intermediates, source.values[output], names)


def _jacobian_spec(name, summary, formula, source: Derived, row_names, per_body: int) -> KernelSpec:
    """The Jacobian rows flattened row by row: 6 entries each (3 with body 2 fixed)."""
    outputs = tuple(e for row in source.jacobian for e in row[:per_body])
    names = tuple(f"{j}_{r}" if r else j for r in row_names for j in JACOBIAN_NAMES[:per_body])
    return KernelSpec(name, summary, formula, source.intermediates, outputs, names)


def friction_specs(f: Derived, formulas: dict[str, str]) -> list[KernelSpec]:
    """The public functions of a case's friction module: v_t, d/dt v_t, J_t, b_t (+ static2)."""
    bias_formula = f"{formulas['tangent_acceleration']}  with every acceleration zero"
    specs = []
    for suffix, v, note, per_body in (("", f, "", 6), ("_static2", f.static2, STATIC_NOTE, 3)):
        specs += [
            _row_spec(
                "tangent_velocity" + suffix,
                "Tangential relative velocity v_t of the contact points (exact, any state).",
                formulas["tangent_velocity"] + note,
                v,
                "tangent_velocity",
                ("vt",),
            ),
            _row_spec(
                "tangent_acceleration" + suffix,
                "Exact d/dt v_t for any state.",
                formulas["tangent_acceleration"] + note,
                v,
                "tangent_acceleration",
                ("at",),
            ),
            _jacobian_spec(
                "tangent_jacobian" + suffix,
                "Tangential Jacobian row J_t: v_t = J_t . velocities, the A-matrix row of friction.",
                formulas["tangent_jacobian"] + note,
                v,
                ("",),
                per_body,
            ),
            _row_spec(
                "tangent_bias" + suffix,
                "Velocity-dependent part of d/dt v_t: the b-vector term of friction.",
                bias_formula + note,
                v.bias,
                "tangent_acceleration",
                ("bt",),
            ),
        ]
    return specs


def joint_specs(
    j: Derived, row_names: tuple[str, ...], formulas: dict[str, str]
) -> list[KernelSpec]:
    """The public functions of a joint module: d, d', d'', J, bias per row (+ static2)."""

    def names(stem: str) -> tuple[str, ...]:
        return tuple(f"{stem}_{r}" if r else stem for r in row_names)

    jac_formula = (
        "rows of (dd/dx1, dd/dy1, dd/dth1, dd/dx2, dd/dy2, dd/dth2)"
        " = the coefficients of the accelerations in d''"
    )
    bias_formula = f"{formulas['gap_acceleration']}  with every acceleration zero"
    specs = [
        _row_spec(
            "gap",
            "Constraint value d (0 when the joint holds).",
            formulas["gap"],
            j,
            "gap",
            names("d"),
        )
    ]
    for suffix, v, note, per_body in (("", j, "", 6), ("_static2", j.static2, STATIC_NOTE, 3)):
        specs += [
            _row_spec(
                "gap_velocity" + suffix,
                "Exact d' for any state.",
                formulas["gap_velocity"] + note,
                v,
                "gap_velocity",
                names("d1"),
            ),
            _row_spec(
                "gap_acceleration" + suffix,
                "Exact d'' for any state.",
                formulas["gap_acceleration"] + note,
                v,
                "gap_acceleration",
                names("d2"),
            ),
            _jacobian_spec(
                "jacobian" + suffix,
                "Jacobian rows of the joint: the A-matrix lever terms.",
                jac_formula + note,
                v,
                row_names,
                per_body,
            ),
            _row_spec(
                "bias" + suffix,
                "Velocity-dependent part of d'': the b-vector term.",
                bias_formula + note,
                v.bias,
                "gap_acceleration",
                names("b"),
            ),
        ]
    return specs


def applied_specs(a) -> list[KernelSpec]:
    """The public functions of an applied force's module (derive/applied.py): the generalized
    forces Q (+ body 2 at rest for a spring) and the potential V when there is one."""
    definition = a.definition
    per_body = 3 * definition.bodies
    rule = "Q = -dV/dq - dR/dq'"
    specs = [
        KernelSpec(
            "force",
            f"Generalized forces {rule}: force and torque on each body (N, N m).",
            f"{definition.potential},  {definition.dissipation}",
            a.intermediates,
            a.forces,
            FORCE_NAMES[:per_body],
        )
    ]
    if definition.world_end:
        specs.append(
            KernelSpec(
                "force_static2",
                f"{rule} on body 1 with body 2 at rest (the world, or a fixed body).",
                f"{definition.potential},  {definition.dissipation}" + STATIC_NOTE,
                a.static2.intermediates,
                a.static2.forces[:3],
                FORCE_NAMES[:3],
            )
        )
    if a.potential != 0:
        specs.append(
            KernelSpec(
                "potential",
                "Potential energy V (J): run.energy adds it.",
                definition.potential,
                a.intermediates,
                (a.potential,),
                ("V",),
            )
        )
    return specs
