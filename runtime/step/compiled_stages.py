"""An integrator step with its contact forces, in one compiled call.

Why: a step of a small island is a few microseconds of arithmetic (kernel rows, a small A, a
Cholesky with the warm-start guess, the RK4 update), and done stage by stage from Python it costs
tens of microseconds of calls; the trial step and every trial time of locating an impact are
such steps. This is the same computation as runtime.step.integrators with the rhs of
runtime.solve.forces -- the same formulas in the same order -- for islands whose warm-start
guess holds and that are at most settings.DENSE_ISLAND contacts. It reports False otherwise
(a guess failed, a large island, a non-finite term), and the caller does the step the general
way (the pivoting solver, the error messages).

Methods: 0 Euler, 1 midpoint, 2 RK4 (runtime.step.integrators.FIXED_STEP's order).
"""

from __future__ import annotations

import numpy as np

from runtime.compiled import njit
from runtime.solve import assembly
from runtime.solve.kernel_set import by_case, rows_by_case

METHOD_ID = {"euler": 0, "midpoint": 1, "rk4": 2}


@njit
def finite(a):
    """Whether every entry of ``a`` (1-d or 2-d, C-contiguous) is finite (no array made)."""
    for x in a.ravel():
        if not np.isfinite(x):
            return False
    return True


@njit
def accelerations(
    q, v, members, body1, body2, geometry, static2, offsets, guess,
    inv_mass, fixed, free_acc, tol, limit, acc, forces, rates, jac, bias,
):  # fmt: skip
    """acc (n, 3) under the forces of the resting contacts (grouped by island, ``offsets``;
    ``members``: kernel_set.by_case), solved with the guess; False if an island needs the
    general path. ``forces``, ``rates``, ``jac``, ``bias``: scratch, written."""
    m = body1.size
    acc[:, :] = free_acc
    if m == 0:
        return True
    rows_by_case(q, v, members, body1, body2, geometry, static2, jac, bias)
    if not (finite(jac) and finite(bias)):
        return False
    ok = np.zeros(offsets.size - 1, np.bool_)
    assembly.solve_small_islands(
        jac, body1, body2, bias, inv_mass, fixed, free_acc, offsets, guess, tol, limit,
        forces, rates, ok,
    )  # fmt: skip
    if not np.all(ok):
        return False
    assembly.add_forces(jac, body1, body2, inv_mass, forces, acc)
    return True


@njit
def lift_state(
    q, v, case, body1, body2, geometry, static2, offsets, guess, inv_mass, fixed, free_acc, tol,
    limit, forces, ddot, diagonal,
):  # fmt: skip
    """The resting contacts' forces, d'' and A_kk (their own inverse effective mass) at (q, v),
    written to ``forces``, ``ddot``, ``diagonal`` (runtime.step.lift_events); False where an
    island needs the general path. ``guess``: as :func:`accelerations`', updated."""
    m = case.size
    rates, jac, bias = np.empty(m), np.empty((m, 6)), np.empty(m)
    acc = np.empty_like(free_acc)
    if not accelerations(
        q, v, by_case(case), body1, body2, geometry, static2, offsets, guess, inv_mass, fixed,
        free_acc, tol, limit, acc, forces, rates, jac, bias,
    ):  # fmt: skip
        return False
    for k in range(m):
        i, j = body1[k], body2[k]
        rate, own = bias[k], 0.0
        for c in range(3):
            rate += jac[k, c] * acc[i, c] + jac[k, 3 + c] * acc[j, c]
            own += jac[k, c] ** 2 * inv_mass[i, c] + jac[k, 3 + c] ** 2 * inv_mass[j, c]
        ddot[k], diagonal[k] = rate, own
    return True


@njit
def lifted(
    q1, v1, case, body1, body2, geometry, static2, offsets, guess, inv_mass, fixed, free_acc,
    tol, limit, pressing, h, speed,
):  # fmt: skip
    """Whether a contact pressing at the trial's start (``pressing``: its force there > 0)
    carries no force at the trial's end (q1, v1) and moves apart there with d'' h > ``speed``
    (runtime.step.lift_events); True where unsure (an island the compiled solve declines).
    ``guess``: scratch, written."""
    m = case.size
    if m == 0 or not np.any(pressing):
        return False
    forces, ddot, diagonal = np.empty(m), np.empty(m), np.empty(m)
    if not lift_state(
        q1, v1, case, body1, body2, geometry, static2, offsets, guess, inv_mass, fixed,
        free_acc, tol, limit, forces, ddot, diagonal,
    ):  # fmt: skip
        return True
    for k in range(m):
        if pressing[k] and forces[k] <= 0.0 and ddot[k] * h > speed:
            return True
    return False


@njit
def stage(q0, v0, dq, dv, h, q, v):
    """(q, v) = (q0 + h dq, v0 + h dv), in place: array expressions would make a temporary of
    every operation (with 10,000 copies, a quarter of the step went into making them)."""
    for i in range(q0.shape[0]):
        for c in range(3):
            q[i, c] = q0[i, c] + h * dq[i, c]
            v[i, c] = v0[i, c] + h * dv[i, c]


@njit
def step(
    method, q0, v0, h, a0, case, body1, body2, geometry, static2, offsets,
    guess, inv_mass, fixed, free_acc, tol, limit, q_out, v_out,
):  # fmt: skip
    """(q_out, v_out) = one step of length h from (q0, v0) with first-stage accelerations a0;
    False if a stage needs the general path."""
    if method == 0:
        stage(q0, v0, v0, a0, h, q_out, v_out)
        return True
    m = case.size
    scratch = (np.empty(m), np.empty(m), np.empty((m, 6)), np.empty(m))
    args = (by_case(case), body1, body2, geometry, static2, offsets, guess, inv_mass, fixed,
            free_acc, tol, limit)  # fmt: skip
    half = 0.5 * h
    q = np.empty_like(q0)
    v2, a2 = np.empty_like(v0), np.empty_like(a0)
    stage(q0, v0, v0, a0, half, q, v2)
    if not accelerations(q, v2, *args, a2, *scratch):
        return False
    if method == 1:
        stage(q0, v0, v2, a2, h, q_out, v_out)
        return True
    v3, a3 = np.empty_like(v0), np.empty_like(a0)
    stage(q0, v0, v2, a2, half, q, v3)
    if not accelerations(q, v3, *args, a3, *scratch):
        return False
    v4, a4 = np.empty_like(v0), np.empty_like(a0)
    stage(q0, v0, v3, a3, h, q, v4)
    if not accelerations(q, v4, *args, a4, *scratch):
        return False
    rk4_sum(q0, v0, a0, v2, a2, v3, a3, v4, a4, h, q_out, v_out)
    return True


@njit
def rk4_sum(q0, v0, a0, v2, a2, v3, a3, v4, a4, h, q_out, v_out):
    """RK4's end state from its four stages' velocities and accelerations, in place."""
    sixth = h / 6.0
    for i in range(q0.shape[0]):
        for c in range(3):
            q_out[i, c] = q0[i, c] + sixth * (v0[i, c] + 2.0 * (v2[i, c] + v3[i, c]) + v4[i, c])
            v_out[i, c] = v0[i, c] + sixth * (a0[i, c] + 2.0 * (a2[i, c] + a3[i, c]) + a4[i, c])
