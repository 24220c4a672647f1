"""The compiled rows of every contact case, dispatched by case id inside compiled stages.

Why one program for all four cases: a compiled stage (runtime.step.compiled_stages, runtime.step.
compiled_frame) evaluates the rows of contacts of every case a scene has. Taking only the scene's
cases' kernels as function arguments compiled a stage per combination of cases, but numba keys
such code by the argument functions' dispatcher objects, which differ in every process: it could
never be cached on disk, and every run compiled the stages afresh (about 20 s of CPU on this
2-core machine before the first step). Called as globals, the four cases' generated batch loops
(generated/compiled/) compile into the stages once per machine and load from the disk cache
after that. A case a scene cannot produce has no contacts, so its loop is never entered. The
NumPy kernels (the general path, the Python API) are still imported per scene: only the cases
it can produce.
"""

from __future__ import annotations

import numpy as np

import generated
from generated.compiled import circle_circle, circle_edge, vertex_circle, vertex_edge
from runtime.compiled import njit

if [generated.CASE_ID[c] for c in ("vertex_edge", "vertex_circle", "circle_edge", "circle_circle")] != [0, 1, 2, 3]:  # fmt: skip
    raise ImportError("generated.CASE_ID changed: runtime/solve/kernel_set.py dispatches by id")


@njit
def by_case(case):
    """The contacts of each case id (0-3), as index arrays: found once, used at every stage."""
    return (np.flatnonzero(case == 0), np.flatnonzero(case == 1), np.flatnonzero(case == 2),
            np.flatnonzero(case == 3))  # fmt: skip


@njit
def rows_by_case(q, v, members, body1, body2, geometry, static2, jac, bias):
    """Jacobian rows and biases of every contact (``members``: :func:`by_case`), each case by
    its generated batch_rows."""
    m0, m1, m2, m3 = members
    if m0.size:
        vertex_edge.batch_rows(q, v, body1, body2, geometry, static2, m0, jac, bias)
    if m1.size:
        vertex_circle.batch_rows(q, v, body1, body2, geometry, static2, m1, jac, bias)
    if m2.size:
        circle_edge.batch_rows(q, v, body1, body2, geometry, static2, m2, jac, bias)
    if m3.size:
        circle_circle.batch_rows(q, v, body1, body2, geometry, static2, m3, jac, bias)


@njit
def all_by_case(q, v, members, body1, body2, geometry, static2, gap, rate, jac, bias):
    """d, d', Jacobian rows and biases of every contact (``members``: :func:`by_case`), each
    case by its generated batch_all."""
    m0, m1, m2, m3 = members
    if m0.size:
        vertex_edge.batch_all(q, v, body1, body2, geometry, static2, m0, gap, rate, jac, bias)
    if m1.size:
        vertex_circle.batch_all(q, v, body1, body2, geometry, static2, m1, gap, rate, jac, bias)
    if m2.size:
        circle_edge.batch_all(q, v, body1, body2, geometry, static2, m2, gap, rate, jac, bias)
    if m3.size:
        circle_circle.batch_all(q, v, body1, body2, geometry, static2, m3, gap, rate, jac, bias)


@njit
def gaps_by_case(q, v, members, body1, body2, geometry, static2, gap, rate):
    """d and d' of every contact (``members``: :func:`by_case`), each case by its generated
    batch_gap and batch_gap_velocity: the same calls as runtime.solve.rows.RowEvaluator.
    gap_and_rate, so the same numbers."""
    m0, m1, m2, m3 = members
    if m0.size:
        vertex_edge.batch_gap(q, body1, body2, geometry, m0, gap)
        vertex_edge.batch_gap_velocity(q, v, body1, body2, geometry, static2, m0, rate)
    if m1.size:
        vertex_circle.batch_gap(q, body1, body2, geometry, m1, gap)
        vertex_circle.batch_gap_velocity(q, v, body1, body2, geometry, static2, m1, rate)
    if m2.size:
        circle_edge.batch_gap(q, body1, body2, geometry, m2, gap)
        circle_edge.batch_gap_velocity(q, v, body1, body2, geometry, static2, m2, rate)
    if m3.size:
        circle_circle.batch_gap(q, body1, body2, geometry, m3, gap)
        circle_circle.batch_gap_velocity(q, v, body1, body2, geometry, static2, m3, rate)


@njit
def candidate_gaps(poses, body1, body2, geometry, members, case_start, gap):
    """d of the contact finder's candidates (runtime.collide.finder: ``members`` grouped by case
    id, each case from ``case_start[id]``), each case by its generated batch_gap; returns how
    many were evaluated (fewer than the candidates: a case beyond the four, a finder's bug)."""
    s = case_start
    m0, m1, m2, m3 = (
        members[s[0] : s[1]],
        members[s[1] : s[2]],
        members[s[2] : s[3]],
        members[s[3] : s[4]],
    )
    if m0.size:
        vertex_edge.batch_gap(poses, body1, body2, geometry, m0, gap)
    if m1.size:
        vertex_circle.batch_gap(poses, body1, body2, geometry, m1, gap)
    if m2.size:
        circle_edge.batch_gap(poses, body1, body2, geometry, m2, gap)
    if m3.size:
        circle_circle.batch_gap(poses, body1, body2, geometry, m3, gap)
    return m0.size + m1.size + m2.size + m3.size
