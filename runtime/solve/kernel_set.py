"""The compiled row kernels of a scene's contact cases, as arguments for compiled stages.

Why: a compiled stage (runtime.step.compiled_stages) evaluates the rows of contacts of every
case a scene has; it takes the four cases' batch loops as arguments, so only the kernels of the
cases the scene can produce are imported (model only what a scene needs) and a case it cannot
produce is a stub that is never called. numba compiles the stage once for each combination
of cases and keeps it in its cache.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

import generated
from runtime.compiled import njit
from runtime.solve.rows import load_compiled_cases


@njit
def no_rows(poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out):
    """The rows of a case the scene cannot produce: never asked for (members is empty)."""
    return


@njit
def no_all(poses, velocities, body1, body2, geometry, static2, members, gap_out, rate_out,
           jacobian_out, bias_out):  # fmt: skip
    """All rows of a case the scene cannot produce: never asked for (members is empty)."""
    return


def _kernels(cases: Iterable[str], name: str, stub) -> tuple:
    modules = load_compiled_cases(cases)
    return tuple(
        getattr(modules[case], name) if case in modules else stub
        for case in sorted(generated.CASE_ID.values())
    )


def row_kernels(cases: Iterable[str]) -> tuple:
    """(batch_rows of case id 0, 1, 2, 3): the Jacobian rows and biases, the generated loop of
    each case of ``cases``, the stub for the others."""
    return _kernels(cases, "batch_rows", no_rows)


def frame_kernels(cases: Iterable[str]) -> tuple:
    """(batch_all of case id 0, 1, 2, 3): gaps, rates, Jacobian rows and biases."""
    return _kernels(cases, "batch_all", no_all)


@njit
def rows_by_case(k0, k1, k2, k3, q, v, case, body1, body2, geometry, static2, jac, bias):
    """Jacobian rows and biases of every contact, each case by its batch_rows (row_kernels)."""
    members = np.flatnonzero(case == 0)
    if members.size:
        k0(q, v, body1, body2, geometry, static2, members, jac, bias)
    members = np.flatnonzero(case == 1)
    if members.size:
        k1(q, v, body1, body2, geometry, static2, members, jac, bias)
    members = np.flatnonzero(case == 2)
    if members.size:
        k2(q, v, body1, body2, geometry, static2, members, jac, bias)
    members = np.flatnonzero(case == 3)
    if members.size:
        k3(q, v, body1, body2, geometry, static2, members, jac, bias)


@njit
def all_by_case(a0, a1, a2, a3, q, v, case, body1, body2, geometry, static2, gap, rate, jac, bias):
    """d, d', Jacobian rows and biases of every contact, each case by its batch_all."""
    members = np.flatnonzero(case == 0)
    if members.size:
        a0(q, v, body1, body2, geometry, static2, members, gap, rate, jac, bias)
    members = np.flatnonzero(case == 1)
    if members.size:
        a1(q, v, body1, body2, geometry, static2, members, gap, rate, jac, bias)
    members = np.flatnonzero(case == 2)
    if members.size:
        a2(q, v, body1, body2, geometry, static2, members, gap, rate, jac, bias)
    members = np.flatnonzero(case == 3)
    if members.size:
        a3(q, v, body1, body2, geometry, static2, members, gap, rate, jac, bias)
