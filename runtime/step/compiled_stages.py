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
from runtime.solve.kernel_set import rows_by_case

METHOD_ID = {"euler": 0, "midpoint": 1, "rk4": 2}

# Not cached on disk: these take the kernels as function arguments, and numba keys their cache
# entries by the kernels' dispatcher objects, which differ in every process. So no process ever
# found another's entry (each compiled afresh and appended one more: the index grew by ~400 KB a
# run), and a process re-saving the index re-pickled the earlier entries, whose dispatchers it
# no longer had once the garbage collector ran: `ReferenceError: underlying object has vanished`,
# a traceback from `simulate` on a valid scene (found by bench/soak.py's interrupted writes).
UNCACHED = {"cache": False}


@njit(**UNCACHED)
def accelerations(
    k0, k1, k2, k3, q, v, case, body1, body2, geometry, static2, offsets, guess,
    inv_mass, fixed, free_acc, tol, limit, acc, forces, rates,
):  # fmt: skip
    """acc (n, 3) under the forces of the resting contacts (grouped by island, ``offsets``),
    solved with the guess; False if an island needs the general path."""
    m = case.size
    acc[:, :] = free_acc
    if m == 0:
        return True
    jac = np.zeros((m, 6))
    bias = np.zeros(m)
    rows_by_case(k0, k1, k2, k3, q, v, case, body1, body2, geometry, static2, jac, bias)
    if not (np.all(np.isfinite(jac)) and np.all(np.isfinite(bias))):
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


@njit(**UNCACHED)
def step(
    k0, k1, k2, k3, method, q0, v0, h, a0, case, body1, body2, geometry, static2, offsets,
    guess, inv_mass, fixed, free_acc, tol, limit, q_out, v_out,
):  # fmt: skip
    """(q_out, v_out) = one step of length h from (q0, v0) with first-stage accelerations a0;
    False if a stage needs the general path."""
    m = case.size
    forces, rates = np.empty(m), np.empty(m)
    args = (case, body1, body2, geometry, static2, offsets, guess, inv_mass, fixed, free_acc,
            tol, limit)  # fmt: skip
    if method == 0:
        q_out[:, :] = q0 + h * v0
        v_out[:, :] = v0 + h * a0
        return True
    half = 0.5 * h
    a2 = np.empty_like(a0)
    v2 = v0 + half * a0
    if not accelerations(k0, k1, k2, k3, q0 + half * v0, v2, *args, a2, forces, rates):
        return False
    if method == 1:
        q_out[:, :] = q0 + h * v2
        v_out[:, :] = v0 + h * a2
        return True
    a3 = np.empty_like(a0)
    v3 = v0 + half * a2
    if not accelerations(k0, k1, k2, k3, q0 + half * v2, v3, *args, a3, forces, rates):
        return False
    a4 = np.empty_like(a0)
    v4 = v0 + h * a3
    if not accelerations(k0, k1, k2, k3, q0 + h * v3, v4, *args, a4, forces, rates):
        return False
    sixth = h / 6.0
    q_out[:, :] = q0 + sixth * (v0 + 2.0 * (v2 + v3) + v4)
    v_out[:, :] = v0 + sixth * (a0 + 2.0 * (a2 + a3) + a4)
    return True
