"""Which contacts collide, rest or separate, and the frame of one instant after its impacts.

Contact modes (:func:`classify`), decided per contact from its gap d and gap velocity d':

* ``OPEN``: d > ``touch``;
* ``COLLIDING``: touching and approaching faster than the resting speed: restitution applies;
* ``RESTING``: touching and |d'| at most the resting speed (approaching) and the separation
  speed (moving apart; equal to the resting speed): any approach left is removed by a plastic
  impulse (restitution 0), then the contact force (the LCP on accelerations) holds it. This is
  what ends a bouncing ball in finite time: once the impact speed is below the resting speed the
  bounce is plastic and the contact rests -- no Zeno loop of ever smaller bounces. A resting
  contact that moves apart while the forces press it is made to rest exactly
  (runtime.step.resting), so nothing hovers;
* ``SEPARATING``: touching and d' > separation speed: it is left free, and its return, if any,
  is an impact located in time;
* ``LIFTING``: resting, but moving apart with nothing pressing it (runtime.step.resting
  decides): free in the step's force computation, watched like a separating contact, recorded
  as resting.

Hysteresis: a contact ``held`` (resting in the previous frame) rests up to d' = resting speed
while it touches, so a contact about to lift off stays in the LCP, which lets it go (zero force)
as soon as it pulls apart -- the lift-off is decided by the forces, not by speeds. Having drifted
apart, up to the hold gap, it still counts as touching unless it moves apart faster than the
resting speed (a force on a contact moving apart would do work): coming back, its impact is now.
So a contact in a settling pile that opens by nanometres and closes again is one resting contact,
not a stream of impacts; the price is that it may rest at a gap of up to the hold gap (never at
a penetration).

Impacts within a small window are resolved together: at an instant with an impact (a located
event, or a step's start), a contact that is not touching yet but approaches within the hold gap
(settings.HOLD touch, or the integrator's drift) would meet within microseconds; it takes its
impulse now, with the others, instead of being located as an impact of its own a moment later.
Its impact is then at a gap of at most the hold gap (1e-7 m by default), not 0.

Restitution of a contact: the larger of its two bodies' (as Box2D), 0 below the resting speed;
and 0 for a contact that was resting at the end of the last step and collides (a resting contact
drifted open by the integration is not a collision: with restitution 1 it would bounce for
ever). The creep speed is the rounding level of d' below which nothing is done.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import IntEnum
from functools import cached_property

import numpy as np

from runtime import settings
from runtime.collide.contact_keys import member
from runtime.collide.contact_set import Contacts
from runtime.compiled import njit
from runtime.solve import assembly, impulses
from runtime.solve.islands import body_islands, contact_islands, grouped
from runtime.solve.rows import Rows


class Mode(IntEnum):
    """What a contact does now (see the module docstring); plain ints in arrays."""

    OPEN = 0
    COLLIDING = 1
    RESTING = 2
    SEPARATING = 3
    LIFTING = 4


OPEN, COLLIDING, RESTING, SEPARATING, LIFTING = (int(m) for m in Mode)
_WATCHED = np.isin(np.arange(len(Mode)), (OPEN, SEPARATING, LIFTING))  # by mode: watched?


@dataclass(frozen=True)
class Limits:
    """The thresholds of :func:`classify` and the impacts (lengths in m, speeds in m/s)."""

    touch: float  # largest gap that counts as touching
    hold_gap: float  # largest gap at which a held contact stays touching
    resting_speed: float  # approach speed below which impacts are plastic
    separation_speed: float  # a touching contact separating slower than this rests
    creep_speed: float  # approach left after impacts (rounding level)
    stick_speed: float = settings.STICK_SPEED  # a frictional contact this slow sticks

    @classmethod
    def for_step(
        cls, resting_speed: float, touch: float, tolerance: float, h: float, gravity: float
    ) -> Limits:
        """The limits of steps of ``h`` under gravity |g| = ``gravity`` (:func:`hold_gap`)."""
        hold = hold_gap(float(h), float(gravity), float(touch), float(tolerance))
        stick = max(settings.STICK_SPEED, settings.STICK_DRIFT * float(gravity) * float(h))
        creep = settings.CREEP * resting_speed
        return cls(touch, hold, resting_speed, resting_speed, creep, stick)


@njit
def hold_gap(h, gravity, touch, tolerance):
    """The hold gap of steps of h: the larger of settings.HOLD touch and the drift -- a resting
    contact may drift off a curved surface by settings.DRIFT of the free-fall distance g h^2 / 2
    in one step and still be held, so large steps do not turn it into an impact every few
    steps -- at most the contact tolerance. Compiled: the coast (runtime.step.coast) takes it
    at every step, Limits.for_step once per step length."""
    drift = settings.DRIFT * 0.5 * gravity * h * h
    return min(max(settings.HOLD * touch, drift), tolerance)


@njit
def classify_modes(gap, rate, touch, hold_gap, resting_speed, separation_speed, held, out):
    """out[k] = the mode of contact k from its gap d and rate d' (the module docstring);
    ``held``: whether it was resting in the frame before."""
    for k in range(gap.size):
        d, r = gap[k], rate[k]
        touching = d <= touch
        if not touching and d <= hold_gap:
            if held[k]:  # drifted open, still within reach: rests unless it moves apart
                touching = r <= resting_speed
            else:  # about to close: its impact is now, with the others of this instant
                touching = r < 0.0
        if not touching:
            out[k] = OPEN
        elif r < -resting_speed:
            out[k] = COLLIDING
        elif r <= (resting_speed if held[k] else separation_speed):
            out[k] = RESTING
        else:
            out[k] = SEPARATING


def classify(
    gap: np.ndarray,
    gap_velocity: np.ndarray,
    limits: Limits,
    held: np.ndarray | None = None,
) -> np.ndarray:
    """Mode of each contact (an int array of :class:`Mode`); ``held``: contacts resting before."""
    gap = np.ascontiguousarray(gap, dtype=float)
    held = np.zeros(gap.size, dtype=bool) if held is None else np.asarray(held, dtype=bool)
    out = np.empty(gap.size, dtype=np.int64)
    classify_modes(gap, np.ascontiguousarray(gap_velocity, dtype=float), limits.touch,
                   limits.hold_gap, limits.resting_speed, limits.separation_speed, held, out)  # fmt: skip
    return out


@dataclass
class Frame:
    """The contacts at one instant (the start of a step or sub-step), classified, after the
    impacts among them have been resolved."""

    contacts: Contacts
    keys: np.ndarray  # identity of each contact (runtime.collide.contact_keys)
    rows: Rows  # kernel rows with the velocities after the impacts
    modes: np.ndarray  # Mode per contact (plain ints)
    velocities: np.ndarray  # (n, 3) after the impacts
    margin: np.ndarray  # per body: how far it may move in the step (runtime.collide.sweep)
    impulses: np.ndarray  # (m,) normal impulse each contact took at this instant
    impact_loss: float = 0.0  # kinetic energy the impacts took out (J)
    resting: np.ndarray = field(init=False)  # indices of the resting contacts

    def __post_init__(self) -> None:
        self.resting = (self.modes == RESTING).nonzero()[0]  # as np.flatnonzero, a call less

    @property
    def lifting(self) -> np.ndarray:
        return np.flatnonzero(self.modes == LIFTING)

    @property
    def monitored(self) -> np.ndarray:
        """Indices of the contacts whose time of impact is watched: open, separating, lifting."""
        return _WATCHED[self.modes].nonzero()[0]

    @cached_property
    def min_gap(self) -> float:
        """The smallest gap (m; inf without contacts): the records and the penetration guard
        ask for it at every step."""
        return float(self.rows.gap.min()) if len(self.rows.gap) else np.inf


@dataclass(frozen=True)
class Bodies:
    """What the frame needs to know of the bodies: (n, 3) inverse masses, fixed flags,
    restitution coefficients and masses (for the energy the impacts take)."""

    inverse_mass: np.ndarray
    fixed: np.ndarray
    restitution: np.ndarray
    mass: np.ndarray  # (n, 3): m, m, I (inf for fixed bodies)

    @classmethod
    def of(cls, scene) -> Bodies:
        fixed = np.asarray(scene.fixed, dtype=bool)
        inertia = np.array([b.inertia for b in scene.bodies], dtype=float)
        mass = np.array([b.mass for b in scene.bodies], dtype=float)
        return cls(
            scene.inverse_masses,
            fixed,
            np.array([b.restitution for b in scene.bodies], dtype=float),
            np.column_stack([mass, mass, inertia]),
        )

    def kinetic(self, velocities: np.ndarray) -> float:
        moving = ~self.fixed
        return 0.5 * float(np.sum(self.mass[moving] * velocities[moving] ** 2))


def make_frame(
    evaluator,
    bodies: Bodies,
    contacts: Contacts,
    poses: np.ndarray,
    velocities: np.ndarray,
    margin: np.ndarray,
    held: np.ndarray,
    limits: Limits,
    recent: np.ndarray,
    keys: np.ndarray,
    impacts=None,
) -> Frame:
    """Classify ``contacts`` (``keys``: their keys, runtime.collide.contact_keys; ``held``:
    keys of the contacts resting before) and resolve the impacts among the touching ones,
    island by island. A contact of ``recent`` (resting at the end of the last step) that
    collides is a resting contact that drifted open, not a collision: plastic. ``impacts``:
    what resolves them instead of :func:`_impacts` (same arguments and result;
    runtime.solve.linked_forces holds joints through them)."""
    rows = evaluator.rows(contacts, poses, velocities)
    modes = classify(rows.gap, rows.gap_velocity, limits, member(keys, held))
    m = len(contacts)
    frame = Frame(contacts, keys, rows, modes, velocities, margin, np.zeros(m))
    touching = np.flatnonzero(modes != OPEN)
    if touching.size == 0 or not np.any(rows.gap_velocity[touching] < -limits.creep_speed):
        return frame
    p, dv = (impacts or _impacts)(bodies, velocities, rows, touching, keys, recent, limits)
    new_velocities = velocities + dv
    rows = rows.with_velocity_change(dv)
    new_modes = classify(rows.gap, rows.gap_velocity, limits, member(keys, held))
    new_modes[modes == OPEN] = OPEN
    loss = bodies.kinetic(velocities) - bodies.kinetic(new_velocities)
    return Frame(contacts, keys, rows, new_modes, new_velocities, margin, p, loss)


def _impacts(bodies: Bodies, velocities, rows: Rows, touching, keys, recent, limits: Limits):
    """(impulse per contact, velocity change (n, 3)) of the impacts among the touching
    contacts, island by island (islands where nothing approaches are left alone)."""
    n = len(bodies.fixed)
    b1, b2 = rows.body1[touching], rows.body2[touching]
    labels = contact_islands(body_islands(n, b1, b2, bodies.fixed), b1, b2, bodies.fixed)
    order, offsets = grouped(labels)
    members = touching[order]
    rate = rows.gap_velocity
    e = np.maximum(bodies.restitution[rows.body1], bodies.restitution[rows.body2])
    drifted = member(keys, recent) & (rate < -limits.resting_speed)
    e[drifted] = 0.0
    jac = np.ascontiguousarray(rows.jacobian[members])
    sub_b1, sub_b2 = rows.body1[members], rows.body2[members]
    p = np.zeros(len(rate))
    mu = getattr(rows, "mu", None)  # FrictionRows in a scene with friction
    frictional, dv_friction = np.zeros(len(rate), dtype=bool), np.zeros((n, 3))
    for g in range(len(offsets) - 1):
        start, stop = int(offsets[g]), int(offsets[g + 1])
        island = members[start:stop]
        if not np.any(rate[island] < -limits.creep_speed):
            continue
        if mu is not None and np.any(mu[island] > 0):  # impulses with friction
            from runtime.solve.friction_impulses import resolve_frictional

            p[island], dv_island = resolve_frictional(
                rows.take(island), e[island], bodies, velocities, limits.resting_speed,
                limits.creep_speed,
            )  # fmt: skip
            frictional[island], dv_friction = True, dv_friction + dv_island
            continue
        A = np.empty((stop - start, stop - start))
        assembly.island_matrix(
            jac, sub_b1, sub_b2, bodies.inverse_mass, bodies.fixed, start, stop, A
        )
        outcome = impulses.resolve(
            A, rate[island], e[island], limits.resting_speed, limits.creep_speed
        )
        p[island] = outcome.impulses
    dv = dv_friction
    normal = np.where(frictional, 0.0, p)[members]  # the frictional islands' are in dv already
    assembly.add_forces(jac, sub_b1, sub_b2, bodies.inverse_mass, normal, dv)
    return p, dv
