"""Impulses at impacts: the velocity jumps that leave no touching contact approaching.

Why: at the instant two bodies meet (located by runtime.step.events, so the gap is 0), their
velocities must jump. The jump uses the same A = J M^-1 J^T as the contact forces: d' = J v is
linear in the velocities, so normal impulses p change d' by exactly A p and the velocities by
M^-1 J^T p. This module works on one island of touching contacts at a time (its dense A and d');
runtime.step.classify decides which contacts take part and with which restitution.

Policy for several contacts (:func:`resolve`): waves of simultaneous impulses, then one inelastic
simultaneous pass.

1. A wave takes the contacts that approach faster than the resting speed *now* and solves them
   together, as the LCP A_WW p + (1 + e) d'_W >= 0, p >= 0, complementary (Newton's law on the
   velocities of that instant); the other touching contacts take no impulse in this wave.
2. The impulses change d' at the other touching contacts (A_{.W} p); those that now approach
   form the next wave. Waves repeat until nothing approaches faster than the resting speed
   (at most settings.MAX_WAVES).
3. A final simultaneous LCP with restitution 0 over the touching contacts, A p + d' >= 0,
   leaves none approaching (it catches slow approaches and waves that did not converge). It is
   one LCP over the island's touching contacts, warm-started with the approaching ones taking
   an impulse (growing that set one solve at a time instead cost ten solves in a landing pile).
   Each LCP goes to the compiled dense solver (runtime.solve.lcp_dense), whose first stage is
   the guess -- one Cholesky -- and pivoting from there if it misses.

So impacts at the same instant (a block landing flat on two corners, a ball meeting two balls at
once) are simultaneous, and an impulse travels through contacts that were merely touching one
contact at a time, which gives Newton's cradle: a purely simultaneous LCP over the whole row
(:func:`simultaneous`, kept for comparison) moves the struck row together instead of sending the
last disc off.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from runtime import settings
from runtime.compiled import njit
from runtime.solve import assembly, lcp


@dataclass(frozen=True)
class IslandImpact:
    """The outcome of :func:`resolve` for one island."""

    impulses: np.ndarray  # (K,) total normal impulse per contact
    gap_velocity: np.ndarray  # (K,) d' after the impact
    waves: int  # restitution waves used


@njit
def impulse_lcp(A, b, guess, p):
    """p >= 0 with A p + b >= 0, complementary, written to p, by the dense solver warm-started
    from ``guess`` (the contacts expected to take an impulse: for most impacts every one of
    them, as they are all approaching); False if it has no solution."""
    return assembly.dense_lcp(A, b, np.zeros(b.size, np.bool_), guess.copy(), p)


@njit
def _wave_problem(A, rate, restitution, wave):
    """The LCP of one wave (step 1 of the module docstring): A_WW and (1 + e) d'_W."""
    return np.ascontiguousarray(A[wave][:, wave]), (1.0 + restitution[wave]) * rate[wave]


@njit
def _apply_wave(A, wave, p, total, rate):
    """A wave's impulses added, and passed on to every touching contact's d' (step 2)."""
    total[wave] += p
    rate += A[:, wave] @ p


@njit
def _apply_final(A, p, total, rate):
    """The final plastic pass's impulses added, and d' after them (step 3)."""
    total += p
    rate += A @ p


@njit
def resolve_island(A, rate, restitution, resting_speed, creep_speed, total):
    """Impulses (added to ``total``) for the touching contacts of one island with
    effective-mass matrix A and rates ``rate`` (updated: d' after the impacts), by the policy
    of the module docstring. Returns the number of restitution waves, -1 if an impulse problem
    has no solution."""
    waves = 0
    while waves < settings.MAX_WAVES:
        wave = np.flatnonzero(rate < -resting_speed)
        if wave.size == 0:
            break
        waves += 1
        sub, b = _wave_problem(A, rate, restitution, wave)
        p = np.zeros(wave.size)
        if not impulse_lcp(sub, b, np.ones(wave.size, np.bool_), p):
            return -1
        _apply_wave(A, wave, p, total, rate)
    if not np.any(rate < -creep_speed):
        return waves
    p = np.zeros(rate.size)
    if not impulse_lcp(A, rate.copy(), rate < -creep_speed, p):
        return -1
    _apply_final(A, p, total, rate)
    return waves


def resolve(
    A: np.ndarray,
    gap_velocity: np.ndarray,
    restitution: np.ndarray,
    resting_speed: float,
    creep_speed: float,
) -> IslandImpact:
    """Impulses for the touching contacts of one island (:func:`resolve_island`)."""
    A = np.ascontiguousarray(A, dtype=float)
    restitution = np.asarray(restitution, dtype=float)
    rate = np.array(gap_velocity, dtype=float)
    total = np.zeros_like(rate)
    waves = resolve_island(A, rate, restitution, resting_speed, creep_speed, total)
    if waves < 0:  # the compiled dense solver gave up: the same waves by the general solver
        rate = np.array(gap_velocity, dtype=float)
        total = np.zeros_like(rate)
        waves = _resolve_general(A, rate, restitution, resting_speed, creep_speed, total)
    if waves < 0:
        raise lcp.ContactSolverError("the impulses of an impact have no solution", [])
    return IslandImpact(total, rate, waves)


def _resolve_general(A, rate, restitution, resting_speed, creep_speed, total) -> int:
    """:func:`resolve_island`, each LCP by runtime.solve.lcp.solve_warm: its sparse path and
    fallbacks for islands above settings.LCP_DENSE_MAX rows. Why: the compiled dense solver
    can give up on a large island with dependent rows that has a solution -- the final plastic
    pass of a landing 200-disc pile (213 rows, rank 203) at t = 0.749 s, which the sparse path
    solves to a residual of 6e-16."""
    waves = 0
    while waves < settings.MAX_WAVES:
        wave = np.flatnonzero(rate < -resting_speed)
        if wave.size == 0:
            break
        waves += 1
        try:
            p, _ = lcp.solve_warm(*_wave_problem(A, rate, restitution, wave))
        except lcp.ContactSolverError:
            return -1
        _apply_wave(A, wave, p, total, rate)
    if not np.any(rate < -creep_speed):
        return waves
    try:
        p, _ = lcp.solve_warm(A, rate.copy(), guess=rate < -creep_speed)
    except lcp.ContactSolverError:
        return -1
    _apply_final(A, p, total, rate)
    return waves


def simultaneous(
    A: np.ndarray, gap_velocity: np.ndarray, restitution: np.ndarray, resting_speed: float
) -> np.ndarray:
    """The purely simultaneous alternative (not used by the engine): one LCP over all touching
    contacts, A p + (1 + e) d'_- >= 0, restitution 0 below the resting speed. Impulses."""
    e = np.where(-np.asarray(gap_velocity) > resting_speed, restitution, 0.0)
    return lcp.solve(A, (1.0 + e) * np.asarray(gap_velocity))
