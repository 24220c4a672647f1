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
   solved over the approaching contacts, grown by those its impulses make approach until none
   outside approaches (up to the creep speed): a solution of the LCP over all of them, found on
   a smaller matrix. Each LCP is first tried with every contact in it taking an impulse (one
   Cholesky), and solved by pivoting (runtime.solve.lcp) if that fails.

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
from runtime.solve import assembly, lcp


@dataclass(frozen=True)
class IslandImpact:
    """The outcome of :func:`resolve` for one island."""

    impulses: np.ndarray  # (K,) total normal impulse per contact
    gap_velocity: np.ndarray  # (K,) d' after the impact
    waves: int  # restitution waves used
    inelastic_pass: bool  # whether the final plastic pass changed anything


def resolve(
    A: np.ndarray,
    gap_velocity: np.ndarray,
    restitution: np.ndarray,
    resting_speed: float,
    creep_speed: float,
    max_waves: int = settings.MAX_WAVES,
) -> IslandImpact:
    """Impulses for the touching contacts of one island with effective-mass matrix ``A`` and
    rates ``gap_velocity`` (the policy of the module docstring)."""
    dv = np.array(gap_velocity, dtype=float)
    e = np.asarray(restitution, dtype=float)
    total = np.zeros_like(dv)
    waves = 0
    while waves < max_waves:
        wave = np.flatnonzero(dv < -resting_speed)
        if wave.size == 0:
            break
        waves += 1
        p = impulse_lcp(A[np.ix_(wave, wave)], (1.0 + e[wave]) * dv[wave])
        total[wave] += p
        dv += A[:, wave] @ p
    plastic = bool(np.any(dv < -creep_speed))
    if plastic:  # over the approaching contacts and those their impulses make approach
        chosen = dv < -creep_speed
        while True:
            idx = np.flatnonzero(chosen)
            p = impulse_lcp(A[np.ix_(idx, idx)], dv[idx])
            after = dv + A[:, idx] @ p
            more = (after < -creep_speed) & ~chosen
            if not more.any():
                break
            chosen |= more
        total[idx] += p
        dv = after
    return IslandImpact(total, dv, waves, plastic)


def impulse_lcp(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """p >= 0 with A p + b >= 0, complementary: first guessing that every contact takes an
    impulse (true for most impacts: they are all approaching), else by pivoting."""
    p = np.zeros(b.size)
    every = np.ones(b.size, dtype=bool)
    if assembly.solve_with_guess(np.ascontiguousarray(A), b, b.size, every, settings.LCP_TOL, p):
        return p
    return lcp.solve(A, b)


def simultaneous(
    A: np.ndarray, gap_velocity: np.ndarray, restitution: np.ndarray, resting_speed: float
) -> np.ndarray:
    """The purely simultaneous alternative (not used by the engine): one LCP over all touching
    contacts, A p + (1 + e) d'_- >= 0, restitution 0 below the resting speed. Impulses."""
    e = np.where(-np.asarray(gap_velocity) > resting_speed, restitution, 0.0)
    return lcp.solve(A, (1.0 + e) * np.asarray(gap_velocity))
