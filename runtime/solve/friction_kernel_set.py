"""The compiled tangential (friction) rows of every contact case, dispatched by case id.

Why: as runtime.solve.kernel_set for the normal rows -- a compiled stage of a scene with friction
(runtime.step.compiled_friction) evaluates the tangential rows of contacts of every case it
has, and the four cases' generated batch loops (generated/compiled/<case>_friction.py), called
as globals, compile into it once per machine and load from the disk cache after that. A module
of its own: a scene without friction never imports it, nor the friction kernels.
"""

from __future__ import annotations

from generated.compiled import (
    circle_circle_friction,
    circle_edge_friction,
    vertex_circle_friction,
    vertex_edge_friction,
)
from runtime.compiled import njit
from runtime.solve import kernel_set  # noqa: F401  (checks the case ids the dispatch assumes)


@njit
def tangent_rows_by_case(q, v, members, body1, body2, geometry, static2, jac, bias):
    """Tangential Jacobian rows and biases of every contact (``members``:
    runtime.solve.kernel_set.by_case), each case by its generated batch_tangent_rows."""
    m0, m1, m2, m3 = members
    if m0.size:
        vertex_edge_friction.batch_tangent_rows(q, v, body1, body2, geometry, static2, m0, jac,
                                                bias)  # fmt: skip
    if m1.size:
        vertex_circle_friction.batch_tangent_rows(q, v, body1, body2, geometry, static2, m1, jac,
                                                  bias)  # fmt: skip
    if m2.size:
        circle_edge_friction.batch_tangent_rows(q, v, body1, body2, geometry, static2, m2, jac,
                                                bias)  # fmt: skip
    if m3.size:
        circle_circle_friction.batch_tangent_rows(q, v, body1, body2, geometry, static2, m3, jac,
                                                  bias)  # fmt: skip


@njit
def tangent_velocity_by_case(q, v, members, body1, body2, geometry, static2, out):
    """v_t of every contact (``members``: runtime.solve.kernel_set.by_case)."""
    m0, m1, m2, m3 = members
    if m0.size:
        vertex_edge_friction.batch_tangent_velocity(q, v, body1, body2, geometry, static2, m0, out)
    if m1.size:
        vertex_circle_friction.batch_tangent_velocity(q, v, body1, body2, geometry, static2, m1,
                                                      out)  # fmt: skip
    if m2.size:
        circle_edge_friction.batch_tangent_velocity(q, v, body1, body2, geometry, static2, m2, out)
    if m3.size:
        circle_circle_friction.batch_tangent_velocity(q, v, body1, body2, geometry, static2, m3,
                                                      out)  # fmt: skip
