"""Impacts: which touching contacts collide, rest or separate, and the velocity jumps at impacts.

Why this module exists: at the instant two bodies meet (the time of impact is located by
runtime.step.impact_time, so the gap is 0), their velocities must jump so that no touching contact
keeps approaching. The jump uses the same A = J M^-1 J^T as the contact forces (runtime.solve.dynamics):
the gap velocity is linear in the velocities, d' = J v, so impulses p along the normals change it
by exactly A p, and the velocities by M^-1 J^T p.

Contact modes (:func:`classify`), decided per contact from its gap d and gap velocity d':

* ``OPEN``: d > ``touch``;
* ``COLLIDING``: touching and approaching faster than the resting speed: restitution applies;
* ``RESTING``: touching and |d'| at most the resting speed (approaching) and the separation
  speed (moving apart; equal to the resting speed by default): any approach left is removed by
  a plastic impulse (restitution 0), then the contact force (the LCP on accelerations) holds it.
  This is what ends a bouncing ball in finite time: once the impact speed is below the resting
  speed the bounce is plastic and the contact rests -- no Zeno loop of ever smaller bounces. A
  resting contact that moves apart while the forces press it is made to rest exactly
  (runtime.step.resting), so nothing hovers;
* ``SEPARATING``: touching and d' > separation speed: it is left free, and its return, if any,
  is an impact located in time;
* ``LIFTING``: resting, but moving apart with nothing pressing it (runtime.step.resting decides):
  free in the step's force computation, watched like a separating contact, recorded as
  resting.

Hysteresis: a contact ``held`` (resting in the previous frame) rests up to d' = resting speed
while it touches, so a contact about to lift off stays in the LCP, which lets it go (zero force)
as soon as it pulls apart -- the lift-off is decided by the forces, not by speeds. Having drifted
apart, up to the hold gap (100 touch, 1e-7 m by default), it still rests unless it moves apart
(faster than the creep speed: it is let go, since a force on a contact moving apart would do
work and feed energy in) or comes back faster than the separation speed (its impact is
located). A contact in a settling pile that opens by nanometres and closes again slowly is
therefore one resting contact, not a stream of impacts; the price is that it may rest at a gap
of up to the hold gap (never at a penetration).

Restitution of a contact: the larger of its two bodies' (as Box2D), 0 below the resting speed;
a bounce slower than the separation speed that the forces press back rests at once; and 0 for a
contact that was resting at the end of the last step and collides (a resting contact drifted
open by the integration, e.g. of a large scene at a large step, is not a collision: with
restitution 1 it would bounce for ever). Impulses passed on by a wave keep their restitution. The creep
speed (1e-9 of the resting speed) is the rounding level of d' below which nothing is done.

Policy for several contacts (:func:`resolve`): waves of simultaneous impulses, then one inelastic
simultaneous pass.

1. A wave takes the contacts that approach faster than the resting speed *now* and solves them
   together, as the LCP A_WW p + (1 + e) d'_W >= 0, p >= 0, complementary (Newton's law on the
   velocities of that instant); the other touching contacts take no impulse in this wave.
2. The impulses change d' at the other touching contacts (A_{.W} p); those that now approach
   form the next wave. Waves repeat until nothing approaches faster than the resting speed
   (at most ``max_waves``).
3. A final simultaneous LCP with restitution 0 over the touching contacts, A p + d' >= 0,
   leaves none approaching (it catches slow approaches and waves that did not converge). It is
   solved over the approaching contacts, grown by those its impulses make approach until none
   outside approaches (up to the creep speed): a solution of the LCP over all of them, found
   on a smaller matrix. Each of these LCPs is first tried with every contact taking an impulse
   (a linear solve, runtime.solve.warm_start), and solved by pivoting (runtime.solve.lcp) if that fails.

So impacts that happen at the same instant (a block landing flat on two corners, a ball meeting
two balls at once) are simultaneous, and an impulse travels through contacts that were merely
touching one contact at a time, which is what gives Newton's cradle: a purely simultaneous LCP
over the whole row (:func:`simultaneous`, kept for comparison) moves the struck row together
instead of sending the last disc off.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from enum import IntEnum

import numpy as np

from runtime.solve import lcp
from runtime.solve.kernels import ContactRows
from runtime.solve.warm_start import solve_with_guess


class Mode(IntEnum):
    """What a contact does now (see the module docstring); plain ints in arrays."""

    OPEN = 0
    COLLIDING = 1
    RESTING = 2
    SEPARATING = 3
    LIFTING = 4  # resting, but moving apart with nothing pressing it (runtime.step.resting)


_OPEN, _RESTING, _SEPARATING = int(Mode.OPEN), int(Mode.RESTING), int(Mode.SEPARATING)
_LIFTING = int(Mode.LIFTING)


@dataclass(frozen=True)
class Limits:
    """The thresholds of :func:`classify` and :func:`resolve` (lengths in m, speeds in m/s)."""

    touch: float  # largest gap that counts as touching
    hold_gap: float  # largest gap at which a held contact stays touching
    resting_speed: float  # approach speed below which impacts are plastic
    separation_speed: float  # a touching contact separating slower than this rests
    creep_speed: float  # approach left after impacts (rounding level)

    @classmethod
    def default(
        cls, resting_speed: float, touch: float, tolerance: float, drift: float = 0.0
    ) -> Limits:
        """Hold gap the larger of 100 touch and ``drift`` (how far the integrator may carry a
        resting contact off its surface in one step), at most the contact tolerance
        ``tolerance``; separation speed the resting speed, creep speed 1e-9 of it."""
        hold = min(max(100.0 * touch, drift), tolerance)
        return cls(touch, hold, resting_speed, resting_speed, 1e-9 * resting_speed)


def contact_key(contact) -> tuple:
    """What identifies a contact from step to step: its bodies and features."""
    return (contact.body1, contact.body2, contact.feature)


def classify(
    gap: np.ndarray,
    gap_velocity: np.ndarray,
    *,
    touch: float,
    resting_speed: float,
    separation_speed: float,
    held: np.ndarray | None = None,
    hold_gap: float = 0.0,
    creep_speed: float = 0.0,
) -> np.ndarray:
    """Mode of each contact (an int array of :class:`Mode`).

    ``touch``: largest gap that counts as touching. ``held``: contacts that were resting before
    (a bool array): while touching they rest up to d' = ``resting_speed``; drifted apart (up to
    ``hold_gap``) they rest while they move apart no faster than ``creep_speed`` and come back
    no faster than the separation speed; else they are open like any other contact.
    """
    gap, dv = np.asarray(gap, float), np.asarray(gap_velocity, float)
    touching = gap <= touch
    limit: float | np.ndarray = separation_speed
    if held is not None:
        held = np.asarray(held, bool)
        drifted = held & ~touching & (gap <= hold_gap)
        touching = touching | (drifted & (dv >= -separation_speed) & (dv <= resting_speed))
        limit = np.where(held, resting_speed, separation_speed)
    # plain ints (IntEnum attribute access is slow on this hot path)
    mode = np.where(dv < -resting_speed, 1, np.where(dv <= limit, 2, 3))
    mode[~touching] = 0
    return mode


def restitution(bodies: Sequence, contacts: Sequence) -> np.ndarray:
    """Coefficient of restitution of each contact: the larger of its two bodies'."""
    return np.array(
        [max(bodies[c.body1].restitution, bodies[c.body2].restitution) for c in contacts],
        dtype=float,
    )


@dataclass(frozen=True)
class Impact:
    """The outcome of :func:`resolve`."""

    velocities: np.ndarray  # (n, 3) after the impact
    impulses: np.ndarray  # (m,) total normal impulse per contact
    gap_velocity: np.ndarray  # (m,) d' after the impact
    waves: int  # restitution waves used
    inelastic_pass: bool  # whether the final plastic pass changed anything


def resolve(
    dynamics,
    rows,
    velocities: np.ndarray,
    coefficients: np.ndarray,
    resting_speed: float,
    creep_speed: float,
    *,
    max_waves: int = 200,
) -> Impact:
    """Velocities after the impacts among touching contacts with kernel ``rows`` (the policy of
    the module docstring). ``coefficients``: restitution per contact. A final plastic pass runs
    if some contact still approaches faster than ``creep_speed``."""
    a_matrix, _, jm = dynamics.effective_mass_matrix(rows)
    dv = np.array(rows.gap_velocity, dtype=float)
    e = np.asarray(coefficients, dtype=float)
    total = np.zeros_like(dv)
    waves = 0
    while waves < max_waves:
        wave = np.flatnonzero(dv < -resting_speed)
        if wave.size == 0:
            break
        waves += 1
        p = _solve(a_matrix[np.ix_(wave, wave)], (1.0 + e[wave]) * dv[wave])
        total[wave] += p
        dv += a_matrix[:, wave] @ p
    plastic = bool(np.any(dv < -creep_speed))
    if plastic:  # over the approaching contacts and those their impulses make approach
        chosen = dv < -creep_speed
        while True:
            idx = np.flatnonzero(chosen)
            p = _solve(a_matrix[np.ix_(idx, idx)], dv[idx])
            after = dv + a_matrix[:, idx] @ p
            more = (after < -creep_speed) & ~chosen
            if not more.any():
                break
            chosen |= more
        total[idx] += p
        dv = after
    new = velocities + (jm.T @ total).reshape(velocities.shape)
    return Impact(new, total, dv, waves, plastic)


def _solve(a_matrix: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The impulse LCP, first guessing that every contact in it takes an impulse (true for
    most impacts: they are all approaching), else by pivoting (runtime.solve.lcp)."""
    f = solve_with_guess(a_matrix, b, np.ones(b.shape, dtype=bool))
    return lcp.solve(a_matrix, b) if f is None else f


def simultaneous(
    dynamics, rows, velocities: np.ndarray, coefficients: np.ndarray, resting_speed: float
) -> np.ndarray:
    """The purely simultaneous alternative (not used by the engine): one LCP over all touching
    contacts, A p + (1 + e) d'_- >= 0, restitution 0 below the resting speed. Velocities after."""
    e = np.where(-np.asarray(rows.gap_velocity) > resting_speed, coefficients, 0.0)
    a_matrix, _, jm = dynamics.effective_mass_matrix(rows)
    p = lcp.solve(a_matrix, (1.0 + e) * rows.gap_velocity)
    return velocities + (jm.T @ p).reshape(velocities.shape)


@dataclass
class Frame:
    """The contacts at one instant (the start of a step or sub-step), classified, after the
    impacts among them have been resolved."""

    contacts: list
    rows: ContactRows | None  # kernel rows with the velocities after the impacts
    modes: np.ndarray  # Mode per contact (plain ints)
    velocities: np.ndarray  # (n, 3) after the impacts
    margin: np.ndarray  # per body: how far it may move in the step (runtime.collide.sweep)
    impact: Impact | None = None
    resting: list = field(init=False)

    def __post_init__(self) -> None:
        self.resting = [self.contacts[k] for k in np.flatnonzero(self.modes == _RESTING)]

    @property
    def lifting(self) -> list:
        return [self.contacts[k] for k in np.flatnonzero(self.modes == _LIFTING)]

    @property
    def monitored(self) -> np.ndarray:
        """Indices of the contacts whose time of impact is watched: open, separating, lifting."""
        m = self.modes
        return np.flatnonzero((m == _OPEN) | (m == _SEPARATING) | (m == _LIFTING))

    @property
    def min_gap(self) -> float:
        return float(np.min(self.rows.gap)) if self.rows is not None else np.inf


def make_frame(
    dynamics,
    contacts: list,
    poses: np.ndarray,
    velocities: np.ndarray,
    margin: np.ndarray,
    held: set,
    limits: Limits,
    recent: set | frozenset = frozenset(),
) -> Frame:
    """Classify ``contacts`` (``held``: keys of the contacts resting before) and resolve the
    impacts among the touching ones. A contact of ``recent`` (resting at the end of the last
    step) that collides is a resting contact that drifted open, not a collision: plastic."""
    if not contacts:
        return Frame([], None, np.zeros(0, dtype=int), velocities, margin)
    rows = dynamics.rows(contacts, poses, velocities)
    was_held = np.array([contact_key(c) in held for c in contacts], dtype=bool)
    options = dict(
        touch=limits.touch,
        resting_speed=limits.resting_speed,
        separation_speed=limits.separation_speed,
        held=was_held,
        hold_gap=limits.hold_gap,
        creep_speed=limits.creep_speed,
    )
    modes = classify(rows.gap, rows.gap_velocity, **options)
    touching = np.flatnonzero(modes != _OPEN)
    impact = None
    if touching.size and np.any(rows.gap_velocity[touching] < -limits.creep_speed):
        touched = [contacts[k] for k in touching]
        e = restitution(dynamics.scene.bodies, touched)
        if recent:
            drifted = [contact_key(c) in recent for c in touched]
            e[np.asarray(drifted) & (rows.gap_velocity[touching] < -limits.resting_speed)] = 0.0
        impact = resolve(
            dynamics,
            subset(rows, touching),
            velocities,
            e,
            limits.resting_speed,
            limits.creep_speed,
        )
        change = (impact.velocities - velocities).ravel()
        velocities = impact.velocities
        before = rows.gap_velocity  # d' = J v: the impulses change it by J (v+ - v-)
        rows = replace(rows, gap_velocity=before + rows.dense_jacobian(len(velocities)) @ change)
        was_open = modes == _OPEN
        modes = classify(rows.gap, rows.gap_velocity, **options)
        modes[was_open] = _OPEN
    return Frame(contacts, rows, modes, velocities, margin, impact)


def subset(rows: ContactRows, idx: np.ndarray) -> ContactRows:
    """The kernel rows of the contacts ``idx``."""
    return ContactRows(
        rows.gap[idx],
        rows.gap_velocity[idx],
        rows.jacobian[idx],
        rows.bias[idx],
        rows.body1[idx],
        rows.body2[idx],
    )
