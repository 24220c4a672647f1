"""A scene stepped one step at a time: the engine's state and what a user asks of it.

Why: pymunk users drive a Space step by step, change velocities between steps, and look at the
contacts; `simulate` and the CLI are built on the same object. A World owns the state
(t, poses, velocities), the stepper (runtime.step.stepper) and the guards (runtime.step.guards),
and raises :class:`SimulationError` naming the step, the time and the contacts when a step goes
wrong -- keeping the state it had before that step.

    world = runtime.World(scene)
    for _ in range(1000):
        world.step(1e-3)
    world.t, world.poses, world.velocities, world.energy()
    world.contacts, world.contact_forces            # at the current state
    world.apply_impulse("disc", (0.0, 2.0), point=(0.1, 0.0))
"""

from __future__ import annotations

import math

import numpy as np

from runtime import settings
from runtime.collide.contact_set import Contacts
from runtime.compiled import njit
from runtime.solve.forces import Stabilisation
from runtime.solve.lcp import ContactSolverError
from runtime.step.classify import OPEN
from runtime.step.guards import (
    FixedEdges,
    Guards,
    contact_names,
    deepest_overlap,
    energy_scale,
    inner_radius,
    passed_through,
)
from runtime.step.integrators import METHODS, TIME_STEPPING
from runtime.step.stepper import Stepper, StepReport


class SimulationError(RuntimeError):
    """A step failed. ``state`` is (poses, velocities) before the failing step; ``run`` holds
    what `simulate` recorded up to the last good step (None for a World used directly)."""

    def __init__(self, message: str, run, state: tuple[np.ndarray, np.ndarray]):
        super().__init__(message)
        self.run = run
        self.state = state


def body_masses(scene) -> tuple[np.ndarray, np.ndarray]:
    """(mass, moment of inertia) per body, 0 for fixed ones: the weights of the energy and
    momentum sums, taken once per run (summed per body in Python they cost ~3 us a body and
    step: 47 ms a step for 10,000 discs)."""
    moving = [not b.fixed for b in scene.bodies]
    mass = np.array([b.mass if m else 0.0 for b, m in zip(scene.bodies, moving, strict=True)])
    inertia = np.array([b.inertia if m else 0.0 for b, m in zip(scene.bodies, moving, strict=True)])
    return mass.reshape(-1), inertia.reshape(-1)


def kinetic_energy(scene, velocities: np.ndarray, masses=None) -> float:
    """Kinetic energy of the moving bodies (``masses``: body_masses(scene), if at hand)."""
    mass, inertia = body_masses(scene) if masses is None else masses
    v = np.ascontiguousarray(velocities, dtype=float).reshape(-1, 3)
    return _kinetic(mass, inertia, v)


def mechanical_energy(scene, poses: np.ndarray, velocities: np.ndarray, masses=None) -> float:
    """Kinetic + gravitational potential energy of the moving bodies (+ the springs' and the
    mutual gravitation's energy, if any: runtime.solve.applied_forces)."""
    mass, inertia = body_masses(scene) if masses is None else masses
    gx, gy = scene.gravity
    q = np.ascontiguousarray(poses, dtype=float).reshape(-1, 3)
    v = np.ascontiguousarray(velocities, dtype=float).reshape(-1, 3)
    energy = _kinetic(mass, inertia, v) - _lifted(mass, float(gx), float(gy), q)
    if scene.springs or scene.mutual_gravity:
        from runtime.solve.applied_forces import applied_potential

        energy += applied_potential(scene, poses)
    return energy


@njit
def _kinetic(mass, inertia, v):
    """sum m |v|^2 / 2 + I w^2 / 2 over the bodies (0 weights for fixed ones), one compiled
    loop: summed by NumPy ufuncs it cost ~10 us a step for a scene of two bodies."""
    e = 0.0
    for i in range(v.shape[0]):
        e += 0.5 * mass[i] * (v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1])
        e += 0.5 * inertia[i] * v[i, 2] * v[i, 2]
    return e


@njit
def _lifted(mass, gx, gy, q):
    """sum m g . x over the bodies: minus their gravitational potential energy."""
    s = 0.0
    for i in range(q.shape[0]):
        s += mass[i] * (gx * q[i, 0] + gy * q[i, 1])
    return s


def linear_momentum(scene, velocities: np.ndarray, masses=None) -> np.ndarray:
    mass = (body_masses(scene) if masses is None else masses)[0]
    v = np.ascontiguousarray(velocities, dtype=float).reshape(-1, 3)
    return _momentum(mass, v)


@njit
def _momentum(mass, v):
    """sum m v over the bodies (0 weights for fixed ones), one compiled loop."""
    out = np.zeros(2)
    for i in range(v.shape[0]):
        out[0] += mass[i] * v[i, 0]
        out[1] += mass[i] * v[i, 1]
    return out


class World:
    """One scene's state, stepped by :meth:`step` (see the module docstring).

    ``method``: one of runtime.step.integrators.METHODS (default: the scene's). ``stabilisation``:
    Baumgarte drift control (default: the scene's ``[simulation] stabilisation`` flag, which
    turns on a critically damped one with a time scale of 10 steps of the scene's dt).
    ``guards``: limits that stop a run that went wrong (runtime.step.guards).
    """

    def __init__(
        self,
        scene,
        method: str | None = None,
        *,
        stabilisation: Stabilisation | None = None,
        guards: Guards | None = None,
        resting_speed: float = settings.RESTING_SPEED,
    ) -> None:
        defaults = scene.simulation
        method = (defaults.method if method is None else str(method)).lower()
        if method not in METHODS:
            raise ValueError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
        if not (math.isfinite(resting_speed) and resting_speed > 0):
            raise ValueError(f"resting_speed must be a finite number > 0, got {resting_speed}")
        if stabilisation is None and defaults.stabilisation:
            stabilisation = Stabilisation.critically_damped(10.0 * defaults.dt)
        self.scene, self.method = scene, method
        self.guards = Guards() if guards is None else guards
        if method == TIME_STEPPING:  # imported here: the other methods never load it
            from runtime.step.time_stepping import TimeStepper

            self.stepper = TimeStepper(scene, method, stabilisation, resting_speed)
        else:
            self.stepper = Stepper(scene, method, stabilisation, resting_speed)
        self.t = 0.0
        self.steps = 0
        self.poses, self.velocities = scene.poses(), scene.velocities()
        self._masses = body_masses(scene)
        self.last: StepReport | None = None  # (None after steps that coasted: simulate's)
        self.impact_times: list[float] = []
        self.lift_times: list[float] = []
        self._at_state = None  # (frame, resting solution) at the current state, when asked for
        self._last_dt: float | None = None
        with np.errstate(all="ignore"):
            self._energy = mechanical_energy(scene, self.poses, self.velocities, self._masses)
            kinetic = kinetic_energy(scene, self.velocities, self._masses)
        radii = self.stepper.radii
        self.energy0 = self._energy
        self.energy_scale = (
            energy_scale(scene, radii, kinetic) if self.guards.energy_growth is not None else 0.0
        )
        self._edges = FixedEdges(scene) if self.guards.penetration is not None else None
        self._moving = np.flatnonzero(~np.asarray(scene.fixed, dtype=bool))
        self._inner = np.array([inner_radius(s) for s in scene.shapes])
        self._hollow = np.asarray(scene.fixed, dtype=bool) | (self._inner == 0)
        for pair in scene.joined_pairs:  # linked bodies may overlap: not checked by centres
            self._hollow[list(pair)] = True

    # -- state -----------------------------------------------------------------------------

    def energy(self) -> float:
        """Kinetic + gravitational potential energy of the moving bodies now (J)."""
        return self._energy

    def index(self, body: int | str) -> int:
        if isinstance(body, str):
            return self.scene.index(body)
        k = int(body)
        if not 0 <= k < len(self.scene.bodies):
            raise IndexError(f"no body {k}: the scene has {len(self.scene.bodies)} bodies")
        return k

    def apply_impulse(self, body: int | str, impulse, point=None) -> None:
        """Give a moving body (index or name) the impulse (N s, world axes) at ``point`` (world
        coordinates; default its centre of mass): its velocity changes by impulse / m and its
        angular velocity by (point - centre) x impulse / I, and by the joint impulses that keep
        its joints' d' (runtime.solve.linked_forces)."""
        k = self.index(body)
        b = self.scene.bodies[k]
        if b.fixed:
            raise ValueError(f"body {b.name!r} is fixed: an impulse cannot move it")
        p = np.asarray(impulse, dtype=float).reshape(2)
        r = (
            np.zeros(2)
            if point is None
            else np.asarray(point, dtype=float).reshape(2) - self.poses[k, :2]
        )
        if not (np.all(np.isfinite(p)) and np.all(np.isfinite(r))):
            raise ValueError(f"impulse and point must be finite, got {impulse!r}, {point!r}")
        before = self.velocities.copy()
        self.velocities[k, :2] += p / b.mass
        self.velocities[k, 2] += (r[0] * p[1] - r[1] * p[0]) / b.inertia
        if self.stepper.links is not None:  # the body's joints pass the impulse on
            self.velocities = self.stepper.links.held_velocities(
                self.poses, before, self.velocities
            )
        self._changed()

    def _changed(self) -> None:
        self._at_state = None
        self._energy = mechanical_energy(self.scene, self.poses, self.velocities, self._masses)

    def _current(self):
        if self._at_state is None:
            h = self._last_dt if self._last_dt is not None else 0.0
            self._at_state = self.stepper.classify(self.poses, self.velocities, h)
        return self._at_state

    @property
    def contacts(self) -> Contacts:
        """The contacts touching now (resting or touching and separating), as arrays: bodies,
        case, point, normal, gap (runtime.collide.contact_set.Contacts)."""
        frame, _ = self._current()
        return frame.contacts.take(np.flatnonzero(frame.modes != OPEN))

    @property
    def contact_forces(self) -> np.ndarray:
        """The force (N) of each contact of :attr:`contacts` now (0 where it does not rest)."""
        return self._touching(lambda solution: solution.forces)

    @property
    def friction_forces(self) -> np.ndarray:
        """The friction force (N) of each contact of :attr:`contacts` now: f_t on body 1 along
        t = n turned by +90 degrees (docs/conventions.md), 0 where it does not rest or has no
        friction."""
        return self._touching(lambda solution: solution.tangent_forces)

    def _touching(self, of_resting) -> np.ndarray:
        """A value per contact of :attr:`contacts`: ``of_resting(solution)`` (per resting
        contact, or None) where it rests, 0 elsewhere."""
        frame, solution = self._current()
        values = np.zeros(len(frame.contacts))
        resting = of_resting(solution)
        if resting is not None:
            values[frame.resting] = resting
        return values[np.flatnonzero(frame.modes != OPEN)]

    def final_frame(self):
        """(frame, resting solution) at the current state, checked by the penetration guard
        (the last step may have left an overlap): what the last record of a run shows."""
        frame, solution = self._current()
        self._check_start(StepReport(frame=frame))
        return frame, solution

    # -- stepping --------------------------------------------------------------------------

    def step(self, dt: float) -> StepReport:
        """Advance the state by dt (s). Raises SimulationError (the state stays as it was)
        when the step fails or a guard trips."""
        if not (isinstance(dt, int | float) and math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt must be a finite number > 0, got {dt!r}")
        q, v = self.poses, self.velocities
        with np.errstate(all="ignore"):
            try:
                new_q, new_v, report = self.stepper.step(q, v, float(dt))
            except (ContactSolverError, RuntimeError, FloatingPointError, ValueError) as exc:
                raise self.failure(f"failed ({exc})") from exc
            self._check_start(report)
            self._check_step(new_q, new_v)
            energy = mechanical_energy(self.scene, new_q, new_v, self._masses)
            self._check_energy(energy)
        _wrap_angles(new_q)
        self.impact_times += [self.t + tau for tau in report.impact_times]
        self.lift_times += [self.t + tau for tau in report.lift_times]
        self.poses, self.velocities, self._energy = new_q, new_v, energy
        self.steps += 1
        self.t += float(dt)
        self.last = report
        self._last_dt = float(dt)
        self._at_state = None
        return report

    def advanced(self, t: float, poses, velocities, energy: float, steps: int, last) -> None:
        """The state after ``steps`` steps done in one compiled loop (runtime.step.coast), each
        checked by the guards there; ``last``: (t, poses, velocities, dt) of the last of them
        (a guard of the next step names it)."""
        self._previous = (last[0], (last[1].copy(), last[2].copy()))
        self.poses, self.velocities, self._energy, self.t = poses, velocities, energy, t
        self.steps += steps
        self.last = None
        self._last_dt = float(last[3])
        self._at_state = None

    # -- guards ----------------------------------------------------------------------------

    def failure(self, what: str, contacts: Contacts | None = None) -> SimulationError:
        """A SimulationError for the step about to be taken from the current state."""
        if contacts is None:
            with np.errstate(all="ignore"):
                found = np.all(np.isfinite(self.poses))
                contacts = (
                    self.stepper.collision.swept(self.poses, np.zeros(len(self.poses)), None)
                    if found
                    else Contacts.empty()
                )
        return SimulationError(
            f"step {self.steps} at t = {self.t:.6g} s {what}; contacts: "
            f"{contact_names(self.scene, contacts)}",
            None,
            (self.poses.copy(), self.velocities.copy()),
        )

    def _check_start(self, report: StepReport) -> None:
        """The contacts at the start of this step overlap too deeply: the last step made them
        (or, at step 0, the scene starts that way)."""
        limit = self.guards.penetration
        frame = report.frame
        found = (
            None if limit is None or frame is None else deepest_overlap(frame, self.stepper.radii)
        )
        if found is None or found[1] <= limit:
            return
        depth, relative, k = found
        pair = contact_names(self.scene, frame.contacts.take([k]))
        size = f"{depth:.3g} m, {relative:.3g} of the smaller body's size (limit {limit:g})"
        if self.steps == 0:
            raise self.failure(f"starts with {pair} overlapping by {size}", frame.contacts)
        raise SimulationError(
            f"step {self.steps - 1} at t = {self._previous[0]:.6g} s left {pair} overlapping by "
            f"{size}: {_TOO_LARGE}",
            None,
            self._previous[1],
        )

    def _check_step(self, new_q: np.ndarray, new_v: np.ndarray) -> None:
        """A non-finite state, a centre of mass through a fixed edge, two moving bodies through
        each other."""
        if not (math.isfinite(new_q.sum()) and math.isfinite(new_v.sum())):  # one call each
            # (a sum of finite entries can overflow: then each entry is looked at)
            if not (np.isfinite(new_q).all() and np.isfinite(new_v).all()):
                raise self.failure("produced a non-finite state")
        self._previous = (self.t, (self.poses.copy(), self.velocities.copy()))
        if self._edges is None:
            return
        bodies = self.scene.bodies
        crossed = self._edges.crossing(self.poses, new_q, self._moving)
        if crossed is not None:
            body, wall = bodies[crossed[0]], bodies[crossed[1]]
            raise self.failure(
                f"moved the centre of mass of {body.name} through {wall.name} (it tunnelled): "
                f"{_TOO_LARGE}"
            )
        hit = passed_through(self.poses, new_q, self._inner, self._hollow)
        if hit is not None:
            i, j = bodies[hit[0]], bodies[hit[1]]
            raise self.failure(
                f"moved {i.name} and {j.name} through each other (a centre of mass came inside "
                f"the other body's inscribed circle): {_TOO_LARGE}"
            )

    def _check_energy(self, energy: float) -> None:
        if (
            self.energy_scale > 0
            and energy - self.energy0 > self.guards.energy_growth * self.energy_scale
        ):
            raise self.failure(
                f"raised the energy from {self.energy0:.6g} J at t = 0 to {energy:.6g} J, "
                f"more than {self.guards.energy_growth:g} x the scene's energy scale "
                f"{self.energy_scale:.3g} J (no contact adds energy): the time step is too "
                f"large for {self.method}"
            )


_TOO_LARGE = (
    "the time step is too large (or a wall faces the wrong way: a body behind a wall's back "
    "face passes through it; or a chain's end corners are missing: end_vertices)"
)


def _wrap_angles(poses: np.ndarray) -> None:
    """Angles beyond settings.ANGLE_WRAP wrapped to (-pi, pi] (in place), so a long spin keeps
    the integrator's resolution of the angle."""
    if _far_angle(poses, settings.ANGLE_WRAP):
        far = np.abs(poses[:, 2]) > settings.ANGLE_WRAP
        poses[far, 2] = np.remainder(poses[far, 2] + np.pi, 2.0 * np.pi) - np.pi


@njit
def _far_angle(poses, limit):
    """Whether some angle is beyond ``limit`` (one compiled pass: this runs at every step)."""
    for i in range(poses.shape[0]):
        if abs(poses[i, 2]) > limit:
            return True
    return False
