"""Kernel specs: for each case, the named functions the runtime calls and what each computes.

A spec is pure data (name, docstring, ordered arguments, intermediates, outputs); the emitter turns it
into NumPy code. This is the case -> functions table in docs/conventions.md.
"""

from __future__ import annotations

from dataclasses import dataclass

import sympy as sp

from derive.derivation import ACCELERATION, POSE, VELOCITY, Derivatives

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
        needed: set[sp.Symbol] = set().union(*(o.free_symbols for o in self.outputs))
        for s, value in reversed(self.intermediates):
            if s in needed:
                needed |= value.free_symbols
        return tuple((s, v) for s, v in self.intermediates if s in needed)

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
