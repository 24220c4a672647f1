"""Constraint rows beyond a contact's normal (friction, joints): named outputs over intermediates.

A contact case has one row (the gap d, derive/derivation.py). A tangential (friction) row is a
velocity-level quantity v_t with its rate, and a pin joint has two rows (x and y of a separation).
`Derived` holds any of these the same way: the kernel outputs, one expression per row, written in
named intermediates over the state symbols; the output that is linear in the accelerations gives
the Jacobian rows (its coefficients) and the bias (the rest).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import sympy as sp

from derive.derivation import (
    ACCELERATION,
    BODY2_MOTION,
    Intermediates,
    fold_state,
    inline,
    total_derivative,
)


@dataclass(frozen=True, eq=False)
class Derived:
    """Kernel outputs of a set of rows: values[output] has one expression per row.

    `acceleration` names the output that is linear in the accelerations (d'' of a joint,
    d/dt v_t of a friction row): its coefficients form the Jacobian rows.
    """

    name: str
    intermediates: Intermediates
    values: dict[str, tuple[sp.Expr, ...]]
    acceleration: str

    @property
    def rows(self) -> int:
        return len(self.values[self.acceleration])

    @cached_property
    def jacobian(self) -> tuple[tuple[sp.Expr, ...], ...]:
        """Per row, the coefficients of (ax1, ay1, al1, ax2, ay2, al2) in the acceleration output."""
        return tuple(
            tuple(total_derivative(self.intermediates, e, a) for a in ACCELERATION)
            for e in self.values[self.acceleration]
        )

    def with_state(self, values: dict[sp.Symbol, sp.Expr]) -> Derived:
        """The same outputs with some state symbols fixed (constant intermediates folded)."""
        inter, folded = fold_state(self.intermediates, values)
        outputs = {k: tuple(e.subs(folded) for e in v) for k, v in self.values.items()}
        return Derived(self.name, inter, outputs, self.acceleration)

    @cached_property
    def bias(self) -> Derived:
        """Every acceleration zero: the acceleration output is the b term."""
        return self.with_state({a: 0 for a in ACCELERATION})

    @cached_property
    def static2(self) -> Derived:
        """Body 2 fixed: its velocity and acceleration are zero."""
        return self.with_state({m: 0 for m in BODY2_MOTION})

    def in_state_symbols(self, expr: sp.Expr) -> sp.Expr:
        """`expr` with every intermediate replaced by its definition (proofs, lambdify)."""
        return inline(self.intermediates, expr)
