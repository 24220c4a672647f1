"""Quiet stretches of a run, stepped in one compiled loop.

Why: a step of a small scene is ~20 us of compiled physics wrapped in ~50 us of Python (the
stages' calls, a Frame and a report per step, the World's guards and energy, the record). Most
steps of most runs are quiet -- the same contacts, no impact, nothing for the event search --
and for those the Python decides nothing. This loop takes the same compiled stages in the same
order -- the contact finder's three stages (runtime.collide.finder), the frame
(runtime.step.compiled_frame), the trial (runtime.step.compiled_stages), the quiet check
(runtime.step.quiet), the World's guards, energy and momentum -- and writes each step's record
into arrays. It stops before the first step that is not such a step: another contact set, a
frame or trial the compiled stages decline, a lifting contact (its record needs a solve of its
own), a trial that is not quiet, a guard that trips, an angle to wrap. World.step
then does that step the usual way, and names a failure. So a coasted step is the same step, to
the bit (tests/runtime/test_coast.py), and the World's memory after a stretch (the contacts
held, the warm-start guesses) is what the steps one by one leave.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from runtime import settings
from runtime.collide.contact_keys import _looked_up, _packed, key_set
from runtime.collide.contact_set import Contacts
from runtime.collide.finder import _first_bad_margin, _tolerance
from runtime.collide.narrowphase import find_candidates
from runtime.collide.selection import select
from runtime.collide.sweep import _margins
from runtime.compiled import Bound, njit
from runtime.solve.kernel_set import candidate_gaps
from runtime.step.classify import LIFTING, RESTING, hold_gap
from runtime.step.compiled_frame import settle_frame
from runtime.step.compiled_stages import METHOD_ID, lifted, step
from runtime.step.guards import _crossing, _passed_through, deepest_relative
from runtime.step.quiet import is_quiet
from runtime.step.world import _far_angle, _kinetic, _lifted, _momentum


@njit
def _no_contacts():
    """:func:`stretch_contacts`' answer where the finder's Python must decide (m = -1)."""
    return (-1, np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64),
            np.zeros((0, 7)), np.zeros((0, 4), np.int64), np.zeros((0, 2)), np.zeros((0, 2)),
            np.zeros(0), np.zeros(0, np.int64))  # fmt: skip


@njit(inline="always")  # (no call, no reference counting per step)
def stretch_contacts(q, v, hi, finder, radii, moving, gravity, everyone, margin):
    """Stage 1 of a coasted step: the contacts that can close within hi
    (runtime.collide.finder.find), ``margin`` written. Returns (m, case, body1, body2,
    geometry, feature, point, normal, gap, keys), m = -1 where the finder's Python must
    decide (a margin out of range, candidate buffers too small, a gap not evaluated)."""
    tol, groups, apart, rows, start, body, owner, compound, cand, inputs, nkeys, width = finder
    _margins(v, hi, radii, moving, gravity, margin)
    if _first_bad_margin(margin) >= 0:
        return _no_contacts()
    if compound:
        p, widen, allow = q[owner], margin[owner], everyone[owner]
    else:
        p, widen, allow = q, margin, everyone
    count = find_candidates(p, tol, widen, allow, groups, apart, rows, start, body, owner,
                            compound, cand, inputs)  # fmt: skip
    if count < 0 or count > cand.shape[0]:
        return _no_contacts()
    b1, b2, geometry_c, members, case_start = inputs
    gap = np.empty(count)
    if candidate_gaps(p, b1, b2, geometry_c, members, case_start, gap) != count:
        return _no_contacts()
    out = (np.empty(count, np.int64), np.empty(count, np.int64), np.empty(count, np.int64),
           np.empty((count, 7)), np.empty((count, 4), np.int64), np.empty((count, 2)),
           np.empty((count, 2)))  # fmt: skip
    m = select(p, tol, widen, body, cand, count, b1, b2, gap, out) if count else 0
    one, two = out[1][:m], out[2][:m]
    if compound:
        one, two = owner[one], owner[two]
    feature = out[4][:m]
    return (m, out[0][:m], one, two, out[3][:m], feature, out[5][:m], out[6][:m], gap[:m],
            _packed(one, two, feature, nkeys, width))  # fmt: skip


@njit(inline="always")  # (no call, no reference counting per step)
def guarded_energy(q, q1, v1, frame_gap, one, two, radii, guards, wrap):
    """The energy after a coasted step from q to (q1, v1), or NaN where one of the World's
    guards (runtime.step.world: penetration, a centre through an edge or a body, non-finite
    numbers, energy growth) would trip or an angle is to be wrapped: World.step then does the
    step and names the failure."""
    (penetration, segments, arcs, moved_rows, inner, hollow, energy0, energy_limit, e_mass,
     e_inertia, gx, gy) = guards  # fmt: skip
    if penetration > 0.0 and deepest_relative(frame_gap, one, two, radii)[1] > penetration:
        return np.nan
    if not (np.all(np.isfinite(q1)) and np.all(np.isfinite(v1))):
        return np.nan
    if penetration > 0.0 and (  # (a centre through a fixed edge, or through a body)
        _crossing(q, q1, moved_rows, segments, arcs)[0] >= 0
        or _passed_through(q, q1, inner, hollow)[0] >= 0
    ):
        return np.nan
    e1 = _kinetic(e_mass, e_inertia, v1) - _lifted(e_mass, gx, gy, q1)
    if e1 - energy0 > energy_limit or _far_angle(q1, wrap):
        return np.nan
    return e1


@njit
def stretch_records(steps, n):
    """A stretch's per-step records of the state before each step: (clock, poses, velocities,
    energies, momenta, min gaps, impact losses), as :class:`Coaster` reads them."""
    return (np.empty(steps), np.empty((steps, n, 3)), np.empty((steps, n, 3)), np.empty(steps),
            np.empty((steps, 2)), np.empty(steps), np.empty(steps))  # fmt: skip


@njit(inline="always")  # (no call, no reference counting per step)
def write_record(records, i, t, q, v, energy, e_mass, min_gap, loss):
    """Record i of :func:`stretch_records`: the state (q, v) at time t before the step."""
    clock, poses, velocities, energies, momenta, min_gaps, losses = records
    clock[i], energies[i], min_gaps[i], losses[i] = t, energy, min_gap, loss
    poses[i], velocities[i] = q, v
    momenta[i] = _momentum(e_mass, v)


@njit
def contact_records(steps, m):
    """(the contact set's kind arrays, empty; per-step gaps, points, normals, forces and
    resting flags of m contacts)."""
    kind = (np.zeros(0, np.int64), np.zeros(0, np.int64), np.zeros(0, np.int64),
            np.zeros((0, 7)), np.zeros((0, 4), np.int64))  # fmt: skip
    return kind, (np.empty((steps, m)), np.empty((steps, m, 2)), np.empty((steps, m, 2)),
                  np.empty((steps, m)), np.empty((steps, m), np.bool_))  # fmt: skip


@njit
def coast(times, t, q, v, energy, finder, memory, bodies, numbers, guards):  # noqa: C901
    """Steps to each of ``times`` from (q, v) at time t, while each is a quiet step (see the
    module docstring). ``finder``, ``memory``, ``bodies``, ``numbers``, ``guards``: the tables of
    runtime.collide.finder, the stepper's memory, the bodies, the settings and the World's
    guards (:class:`Coaster`).
    Returns the number of steps done, the state after them, the records of the states before
    each, the contact set and each step's contacts and forces, and the memory to write back."""
    rows = finder[3]
    held_table, guess_keys, guess_clamped = memory
    (radii, moving, gravity, restitution, mass, inv_mass, fixed, free_acc, step_inv_mass,
     half_width, switches, depths, body_start) = bodies  # fmt: skip
    (method, lcp_tol, dense, rounds, touch, tolerance, resting_speed, creep, fast_pair,
     wrap) = numbers  # fmt: skip
    e_mass = guards[8]
    n, steps = q.shape[0], times.size
    records = stretch_records(steps, n)
    everyone = np.ones(n, np.bool_)
    keys = np.zeros(0, np.int64)
    held = np.zeros(0, np.bool_)
    before = held
    guess_memory = held
    touched = held
    kind, (gaps, points, normals, forces_out, resting_out) = contact_records(0, 0)
    evaluations = 0
    done = 0
    for i in range(steps):
        hi = times[i] - t  # as World.step's dt: the next grid time minus the time now
        # 1. the contacts that can close within h (runtime.collide.finder.find)
        margin = np.empty(n)
        found_ = stretch_contacts(q, v, hi, finder, radii, moving, gravity, everyone, margin)
        if found_[0] < 0:
            break
        m, case, one, two, geometry, feature, point, normal, gap, found = found_
        if i == 0:  # the set of this stretch, and the memory the stepper has of it
            keys = found
            held = _looked_up(keys, held_table, np.ones(0, np.bool_))
            guess_memory = _looked_up(keys, guess_keys, guess_clamped)
            touched = np.zeros(m, np.bool_)
            kind = (case, one, two, geometry, feature)
            gaps, points, normals, forces_out, resting_out = contact_records(steps, m)[1]
        elif m != keys.size or not np.all(found == keys):
            break
        # 2-4. the frame: classify, impacts, settle, resting forces (runtime.step.stepper; with
        # no contacts, the general path's frame: gravity alone)
        static2 = fixed[two]
        guess = guess_memory.copy()
        start_v = v.copy()
        frame_gap, rate, bias = np.empty(m), np.empty(m), np.empty(m)
        jac = np.empty((m, 6))
        modes = np.empty(m, np.int64)
        impulses, forces, rates = np.zeros(m), np.zeros(m), np.zeros(m)
        acc = free_acc.copy()
        order, offsets, labels = (
            np.empty(m, np.int64),
            np.zeros(m + 1, np.int64),
            np.empty(m, np.int64),
        )
        counts = np.zeros(2, np.int64)
        loss = 0.0
        if m:
            hold = hold_gap(hi, gravity, touch, tolerance)
            lim = (touch, hold, resting_speed, resting_speed, creep)  # (Limits.for_step)
            ok, loss = settle_frame(
                q, case, one, two, geometry, static2, held, held, restitution, mass, inv_mass,
                fixed, free_acc, lim, lcp_tol, dense, rounds, start_v, frame_gap, rate, jac,
                bias, modes, impulses, guess, forces, rates, acc, (order, offsets, labels, counts),
            )  # fmt: skip
            if not ok or np.any(modes == LIFTING):
                break
        rest = order[: counts[0]]
        # 5. the trial with the resting contacts' forces, each island its own
        q1, v1 = np.empty_like(q), np.empty_like(v)
        resting = (case[rest], one[rest], two[rest], np.ascontiguousarray(geometry[rest]),
                   static2[rest], offsets[: counts[1]])  # fmt: skip
        staged = guess[rest]  # (its clamped flags: updated by each stage's solve)
        if not step(method, q, start_v, hi, acc, *resting, staged, step_inv_mass, fixed,
                    free_acc, lcp_tol, dense, q1, v1):  # fmt: skip
            break
        # 6. nothing for the event search to find, and no pressing contact lifting off
        # (runtime.step.lift_events)
        if not is_quiet(q, q1, v1, margin, radii, half_width, switches, case, one, two,
                        geometry, static2, modes, frame_gap, rate, touch, creep, fast_pair,
                        fixed, depths, rows, body_start, feature, start_v, acc, hi):  # fmt: skip
            break
        pressing = forces[rest] > 0.0
        if np.any(pressing & ~staged) and lifted(
            q1, v1, *resting, staged, step_inv_mass, fixed, free_acc, lcp_tol, dense, pressing,
            hi, resting_speed,
        ):  # fmt: skip
            break
        # the World's guards (runtime.step.world), its energy and angle wrap
        min_gap = frame_gap.min() if m else np.inf
        e1 = guarded_energy(q, q1, v1, frame_gap, one, two, radii, guards, wrap)
        if not np.isfinite(e1):
            break
        # the record of the state before the step, and the step taken
        write_record(records, i, t, q, v, energy, e_mass, min_gap, loss)
        gaps[i], points[i], normals[i], forces_out[i] = gap, point, normal, forces
        for k in range(m):
            resting_out[i, k] = modes[k] == RESTING
        for k in rest:
            guess_memory[k] = guess[k]
            touched[k] = True
        before = held
        held = (modes == RESTING) | (modes == LIFTING)
        q, v, energy, t = q1, v1, e1, t + hi
        evaluations += 3 if method == 2 else method
        done += 1
    return (done, t, q, v, energy, evaluations, records, kind,
            (gaps, points, normals, forces_out, resting_out),
            (keys, held, before, guess_memory, touched))  # fmt: skip


@dataclass(frozen=True)
class Stretch:
    """The records of the steps a coast did (one per step, the state before it): as a Run's
    arrays, and each step's contacts (one set; its gaps, points, normals per step) and forces."""

    t: np.ndarray
    poses: np.ndarray
    velocities: np.ndarray
    energy: np.ndarray
    momentum: np.ndarray
    min_gap: np.ndarray
    impact_loss: np.ndarray
    kind: tuple  # case, body1, body2, geometry, feature of the contact set (read-only)
    gap: np.ndarray  # (steps, m) each step's contacts' gaps, points (steps, m, 2), normals
    point: np.ndarray
    normal: np.ndarray
    forces: np.ndarray  # (steps, m): 0 where a contact does not rest
    resting: np.ndarray  # (steps, m) bool
    every: list[bool]  # per step: whether every contact rests
    friction: np.ndarray | None = None  # (steps, m) friction forces f_t (None: no friction)

    def __len__(self) -> int:
        return len(self.t)

    def contacts(self, i: int) -> tuple[Contacts, np.ndarray, np.ndarray | None]:
        """The resting contacts at record i, their forces and friction forces (None without
        friction): what runtime.step.stepper's first frame records."""
        every = Contacts(*self.kind, self.gap[i], self.point[i], self.normal[i])
        friction = self.friction
        if self.every[i]:
            return every, self.forces[i], None if friction is None else friction[i]
        rest = self.resting[i]
        return (every.take(rest), self.forces[i][rest],
                None if friction is None else friction[i][rest])  # fmt: skip


class Coaster:
    """A World's compiled loop over quiet steps (see the module docstring): its fixed arguments,
    when to try it, and the World and stepper it brings up to date."""

    def __init__(self, world) -> None:
        stepper = world.stepper
        finder = stepper.collision.finder
        self.world = world
        records = settings.COAST_RECORD_BYTES // (48 * stepper.n)  # 48 bytes: a body's q and v
        self.batch = int(min(settings.COAST_BATCH, max(1, records)))  # steps a call at most
        self._friction = None
        if stepper.compiled_friction:  # imported here: a frictionless scene never loads it
            from runtime.step.coast_friction import coast_friction

            self._call = Bound(coast_friction)
            self._friction = (np.asarray(stepper.evaluator.friction, dtype=float),)
        else:
            self._call = Bound(coast)
        self._wait = self._patience = 0
        t = finder.tables
        self._finder = (
            _tolerance(stepper.collision.tolerance), finder._unit_groups, finder.apart, t.rows,
            t.start, t.body, t.owner, finder.compound,
        )  # fmt: skip
        b = stepper.bodies
        self._bodies = (
            stepper.radii, stepper.moving, float(stepper.gravity), b.restitution, b.mass,
            b.inverse_mass, b.fixed, stepper.forces.free_acceleration,
            stepper.forces.inverse_mass, stepper.events.half_width, stepper.events.switches,
            stepper.events.deepest, t.body_start,
        )  # fmt: skip
        self._numbers = (
            METHOD_ID[stepper.method], settings.LCP_TOL, settings.DENSE_ISLAND,
            settings.SETTLE_ROUNDS, float(stepper.touch), float(stepper.scene.contact_tolerance),
            float(stepper.resting_speed), settings.CREEP * stepper.resting_speed,
            settings.FAST_PAIR, settings.ANGLE_WRAP,
        )  # fmt: skip
        guards = world.guards
        edges = world._edges  # (None: no penetration guard)
        none = np.zeros((0, 5)), np.zeros((0, 6))
        mass, inertia = world._masses
        gx, gy = world.scene.gravity
        scale = world.energy_scale
        self._guards = (
            -1.0 if guards.penetration is None else float(guards.penetration),
            *(none if edges is None else (edges.segments, edges.arcs)),
            world._moving, world._inner, world._hollow, float(world.energy0),
            guards.energy_growth * scale if scale > 0 else math.inf,
            mass, inertia, float(gx), float(gy),
        )  # fmt: skip

    @staticmethod
    def applies(world) -> bool:
        """Whether a World's steps can coast: the compiled path (with or without friction),
        with int64 contact keys."""
        stepper = world.stepper
        compiled = stepper.compiled or stepper.compiled_friction
        return compiled and stepper.collision.finder.keys.packed

    def ready(self, quiet: bool) -> bool:
        """Whether to try after a step that was (or was not) ``quiet``: after an attempt that did
        no step, the next 1, 2, 4, ... settings.COAST_PATIENCE quiet steps go one by one."""
        if not quiet:
            return False
        if self._wait:
            self._wait -= 1
            return False
        return True

    def run(self, times: np.ndarray) -> Stretch | None:
        """Step the World to each of ``times`` (grid times after its own, in order) while the
        steps are quiet; the records of those done (None: none)."""
        world, stepper = self.world, self.world.stepper
        finder = stepper.collision.finder
        buffers = (finder._candidates, finder._kernel_inputs)  # (the finder may grow them)
        tables = (*self._finder, *buffers, finder.keys.n, finder.keys.width)
        memory = stepper.forces.memory
        remembered = (stepper.held, memory.keys, memory.clamped)
        friction = self._friction
        if friction is not None:
            bases = stepper.forces.bases
            remembered = (*remembered, bases.keys, bases.clamped)
        with np.errstate(all="ignore"):
            done, t, q, v, energy, evaluations, records, kind, contacts, written = self._call(
                times, world.t, world.poses, world.velocities, float(world.energy()),
                tables, remembered, self._bodies, self._numbers, self._guards,
                *(() if friction is None else friction),
            )  # fmt: skip
        if done == 0:
            self._patience = min(max(2 * self._patience, 1), settings.COAST_PATIENCE)
            self._wait = self._patience
            return None
        self._patience = 0
        keys, held, before, guesses, touched = written[:5]
        recent = stepper.held if done == 1 else key_set(keys[before])
        stepper.held, stepper.recent = key_set(keys[held]), recent
        memory.update(keys[touched], guesses[touched])
        if friction is not None:
            stepper.forces.bases.update(keys[touched], written[5][touched])
        stepper.evaluations += evaluations
        clock, poses, velocities, energies, momenta, min_gaps, losses = (r[:done] for r in records)
        last = (clock[-1], poses[-1], velocities[-1], times[done - 1] - clock[-1])
        world.advanced(t, q, v, energy, done, last)
        for a in kind:
            a.flags.writeable = False
        gap, point, normal, forces, resting = (a[:done] for a in contacts[:5])
        tangent = None if friction is None else contacts[5][:done]
        return Stretch(clock, poses, velocities, energies, momenta, min_gaps, losses, kind,
                       gap, point, normal, forces, resting, resting.all(axis=1).tolist(),
                       tangent)  # fmt: skip


__all__ = ["Coaster", "Stretch", "coast"]
