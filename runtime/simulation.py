"""The time-stepping driver: contacts, impacts, contact forces and integration, step by step.

Each step: find the contacts at the current poses (broad + narrow phase); resolve impacts at
touching contacts that approach faster than the resting speed; take the contacts that touch and
neither approach nor separate as the resting set; integrate one step with the forces of the resting
set re-solved at every stage (Euler, midpoint, RK4, or scipy's adaptive RK45/DOP853 over the step).
A resting contact is held at d'' >= 0 with d = 0 kept exactly by the exact derived b term (no
artificial positive gap); a contact whose force would be negative leaves the clamped set.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from runtime.collisions import impact_velocities
from runtime.dynamics import ContactDynamics, Stabilisation
from runtime.integrators import ADAPTIVE, FIXED_STEP, METHODS
from runtime.lcp import ContactSolverError


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
    min_gap: list[float] = field(default_factory=list)
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


def mechanical_energy(scene, poses: np.ndarray, velocities: np.ndarray) -> float:
    """Kinetic + gravitational potential energy of the moving bodies."""
    total = 0.0
    g = np.asarray(scene.gravity)
    for body, q, v in zip(scene.bodies, poses, velocities, strict=True):
        if body.fixed:
            continue
        total += 0.5 * body.mass * (v[0] ** 2 + v[1] ** 2) + 0.5 * body.inertia * v[2] ** 2
        total -= body.mass * float(g @ q[:2])
    return total


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
    """Steps one scene; `simulate` is the one-call front end."""

    def __init__(
        self,
        scene,
        method: str = "rk4",
        stabilisation: Stabilisation | None = None,
        resting_speed: float = 1e-3,
        rtol: float = 1e-9,
        atol: float = 1e-12,
    ) -> None:
        self.scene = scene
        self.method = method
        self.dynamics = ContactDynamics(scene, stabilisation)
        self.resting_speed = resting_speed
        self.rtol, self.atol = rtol, atol
        self.n = len(scene.bodies)
        self.evaluations = 0

    def _rhs(self, resting: list) -> Callable[[np.ndarray], np.ndarray]:
        n = self.n

        def rhs(y: np.ndarray) -> np.ndarray:
            self.evaluations += 1
            poses, vel = y[: 3 * n].reshape(n, 3), y[3 * n :].reshape(n, 3)
            acc = self.dynamics.solve(resting, poses, vel).accelerations
            return np.concatenate([vel.ravel(), acc.ravel()])

        return rhs

    def classify(self, poses: np.ndarray, velocities: np.ndarray):
        """Contacts now, after impacts: (resting contacts, velocities, all touching contacts)."""
        contacts = self.scene.find_contacts(poses)
        if not contacts:
            return [], velocities, contacts
        rows = self.dynamics.rows(contacts, poses, velocities)
        if np.any(rows.gap_velocity < -self.resting_speed):
            velocities = impact_velocities(
                self.dynamics, contacts, rows, velocities, self.resting_speed
            )
            rows = self.dynamics.rows(contacts, poses, velocities)
        resting = [
            c
            for c, dv in zip(contacts, rows.gap_velocity, strict=True)
            if abs(dv) <= self.resting_speed
        ]
        return resting, velocities, contacts

    def step(self, poses: np.ndarray, velocities: np.ndarray, dt: float):
        """One step from (poses, velocities): returns (poses, velocities, resting, forces)."""
        resting, velocities, _ = self.classify(poses, velocities)
        solution = self.dynamics.solve(resting, poses, velocities)
        y = np.concatenate([poses.ravel(), velocities.ravel()])
        rhs = self._rhs(resting)
        if self.method in FIXED_STEP:
            k1 = np.concatenate([velocities.ravel(), solution.accelerations.ravel()])
            y = FIXED_STEP[self.method](rhs, y, dt, k1)
        else:
            from scipy.integrate import solve_ivp  # imported on use: it costs ~1 s to import

            sol = solve_ivp(
                lambda _t, yy: rhs(yy),
                (0.0, dt),
                y,
                method=ADAPTIVE[self.method],
                rtol=self.rtol,
                atol=self.atol,
            )
            if not sol.success:
                raise RuntimeError(f"solve_ivp failed: {sol.message}")
            y = sol.y[:, -1]
        n = self.n
        return y[: 3 * n].reshape(n, 3), y[3 * n :].reshape(n, 3), resting, solution


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
) -> Run:
    """Run `scene` for `duration` seconds (defaults from the scene's [simulation] table)."""
    defaults = scene.simulation
    duration = defaults.duration if duration is None else float(duration)
    dt = defaults.dt if dt is None else float(dt)
    method = (defaults.method if method is None else method).lower()
    _check_arguments(duration, dt, method)
    sim = Simulator(scene, method, stabilisation, resting_speed, rtol, atol)
    run = Run(scene.name, method, dt)
    poses, vel = scene.poses(), scene.velocities()
    steps = int(round(duration / dt))
    start = time.perf_counter()
    t = 0.0
    for k in range(steps + 1):
        try:
            if k == steps:
                resting, vel, _ = sim.classify(poses, vel)
                solution = sim.dynamics.solve(resting, poses, vel)
                new = None
            else:
                new_poses, new_vel, resting, solution = sim.step(poses, vel, dt)
                new = (new_poses, new_vel)
        except (ContactSolverError, RuntimeError, FloatingPointError) as exc:
            names = sorted(
                {
                    f"{scene.bodies[c.body1].name}/{scene.bodies[c.body2].name}"
                    for c in sim.scene.find_contacts(poses)
                }
            )
            raise SimulationError(
                f"step {k} at t = {t:.6g} s failed ({exc}); contacts: {', '.join(names) or 'none'}",
                run,
                (poses.copy(), vel.copy()),
            ) from exc
        if k % record_every == 0 or k == steps:
            run.t.append(t)
            run.poses.append(poses.copy())
            run.velocities.append(vel.copy())
            run.energy.append(mechanical_energy(scene, poses, vel))
            run.momentum.append(linear_momentum(scene, vel))
            run.contacts.append(resting)
            run.contact_forces.append(solution.forces)
            gaps = solution.rows.gap if solution.rows is not None else []
            run.min_gap.append(float(np.min(gaps)) if len(gaps) else np.inf)
        if new is None:
            break
        if not (np.all(np.isfinite(new[0])) and np.all(np.isfinite(new[1]))):
            raise SimulationError(
                f"step {k} at t = {t:.6g} s produced a non-finite state",
                run,
                (poses.copy(), vel.copy()),
            )
        poses, vel = new
        t = (k + 1) * dt
        if progress is not None:
            progress(t / duration if duration else 1.0)
    run.rhs_evaluations = sim.evaluations
    run.wall_time = time.perf_counter() - start
    return run
