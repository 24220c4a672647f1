"""Quiet stretches of a run with friction, stepped in one compiled loop.

Why: as runtime.step.coast for a frictionless scene -- a rolling disc, or a box resting on a
floor with friction, is quiet at almost every step, and World.step spends ~0.25 ms of Python a
step around ~50 us of compiled stages. This loop takes the same compiled stages in the same
order as World.step on a scene with friction -- the contact finder's stages
(runtime.step.coast.stretch_contacts), the frame with friction, the trial with friction and its
friction quiet check (runtime.step.compiled_friction), the quiet check of impacts
(runtime.step.quiet), the World's guards (runtime.step.coast.guarded_energy) -- and stops before
the first step that is not such a step, which World.step then does. A module of its own: a
frictionless scene never imports it (nor the friction kernels).
"""

from __future__ import annotations

import numpy as np

from runtime import settings
from runtime.collide.contact_keys import _looked_up
from runtime.compiled import njit
from runtime.step.classify import LIFTING, RESTING, hold_gap
from runtime.step.coast import (
    contact_records,
    guarded_energy,
    stretch_contacts,
    stretch_records,
    write_record,
)
from runtime.step.compiled_friction import friction_quiet, settle_frame, step
from runtime.step.quiet import is_quiet

_STICK, _DRIFT = settings.STICK_SPEED, settings.STICK_DRIFT


@njit
def coast_friction(times, t, q, v, energy, finder, memory, bodies, numbers, guards, friction):  # noqa: C901
    """runtime.step.coast.coast for a scene with friction: ``memory`` also holds the contacts'
    bases (keys, flags), ``friction`` is each body's coefficient. Returns what coast returns,
    with each step's friction forces beside the normal ones and the bases to write back."""
    rows = finder[3]
    held_table, guess_keys, guess_clamped, basis_keys, basis_flags = memory
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
    before, guess_memory, touched = held, held, held
    flag_memory = np.zeros(0, np.int8)
    mu = np.zeros(0)
    kind, (gaps, points, normals, forces_out, resting_out) = contact_records(0, 0)
    friction_out = np.empty((0, 0))
    evaluations = 0
    done = 0
    for i in range(steps):
        hi = times[i] - t  # as World.step's dt: the next grid time minus the time now
        # 1. the contacts that can close within h
        margin = np.empty(n)
        found_ = stretch_contacts(q, v, hi, finder, radii, moving, gravity, everyone, margin)
        m = found_[0]
        if m <= 0:  # (no contacts: World.step's general path, gravity alone)
            break
        _, case, one, two, geometry, feature, point, normal, gap, found = found_
        if i == 0:  # the set of this stretch, and the memory the stepper has of it
            keys = found
            held = _looked_up(keys, held_table, np.ones(0, np.bool_))
            guess_memory = _looked_up(keys, guess_keys, guess_clamped)
            flag_memory = _looked_up(keys, basis_keys, basis_flags)
            touched = np.zeros(m, np.bool_)
            mu = np.sqrt(friction[one] * friction[two])  # runtime.solve.friction_rows
            kind = (case, one, two, geometry, feature)
            gaps, points, normals, forces_out, resting_out = contact_records(steps, m)[1]
            friction_out = np.empty((steps, m))
        elif m != keys.size or not np.all(found == keys):
            break
        # 2-4. the frame with friction (runtime.step.stepper's settled_frame)
        static2 = fixed[two]
        flags = flag_memory.copy()
        start_v = v.copy()
        frame_gap, rate, bias = np.empty(m), np.empty(m), np.empty(m)
        jac = np.empty((m, 6))
        tangent = (np.empty(m), np.empty((m, 6)), np.empty(m))
        modes = np.empty(m, np.int64)
        impulses, slide, forces, tangential, rates = (np.zeros(m), np.zeros(m), np.zeros(m),
                                                      np.zeros(m), np.zeros(m))  # fmt: skip
        acc = np.empty_like(free_acc)
        order, offsets, labels = (
            np.empty(m, np.int64),
            np.empty(m + 1, np.int64),
            np.empty(m, np.int64),
        )
        counts = np.zeros(2, np.int64)
        lim = (
            touch,
            hold_gap(hi, gravity, touch, tolerance),
            resting_speed,
            resting_speed,
            creep,
        )  # fmt: skip (Limits.for_step)
        stick_speed = max(_STICK, _DRIFT * gravity * hi)
        ok, loss = settle_frame(
            q, case, one, two, geometry, static2, held, held, restitution, mass, inv_mass,
            fixed, free_acc, lim, lcp_tol, dense, rounds, mu, stick_speed, start_v, frame_gap,
            rate, jac, bias, tangent, modes, impulses, flags, slide, forces, tangential, rates,
            acc, (order, offsets, labels, counts),
        )  # fmt: skip
        if not ok or np.any(modes == LIFTING):
            break
        rest = order[: counts[0]]
        # 5. the trial with the resting contacts' forces and modes
        if rest.size == 0:
            break  # (no resting contact: World.step's general trial)
        q1, v1 = np.empty_like(q), np.empty_like(v)
        ends = np.empty((rest.size, 2), np.int64)
        ends[:, 0], ends[:, 1] = one[rest], two[rest]
        args = (case[rest], one[rest], two[rest], np.ascontiguousarray(geometry[rest]),
                static2[rest], ends, offsets[: counts[1]], mu[rest], slide[rest], flags[rest])  # fmt: skip
        if not step(method, q, start_v, hi, acc, *args, step_inv_mass, fixed, free_acc, q1, v1):
            break
        # 6. nothing for the event search to find: no impact, no friction transition
        if not friction_quiet(q1, v1, *args, step_inv_mass, fixed, free_acc):
            break
        if not is_quiet(q, q1, v1, margin, radii, half_width, switches, case, one, two,
                        geometry, static2, modes, frame_gap, rate, touch, creep, fast_pair,
                        fixed, depths, rows, body_start, feature, start_v, acc, hi):  # fmt: skip
            break
        e1 = guarded_energy(q, q1, v1, frame_gap, one, two, radii, guards, wrap)
        if not np.isfinite(e1):
            break
        # the record of the state before the step, and the step taken
        write_record(records, i, t, q, v, energy, e_mass, frame_gap.min(), loss)
        gaps[i], points[i], normals[i] = gap, point, normal
        forces_out[i], friction_out[i] = forces, tangential
        for k in range(m):
            resting_out[i, k] = modes[k] == RESTING
        for k in rest:
            flag_memory[k] = flags[k]
            touched[k] = True
        before = held
        held = (modes == RESTING) | (modes == LIFTING)
        q, v, energy, t = q1, v1, e1, t + hi
        evaluations += 3 if method == 2 else method
        done += 1
    return (done, t, q, v, energy, evaluations, records, kind,
            (gaps, points, normals, forces_out, resting_out, friction_out),
            (keys, held, before, guess_memory, touched, flag_memory))  # fmt: skip
