"""Ensembles: N copies of one scene, differing in a few numbers, stepped together.

    ensemble = runtime.simulate_ensemble(scene, {"disc.angle": angles}, duration=1.0, dt=1e-3)
    ensemble.t (K,), .poses and .velocities (N, K, n, 3), .energy (N, K),
    ensemble.max_penetration (N,), ensemble.failed (N,): each copy's error message or ""

Why one scene: N copies are one scene with N times the bodies in N collision groups
(runtime.step.copies), so the engine steps them as it steps any scene of independent islands:
each generated kernel is called once per stage for every copy's contacts, each copy's impacts
are located and sub-stepped on its own island, each copy's forces solved apart. Each copy's
result is that of its own `runtime.simulate` run (to rounding: the tests hold it to 1e-12).
Where the step does not keep islands apart, copies are not independent any more; see
:func:`simulate_ensemble` for those limits.

A copy that fails does not stop the others. The guards are checked per copy
(runtime.step.copy_guards); a copy that trips one is recorded as `simulate` would record it
(the records before the failing step, its error message) and its bodies are removed: the
combined scene is rebuilt without them (a new Stepper: O(bodies) of Python, ~0.1 s for 10,000
copies) and the others go on from the state the step gave them, which is theirs alone. A step
that raises (the contact solver, a non-finite pose in the contact finder) is redone: the copies
that raise alone are found by halving the set (about 2 log2 N probe steps of shrinking sets),
dropped, and the step is taken again from the state before it by the rest.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from runtime import settings
from runtime.solve.forces import Stabilisation
from runtime.solve.lcp import ContactSolverError
from runtime.step.copies import Copies, Layout, carry, snapshot
from runtime.step.copy_guards import CopyGuards
from runtime.step.guards import Guards
from runtime.step.integrators import FIXED_STEP, METHODS
from runtime.step.simulation import _check_arguments
from runtime.step.variations import read_variations
from runtime.step.world import _wrap_angles

STEP_ERRORS = (ContactSolverError, RuntimeError, FloatingPointError, ValueError)  # as World's


@dataclass
class Ensemble:
    """What an ensemble recorded, as NumPy arrays over N copies and K records (the records of
    `simulate`: t = k dt every ``record_every`` steps, and the end); body_names and fixed:
    the n bodies of the scene.

    t (K,); poses, velocities (N, K, n, 3); energy (N, K) (kinetic + gravitational, J);
    max_penetration (N,) (m, deepest overlap recorded); failed (N,) (the copy's
    SimulationError message, "" if it ran to the end); records (N,) (records a copy has: K,
    or fewer for a failed copy, whose later records are NaN); variations: the per-copy values
    as given (key -> (N,) or (N, 2))."""

    scene_name: str
    method: str
    dt: float
    body_names: list[str]
    fixed: list[bool]
    variations: dict[str, np.ndarray]
    t: np.ndarray
    poses: np.ndarray
    velocities: np.ndarray
    energy: np.ndarray
    max_penetration: np.ndarray
    failed: np.ndarray
    records: np.ndarray
    wall_time: float = 0.0
    rhs_evaluations: int = 0
    rebuilds: int = field(default=0)  # combined scenes rebuilt after failures

    @property
    def copies(self) -> int:
        return len(self.failed)


def simulate_ensemble(
    scene,
    variations: Mapping,
    duration: float | None = None,
    dt: float | None = None,
    method: str | None = None,
    *,
    stabilisation: Stabilisation | None = None,
    resting_speed: float | None = None,
    record_every: int = 1,
    progress: Callable[[float], None] | None = None,
    guards: Guards | None = None,
) -> Ensemble:
    """Run N copies of ``scene`` together for ``duration`` s in steps of ``dt`` (defaults, and
    the other options, as `runtime.simulate`). ``variations`` maps "<body name>.<field>"
    (position, velocity, angle, angular_velocity, mass, restitution, friction; a fixed body's
    position, angle, restitution, friction; "<body>.position[0]" for one component) and "scene.gravity" to arrays
    whose first axis is N, in the scene file's terms (runtime.step.variations); fields not
    named keep the scene's value.

    Limits, where the step couples what it treats as one scene: only the fixed-step methods
    (euler, midpoint, rk4; an adaptive one would choose one step size for all copies); a step
    whose impulse sends a body beyond its reach is redone by the stepper with all bodies as one
    island (stepper._Merge), which then sub-steps every copy at every copy's impacts; with
    varied gravity the swept margins and hold gap use the largest |g| (runtime.step.copies).
    Raises ValueError (one line, naming the key) for bad variations or arguments.
    """
    defaults = scene.simulation
    duration = defaults.duration if duration is None else float(duration)
    dt = defaults.dt if dt is None else float(dt)
    _check_arguments(duration, dt, record_every)
    method = (defaults.method if method is None else str(method)).lower()
    if method not in FIXED_STEP:
        known = "" if method in METHODS else "unknown method; "
        raise ValueError(
            f"simulate_ensemble: {known}method {method!r}: choose one of "
            f"{', '.join(FIXED_STEP)} (an adaptive method would choose one step size for all "
            "copies)"
        )
    speed = settings.RESTING_SPEED if resting_speed is None else float(resting_speed)
    if not (math.isfinite(speed) and speed > 0):
        raise ValueError(f"resting_speed must be a finite number > 0, got {speed}")
    if stabilisation is None and defaults.stabilisation:
        stabilisation = Stabilisation.critically_damped(10.0 * defaults.dt)
    copies = Copies(scene, read_variations(scene, variations))
    steps = max(0, math.ceil(duration / dt - 1e-9))
    lengths = [min(dt, duration - k * dt) if k == steps - 1 else dt for k in range(steps)]
    driver = _Driver(copies, method, stabilisation, speed, guards or Guards())
    recorder = _Recorder(copies, lengths, record_every)
    start = time.perf_counter()
    driver.start(recorder)
    for k, h in enumerate(lengths):
        if not len(driver.layout.members):
            break
        driver.step(k, h, k % record_every == 0)
        if progress is not None:
            progress(min(1.0, (k + 1) / steps))
    driver.finish(lengths[-1] if lengths else 0.0)
    wall = time.perf_counter() - start
    return recorder.ensemble(scene, method, dt, driver, wall)


class _Recorder:
    """The ensemble's arrays, filled record by record for the copies still running."""

    def __init__(self, copies: Copies, lengths: list[float], every: int) -> None:
        times, t = [], 0.0
        for k, h in enumerate(lengths):
            if k % every == 0:
                times.append(t)
            t += h
        times.append(t)
        self.t = np.array(times)
        shape = (copies.count, len(times), copies.n, 3)
        self.poses, self.velocities = np.full(shape, np.nan), np.full(shape, np.nan)
        self.energy = np.full((copies.count, len(times)), np.nan)
        self.records = np.zeros(copies.count, dtype=np.int64)
        self.min_gap = np.full(copies.count, np.inf)

    def add(self, layout: Layout, ok: np.ndarray, qc, vc, energy, frame) -> None:
        """One record of the members ``ok`` (positions): their state (qc, vc: (M, n, 3)),
        energies and the frame at that state (its smallest gap per copy)."""
        copies = layout.members[ok]
        k = self.records[copies]
        self.poses[copies, k] = qc[ok]
        self.velocities[copies, k] = vc[ok]
        self.energy[copies, k] = energy[ok]
        self.records[copies] += 1
        rows = frame.rows
        if len(rows.gap):
            one = layout.member[rows.body1]
            member = np.where(one >= 0, one, layout.member[rows.body2])
            smallest = np.full(len(layout.members), np.inf)
            np.minimum.at(smallest, member, rows.gap)
            self.min_gap[copies] = np.minimum(self.min_gap[copies], smallest[ok])

    def ensemble(self, scene, method: str, dt: float, driver: _Driver, wall: float) -> Ensemble:
        failed = np.array([driver.failed.get(c, "") for c in range(len(self.records))], dtype=str)
        return Ensemble(
            scene_name=scene.name,
            method=method,
            dt=dt,
            body_names=list(scene.names),
            fixed=list(scene.fixed),
            variations=driver.columns,
            t=self.t,
            poses=self.poses,
            velocities=self.velocities,
            energy=self.energy,
            max_penetration=np.maximum(0.0, -self.min_gap) + 0.0,  # + 0.0: no -0.0
            failed=failed,
            records=self.records,
            wall_time=wall,
            rhs_evaluations=driver.evaluations,
            rebuilds=driver.rebuilds,
        )


class _Driver:
    """The running copies' combined scene, state and stepper (see the module docstring)."""

    def __init__(self, copies: Copies, method, stabilisation, resting_speed, guards) -> None:
        self.copies, self.options = copies, (method, stabilisation, resting_speed)
        self.columns = copies.columns
        self.guards = CopyGuards(copies, guards, method)
        self.layout = copies.layout(np.arange(copies.count))
        self.stepper = copies.stepper(self.layout, *self.options)
        self.q, self.v = self.layout.scene.poses(), self.layout.scene.velocities()
        self.t = self.before = 0.0
        self.steps = 0
        self.failed: dict[int, str] = {}
        self.rebuilds, self.retired = 0, 0  # evaluations of steppers replaced

    @property
    def evaluations(self) -> int:
        return self.retired + self.stepper.evaluations

    def start(self, recorder: _Recorder) -> None:
        self.recorder = recorder
        self._gather()
        self.energy = self.guards.start(self.layout.members, self.qc, self.vc)

    def _gather(self) -> None:
        """The state per copy, (M, n, 3) each."""
        self.qc, self.vc = self.layout.per_copy(self.q), self.layout.per_copy(self.v)

    def step(self, k: int, h: float, record: bool) -> None:
        """Step k (length h) of every running copy; the copies that fail are dropped."""
        while len(self.layout.members):
            memory = snapshot(self.stepper)
            try:
                with np.errstate(all="ignore"):
                    new_q, new_v, report = self.stepper.step(self.q, self.v, h)
                break
            except STEP_ERRORS as exc:
                found = self._culprits(exc, k, h, memory)
                self.failed.update(found)
                keep = ~np.isin(self.layout.members, list(found))
                self._rebuild(keep, memory, self.q, self.v, self.energy)
        else:
            return
        layout, guards = self.layout, self.guards
        failed = guards.overlaps(layout, report.frame, k, self.t, self.before)
        _wrap_angles(new_q)
        new_qc, new_vc = layout.per_copy(new_q), layout.per_copy(new_v)
        with np.errstate(all="ignore"):
            energy = guards.energy(layout.members, new_qc, new_vc)
        per_copy = (self.qc, new_qc, new_vc)
        found = guards.after_step(layout, self.q, new_q, per_copy, energy, set(failed))
        if found:
            contacts = self.stepper.collision.swept(self.q, np.zeros(len(self.q)), None)
            for m, what in found.items():
                mine = guards.copy_contacts(layout, contacts, m)
                failed[m] = (
                    f"step {k} at t = {self.t:.6g} s {what}; contacts: "
                    f"{guards.contact_names(layout, mine)}"
                )
        ok = ~np.isin(np.arange(len(layout.members)), list(failed))
        if record:
            self.recorder.add(layout, ok, self.qc, self.vc, self.energy, report.frame)
        self.q, self.v, self.energy = new_q, new_v, energy
        self.qc, self.vc = new_qc, new_vc
        self.before, self.t, self.steps = self.t, self.t + h, self.steps + 1
        if failed:
            self.failed.update({int(layout.members[m]): what for m, what in failed.items()})
            self._rebuild(ok, snapshot(self.stepper), new_q, new_v, energy)

    def finish(self, h: float) -> None:
        """The last record: the final state, checked for an overlap the last step left."""
        layout = self.layout
        if not len(layout.members):
            return
        with np.errstate(all="ignore"):
            frame, _ = self.stepper.classify(self.q, self.v, h)
        failed = self.guards.overlaps(layout, frame, self.steps, self.t, self.before)
        self.failed.update({int(layout.members[m]): what for m, what in failed.items()})
        ok = ~np.isin(np.arange(len(layout.members)), list(failed))
        self.recorder.add(layout, ok, self.qc, self.vc, self.energy, frame)

    # -- failures --------------------------------------------------------------------------

    def _rebuild(self, keep: np.ndarray, memory, q, v, energy) -> None:
        """Go on with the members ``keep`` (a mask) only, from (q, v) with ``memory``."""
        old, copies = self.layout, self.copies
        new = copies.layout(old.members[keep])
        self.retired += self.stepper.evaluations
        if len(new.members):  # else nothing is stepped any more
            self.stepper = copies.stepper(new, *self.options)
            carry(memory, old, new, self.stepper, len(copies.own))
        self.stepper.evaluations = 0
        rows = _rows(old, keep, copies)
        self.layout = new
        self.q, self.v, self.energy = q[rows], v[rows], energy[keep]
        self._gather()
        self.rebuilds += 1

    def _culprits(self, error: Exception, k: int, h: float, memory) -> dict[int, str]:
        """{copy: message} of the copies whose step k fails when stepped alone, found by
        halving the members; all of them if no smaller set fails (the error needs them all)."""
        copies, layout = self.copies, self.layout

        def probe(members: np.ndarray):
            keep = np.isin(layout.members, members)
            sub = copies.layout(members)
            stepper = copies.stepper(sub, *self.options)
            carry(memory, layout, sub, stepper, len(copies.own))
            rows = _rows(layout, keep, copies)
            try:
                with np.errstate(all="ignore"):
                    stepper.step(self.q[rows], self.v[rows], h)
            except STEP_ERRORS as exc:
                return exc, sub, stepper, self.q[rows]
            return None

        def message(members, exc, sub, stepper, q) -> dict[int, str]:
            found = np.all(np.isfinite(q))
            contacts = stepper.collision.swept(q, np.zeros(len(q)), None) if found else None
            out = {}
            for m, c in enumerate(members.tolist()):
                names = (
                    "none"
                    if contacts is None
                    else self.guards.contact_names(sub, self.guards.copy_contacts(sub, contacts, m))
                )
                out[c] = f"step {k} at t = {self.t:.6g} s failed ({exc}); contacts: {names}"
            return out

        def search(members: np.ndarray, failure) -> dict[int, str]:
            if len(members) > 1:
                found: dict[int, str] = {}
                for half in np.array_split(members, 2):
                    result = probe(half)
                    if result is not None:
                        found.update(search(half, result))
                if found:
                    return found
            return message(members, *failure)

        return search(layout.members, (error, layout, self.stepper, self.q))


def _rows(old: Layout, keep: np.ndarray, copies: Copies) -> np.ndarray:
    """Indices into the combined arrays of ``old`` of the bodies of the layout of its members
    ``keep`` (shared bodies first, then each kept copy's own bodies)."""
    shared = np.arange(len(copies.shared))
    return np.r_[shared, old.index[keep][:, copies.own].ravel()].astype(np.int64)
