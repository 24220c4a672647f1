"""The time-stepping driver: contacts, impacts, contact forces and integration, step by step.

Why: resting contacts and impacts need different treatment (forces on accelerations for the
first, velocity jumps for the second), and an impact must be handled when the gap is 0, not at
the end of a step when the bodies have sunk into each other or passed through each other.

Each step (and each sub-step after an impact inside it):

1. Find the contacts that can close within the step: the scene's tolerance inflated by how far
   each body can move (runtime.collide.sweep), so fast bodies cannot tunnel through thin walls.
2. Classify them (runtime.step.collisions.classify: open, colliding, resting, separating) and resolve
   the impacts among the touching ones (runtime.step.collisions.resolve); the resting set is what is
   left touching and neither approaching nor separating. Solve its contact forces (warm-started
   from the last clamped set, runtime.solve.warm_start); a resting contact that moves apart is either
   pressed back to rest or marked lifting (runtime.step.resting), so no force does work.
3. Integrate a trial step with the forces of the resting set re-solved at every stage (Euler,
   midpoint, RK4, or scipy's adaptive RK45/DOP853 over the step). A resting contact is held at
   d'' >= 0 with d = 0 kept by the exact derived b term; a contact whose force would be negative
   leaves the clamped set.
4. If an open (or separating) contact's kernel gap reaches 0 during the trial step, locate the
   first such instant (runtime.step.impact_time), integrate only up to it and go to 1 with the rest
   of the step; otherwise the trial step is the step.

The recorded grid stays t = k dt; impacts inside steps are listed in ``Run.impact_times``.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import numpy as np

from runtime.collide import sweep
from runtime.solve.dynamics import ContactDynamics, Stabilisation
from runtime.solve.lcp import ContactSolverError
from runtime.solve.warm_start import WarmStartSolver
from runtime.step.collisions import Frame, Limits, Mode, contact_key, make_frame
from runtime.step.guards import FixedEdges, Guards, contact_names, deepest_overlap, energy_scale
from runtime.step.impact_time import ImpactSearch
from runtime.step.integrators import ADAPTIVE, FIXED_STEP, METHODS
from runtime.step.resting import settle

DRIFT = 1e-3  # see Simulator._limits


class SimulationError(RuntimeError):
    """A step failed. `run` holds everything up to the last good step, `state` the state before."""

    def __init__(self, message: str, run: Run, state: tuple[np.ndarray, np.ndarray]):
        super().__init__(message)
        self.run = run
        self.state = state


@dataclass
class Run:
    """What a simulation recorded, one entry per recorded step."""

    scene_name: str
    method: str
    dt: float
    t: list[float] = field(default_factory=list)
    poses: list[np.ndarray] = field(default_factory=list)
    velocities: list[np.ndarray] = field(default_factory=list)
    energy: list[float] = field(default_factory=list)
    momentum: list[np.ndarray] = field(default_factory=list)
    contacts: list[list] = field(default_factory=list)
    contact_forces: list[np.ndarray] = field(default_factory=list)
    min_gap: list[float] = field(default_factory=list)  # smallest gap found at each step start
    impact_times: list[float] = field(default_factory=list)  # located times of impact
    rhs_evaluations: int = 0
    wall_time: float = 0.0

    def arrays(self) -> dict[str, np.ndarray]:
        """The run as arrays (for .npz): t (K,), poses (K, n, 3), velocities, energy, ..."""
        return {
            "t": np.asarray(self.t),
            "poses": np.asarray(self.poses),
            "velocities": np.asarray(self.velocities),
            "energy": np.asarray(self.energy),
            "momentum": np.asarray(self.momentum),
            "min_gap": np.asarray(self.min_gap),
            "total_contact_force": np.array([f.sum() for f in self.contact_forces]),
        }

    @property
    def max_penetration(self) -> float:
        return max(0.0, -min(self.min_gap, default=0.0))


def kinetic_energy(scene, velocities: np.ndarray) -> float:
    """Kinetic energy of the moving bodies."""
    terms = (
        0.5 * body.mass * (v[0] ** 2 + v[1] ** 2) + 0.5 * body.inertia * v[2] ** 2
        for body, v in zip(scene.bodies, velocities, strict=True)
        if not body.fixed
    )
    return float(sum(terms))


def mechanical_energy(scene, poses: np.ndarray, velocities: np.ndarray) -> float:
    """Kinetic + gravitational potential energy of the moving bodies."""
    g = np.asarray(scene.gravity)
    potential = sum(
        -body.mass * float(g @ q[:2])
        for body, q in zip(scene.bodies, poses, strict=True)
        if not body.fixed
    )
    return kinetic_energy(scene, velocities) + potential


def linear_momentum(scene, velocities: np.ndarray) -> np.ndarray:
    return sum(
        (b.mass * v[:2] for b, v in zip(scene.bodies, velocities, strict=True) if not b.fixed),
        np.zeros(2),
    )


def _check_arguments(duration: float, dt: float, method: str) -> None:
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; choose one of {', '.join(METHODS)}")
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a finite number > 0, got {dt}")
    if not (np.isfinite(duration) and duration >= 0):
        raise ValueError(f"duration must be a finite number >= 0, got {duration}")


class Simulator:
    """Steps one scene; `simulate` is the one-call front end.

    ``touch``: the largest gap that counts as touching (a located impact has |d| below a
    thousandth of it). ``max_events``: impacts allowed inside one step before giving up.
    """

    def __init__(
        self,
        scene,
        method: str = "rk4",
        stabilisation: Stabilisation | None = None,
        resting_speed: float = 1e-3,
        rtol: float = 1e-9,
        atol: float = 1e-12,
        touch: float = 1e-9,
        max_events: int = 1000,
    ) -> None:
        self.scene = scene
        self.method = method
        self.forces = WarmStartSolver()
        self.dynamics = ContactDynamics(scene, stabilisation, self.forces)
        self.resting_speed = resting_speed
        self.rtol, self.atol = rtol, atol
        touch = min(touch, scene.contact_tolerance)
        self.limits = Limits.default(resting_speed, touch, scene.contact_tolerance)
        self._step_limits: dict[float, Limits] = {}
        self.max_events = max_events
        self.n = len(scene.bodies)
        self.shapes, self.fixed = scene.shapes, scene.fixed
        self.search = ImpactSearch(
            self.dynamics, self.shapes, self.fixed, touch, scene.contact_tolerance
        )
        self.radii = self.search.radii
        self.moving = 1.0 - np.asarray(self.fixed, dtype=float)
        self.gravity = float(np.hypot(*scene.gravity))
        self.evaluations = 0
        self.held: set = set()  # keys of the contacts resting in the last frame
        self.recent: set = set()  # keys of the contacts resting at the end of the last step
        self.impact_times: list[float] = []  # located impacts, time from the step start
        self.last_frame: Frame | None = None  # the first frame of the last step

    def _solve(self, resting: list, poses: np.ndarray, velocities: np.ndarray, keys=None):
        """Contact forces of ``resting``; the warm start follows the contacts, not their order."""
        self.forces.keys = [contact_key(c) for c in resting] if keys is None else keys
        return self.dynamics.solve(resting, poses, velocities)

    def _rhs(self, resting: list) -> Callable[[np.ndarray], np.ndarray]:
        n = self.n
        keys = [contact_key(c) for c in resting]

        def rhs(y: np.ndarray) -> np.ndarray:
            self.evaluations += 1
            poses, vel = y[: 3 * n].reshape(n, 3), y[3 * n :].reshape(n, 3)
            acc = self._solve(resting, poses, vel, keys).accelerations
            return np.concatenate([vel.ravel(), acc.ravel()])

        return rhs

    def _split(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = self.n
        return y[: 3 * n].reshape(n, 3), y[3 * n :].reshape(n, 3)

    # -- contacts and impacts at one instant ------------------------------------------------

    def frame(self, poses: np.ndarray, velocities: np.ndarray, h: float) -> Frame:
        """Contacts that can close within h, classified, with the impacts among them resolved."""
        margin = sweep.margins(velocities, h, self.radii, self.moving, self.gravity)
        return self._frame(
            sweep.swept_contacts(self.scene, poses, margin), poses, velocities, margin
        )

    def _frame(self, contacts: list, poses, velocities, margin) -> Frame:
        frame = make_frame(
            self.dynamics, contacts, poses, velocities, margin, self.held, self.limits, self.recent
        )
        self.held = {contact_key(c) for c in frame.resting}
        return frame

    def classify(self, poses: np.ndarray, velocities: np.ndarray, h: float = 0.0):
        """Contacts now, after impacts: (resting contacts, velocities, all contacts found)."""
        frame = self.last_frame = self.frame(poses, velocities, h)
        return frame.resting, frame.velocities, frame.contacts

    # -- one step -----------------------------------------------------------------------------

    def _trajectory(self, poses, velocities, h: float, resting: list, solution):
        """t -> state after integrating t (0 < t <= h) from (poses, velocities)."""
        y0 = np.concatenate([poses.ravel(), velocities.ravel()])
        rhs = self._rhs(resting)
        cache: dict[float, np.ndarray] = {}
        if self.method in FIXED_STEP:
            k1 = np.concatenate([velocities.ravel(), solution.accelerations.ravel()])
            integrate = FIXED_STEP[self.method]

            def at(t: float) -> np.ndarray:
                if t not in cache:
                    cache[t] = integrate(rhs, y0, t, k1)
                return cache[t]

            return at
        from scipy.integrate import solve_ivp  # imported on use: it costs ~1 s to import

        sol = solve_ivp(
            lambda _t, yy: rhs(yy),
            (0.0, h),
            y0,
            method=ADAPTIVE[self.method],
            rtol=self.rtol,
            atol=self.atol,
            dense_output=True,
        )
        if not sol.success:
            raise RuntimeError(f"solve_ivp failed: {sol.message}")
        return lambda t: sol.y[:, -1] if t >= h else sol.sol(t)

    def step(self, poses: np.ndarray, velocities: np.ndarray, dt: float):
        """One step from (poses, velocities): returns (poses, velocities, resting, forces).

        Integrates to the end of the step, or to the first time of impact inside it, resolves
        the impact there and goes on with the rest of the step. ``resting`` and ``forces`` are
        those at the start of the step.
        """
        remaining, first, events = dt, None, 0
        self.recent = set(self.held)  # resting at the end of the last step
        self.limits = self._limits(dt)
        while True:
            frame, solution = settle(
                self.dynamics,
                self.frame(poses, velocities, remaining),
                lambda rest, vel, at=poses: self._solve(rest, at, vel),
                self.limits.creep_speed,
            )
            resting = frame.resting
            if first is None:
                first = self._record(frame, poses, solution)
                self.last_frame = frame
            traj = self._trajectory(poses, frame.velocities, remaining, resting, solution)
            tau = self._first_impact(frame, traj, remaining, poses)
            if tau is None or tau >= remaining:
                end_poses, end_vel = self._split(traj(remaining))
                return end_poses, end_vel, first[0], first[1]
            poses, velocities = self._split(traj(tau))
            remaining -= tau
            self.impact_times.append(dt - remaining)
            events += 1
            if events > self.max_events:
                raise RuntimeError(f"more than {self.max_events} impacts within one step")

    def _limits(self, dt: float) -> Limits:
        """The contact limits for steps of ``dt``: a resting contact may drift off a curved
        surface by a small part (DRIFT) of the free-fall distance g dt^2 / 2 in one step and
        still be held (runtime.step.collisions.classify), so large steps do not turn it into an
        impact every few steps."""
        if dt not in self._step_limits:
            drift = DRIFT * 0.5 * self.gravity * dt * dt
            tolerance = self.scene.contact_tolerance
            self._step_limits[dt] = Limits.default(
                self.resting_speed, self.limits.touch, tolerance, drift
            )
        return self._step_limits[dt]

    def _record(self, frame: Frame, poses, solution):
        """(resting contacts, their forces) to record: lifting contacts count as resting."""
        if not frame.lifting:
            return frame.resting, solution
        every = frame.resting + frame.lifting
        return every, self._solve(every, poses, frame.velocities)

    # -- time of impact -------------------------------------------------------------------

    def _first_impact(self, frame: Frame, traj, h: float, poses: np.ndarray) -> float | None:
        """Time from the step start of the first impact among the frame's open contacts."""
        end_poses = self._split(traj(h))[0]
        if sweep.outran(poses, end_poses, self.radii, frame.margin):  # widen and search again
            wider = np.maximum(frame.margin, 2.0 * sweep.displacement(poses, end_poses, self.radii))
            lifting = {contact_key(c) for c in frame.lifting}
            contacts = sweep.swept_contacts(self.scene, poses, wider)
            frame = self._frame(contacts, poses, frame.velocities, wider)
            if lifting:  # keep watching the lifting contacts the trial step left free
                modes = frame.modes.copy()
                modes[[k for k, c in enumerate(contacts) if contact_key(c) in lifting]] = int(
                    Mode.LIFTING
                )
                frame = replace(frame, modes=modes)
        return self.search.first(frame, traj, h)


DEFAULT_GUARDS = Guards()


def simulate(
    scene,
    duration: float | None = None,
    dt: float | None = None,
    method: str | None = None,
    *,
    stabilisation: Stabilisation | None = None,
    resting_speed: float = 1e-3,
    rtol: float = 1e-9,
    atol: float = 1e-12,
    record_every: int = 1,
    progress: Callable[[float], None] | None = None,
    guards: Guards = DEFAULT_GUARDS,
) -> Run:
    """Run `scene` for `duration` seconds (defaults from the scene's [simulation] table).

    Raises SimulationError when a step fails (the contact solver, a non-finite state) or a
    guard trips (runtime.step.guards: penetration, energy growth); its ``run`` holds what was recorded
    up to the last good step and its ``state`` the state before the failing step.
    """
    defaults = scene.simulation
    duration = defaults.duration if duration is None else float(duration)
    dt = defaults.dt if dt is None else float(dt)
    method = (defaults.method if method is None else method).lower()
    _check_arguments(duration, dt, method)
    sim = Simulator(scene, method, stabilisation, resting_speed, rtol, atol)
    run = Run(scene.name, method, dt)
    poses, vel = scene.poses(), scene.velocities()
    with np.errstate(all="ignore"):
        energy = mechanical_energy(scene, poses, vel)  # of the current state, carried along
        watch = _Watch(scene, guards, sim.radii, energy, kinetic_energy(scene, vel), run)
    steps = int(round(duration / dt))
    start = time.perf_counter()
    t = 0.0
    for k in range(steps + 1):
        with np.errstate(all="ignore"):  # overflow shows as a non-finite value, checked below
            try:
                if k == steps:
                    resting, vel, _ = sim.classify(poses, vel)
                    solution = sim.dynamics.solve(resting, poses, vel)
                    new = None
                else:
                    before = len(sim.impact_times)
                    new_poses, new_vel, resting, solution = sim.step(poses, vel, dt)
                    run.impact_times += [t + tau for tau in sim.impact_times[before:]]
                    new = (new_poses, new_vel)
            except (ContactSolverError, RuntimeError, FloatingPointError, ValueError) as exc:
                raise watch.failure(k, t, f"failed ({exc})", poses, vel) from exc
            watch.penetration(sim.last_frame, k, t, poses, vel)
            if k % record_every == 0 or k == steps:
                run.t.append(t)
                run.poses.append(poses.copy())
                run.velocities.append(vel.copy())
                run.energy.append(energy)
                run.momentum.append(linear_momentum(scene, vel))
                run.contacts.append(resting)
                run.contact_forces.append(solution.forces)
                run.min_gap.append(sim.last_frame.min_gap if sim.last_frame else np.inf)
            if new is None:
                break
            energy = mechanical_energy(scene, *new)
            watch.after_step(k, t, (poses, vel), new, energy, method)
        poses, vel = new
        t = (k + 1) * dt
        if progress is not None:
            progress(t / duration if duration else 1.0)
    run.rhs_evaluations = sim.evaluations
    run.wall_time = time.perf_counter() - start
    return run


class _Watch:
    """The guards of one run (runtime.step.guards) and the SimulationError messages, built in one
    place so every failure names the step, the time and the contacts the same way."""

    def __init__(
        self, scene, guards: Guards, radii: np.ndarray, energy: float, kinetic: float, run: Run
    ):
        self.scene, self.guards, self.radii, self.run = scene, guards, radii, run
        self.energy0 = energy
        on = guards.energy_growth is not None
        self.scale = energy_scale(scene, radii, kinetic) if on else 0.0
        self.previous: tuple | None = None  # (step, t, poses, velocities) before the last step
        self.moving = np.flatnonzero(~np.asarray(scene.fixed, dtype=bool))
        self.edges = FixedEdges(scene) if guards.penetration is not None else None

    def failure(self, k: int, t: float, what: str, poses, vel) -> SimulationError:
        with np.errstate(all="ignore"):
            found = self.scene.find_contacts(poses) if np.all(np.isfinite(poses)) else []
        return SimulationError(
            f"step {k} at t = {t:.6g} s {what}; contacts: {contact_names(self.scene, found)}",
            self.run,
            (poses.copy(), vel.copy()),
        )

    def penetration(self, frame: Frame | None, k: int, t: float, poses, vel) -> None:
        """Raise if the contacts at the start of step k overlap too deeply: the step before made
        them (or, at k = 0, the scene starts that way)."""
        limit = self.guards.penetration
        found = None if limit is None or frame is None else deepest_overlap(frame, self.radii)
        if found is None or found[1] <= limit:
            return
        depth, relative, contact = found
        pair = contact_names(self.scene, [contact])
        size = f"{depth:.3g} m, {relative:.3g} of the smaller body's size (limit {limit:g})"
        if self.previous is None:
            raise self.failure(k, t, f"starts with {pair} overlapping by {size}", poses, vel)
        raise self.failure(
            *self.previous[:2],
            f"left {pair} overlapping by {size}: the time step is too large",
            *self.previous[2:],
        )

    def after_step(self, k: int, t: float, state, new, energy: float, method: str) -> None:
        """Raise if step k produced a non-finite state, moved a centre of mass through a fixed
        edge or raised the energy too far."""
        if not (np.all(np.isfinite(new[0])) and np.all(np.isfinite(new[1]))):
            raise self.failure(k, t, "produced a non-finite state", *state)
        if self.edges is not None:
            start, end = state[0][self.moving, :2], new[0][self.moving, :2]
            crossed = self.edges.crossing(start, end)
            if crossed is not None:
                body, wall = (
                    self.scene.bodies[self.moving[crossed[0]]],
                    self.scene.bodies[crossed[1]],
                )
                raise self.failure(
                    k,
                    t,
                    f"moved the centre of mass of {body.name} through {wall.name} (it tunnelled): "
                    "the time step is too large",
                    *state,
                )
        if self.scale > 0:
            if energy - self.energy0 > self.guards.energy_growth * self.scale:
                raise self.failure(
                    k,
                    t,
                    f"raised the energy from {self.energy0:.6g} J at t = 0 to {energy:.6g} J, "
                    f"more than {self.guards.energy_growth:g} x the scene's energy scale "
                    f"{self.scale:.3g} J (no contact adds energy): the time step is too large "
                    f"for {method}",
                    *state,
                )
        self.previous = (k, t, *state)
