"""`simulate`: a scene run for a duration on a World, recorded step by step into a Run.

The recorded grid is t = k dt, exactly (the last step shortened so the run ends at the duration);
events located inside steps (impacts, friction transitions, a resting contact leaving its feature
for the next) are listed in ``Run.impact_times``, lift-offs in ``Run.lift_times``. Each record holds the state at
its time and the contacts resting there (with lifting ones) and their forces, as solved at the
start of the step that follows (the last record: at the final state).

Quiet steps (the same contacts, nothing located) go in stretches through one compiled loop
(runtime.step.coast), which writes their records as arrays; the run is the same, bit for bit.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from runtime.collide.contact_set import Contacts
from runtime.solve.forces import Stabilisation
from runtime.step.guards import Guards
from runtime.step.world import (
    SimulationError,
    World,
    body_masses,
    kinetic_energy,
    linear_momentum,
    mechanical_energy,
)

if TYPE_CHECKING:
    from runtime.step.coast import Stretch

_RUN_NAMES = {"loss": "impact_losses", "joints": "joint_forces"}  # the recorder's names -> Run's
_NO_JOINTS = np.zeros(0)  # a record's joint forces in a scene without joints (never written)

__all__ = [
    "Run",
    "SimulationError",
    "kinetic_energy",
    "linear_momentum",
    "mechanical_energy",
    "simulate",
]


@dataclass
class Run:
    """What a simulation recorded: NumPy arrays with one entry per recorded step (K of them),
    except the per-step contact sets, which differ in length from step to step.

    t (K,), poses and velocities (K, n, 3), energy (K,) (mechanical: kinetic + gravitational),
    momentum (K, 2), min_gap (K,) (smallest gap among the contacts found at each record's time:
    < 0 is a penetration), impact_losses (K,) (kinetic energy taken out by impacts since the
    record before; 0 at the first), impact_times (I,) (located impacts and other events), lift_times (L,)
    (located lift-offs: where a pressing contact's force reached 0 and it moved apart);
    contacts[k] (runtime.collide.contact_set.Contacts) and contact_forces[k] (N): the resting
    contacts at record k and their forces (runtime.app.contact_table gives them as one table);
    friction_forces[k] (N): their friction forces f_t along t = n turned by +90 degrees, on body 1
    (docs/conventions.md; 0 without friction).
    joint_forces (K, R) (N): the force of each joint row on its body 1, solved with the contact
    forces, and joint_names (R,) the joint of each row. A pin has two rows, the x and y of its
    force; a distance joint one, along n = (p1 - p2)/|p1 - p2| (< 0: the rod pulls, tension).
    """

    scene_name: str
    method: str
    dt: float
    body_names: list[str] = field(default_factory=list)
    t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    poses: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 3)))
    velocities: np.ndarray = field(default_factory=lambda: np.zeros((0, 0, 3)))
    energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    momentum: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    min_gap: np.ndarray = field(default_factory=lambda: np.zeros(0))
    impact_losses: np.ndarray = field(default_factory=lambda: np.zeros(0))
    impact_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    lift_times: np.ndarray = field(default_factory=lambda: np.zeros(0))
    contacts: list[Contacts] = field(default_factory=list)
    contact_forces: list[np.ndarray] = field(default_factory=list)
    friction_forces: list[np.ndarray] = field(default_factory=list)
    joint_forces: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    joint_names: list[str] = field(default_factory=list)
    rhs_evaluations: int = 0
    wall_time: float = 0.0

    @property
    def max_penetration(self) -> float:
        return max(0.0, -float(np.min(self.min_gap, initial=0.0)))

    def arrays(self) -> dict[str, np.ndarray]:
        """The run's per-record arrays (for .npz); the contacts: runtime.app.contact_table."""
        out = {
            "t": self.t,
            "poses": self.poses,
            "velocities": self.velocities,
            "energy": self.energy,
            "momentum": self.momentum,
            "min_gap": self.min_gap,
            "impact_losses": self.impact_losses,
            "impact_times": self.impact_times,
            "lift_times": self.lift_times,
            "total_contact_force": np.array([float(np.sum(f)) for f in self.contact_forces]),
        }
        return out


class _Recorder:
    """Lists while running, blocks of arrays from stretches of coasted steps (runtime.step.
    coast); a Run of arrays at the end (also of a failed run)."""

    FIELDS = ("t", "poses", "velocities", "energy", "momentum", "min_gap", "loss", "joints")

    def __init__(self, scene, method: str, dt: float, joint_names=()) -> None:
        self.run = Run(scene.name, method, dt, [b.name for b in scene.bodies])
        self.run.joint_names = list(joint_names)
        self.n = len(scene.bodies)
        self.scene = scene
        self.masses = body_masses(scene)
        self.rows: dict[str, list] = {k: [] for k in self.FIELDS}  # records one by one
        self.blocks: list[dict[str, np.ndarray]] = []  # ... and before them, as arrays

    def add(self, state: tuple, frame, recorded, forces, tangent, loss: float, joints=None) -> None:
        """One record: ``state`` = (t, poses, velocities, energy) and the frame at that time;
        ``tangent``: the friction forces, None without a friction stage; ``joints``: the joint
        rows' forces, None without joints."""
        t, poses, velocities, energy = state
        r = self.rows
        r["t"].append(t)
        r["poses"].append(poses.copy())
        r["velocities"].append(velocities.copy())
        r["energy"].append(energy)
        r["momentum"].append(linear_momentum(self.scene, velocities, self.masses))
        r["min_gap"].append(frame.min_gap)
        r["loss"].append(loss)
        rows = len(self.run.joint_names)
        r["joints"].append(_NO_JOINTS if not rows else
                           np.full(rows, np.nan) if joints is None else joints[:rows])  # fmt: skip
        every = len(recorded) == len(frame.contacts)  # recorded: sorted, distinct indices
        contacts = frame.contacts if every else frame.contacts.take(recorded)
        friction = None if tangent is None else np.asarray(tangent, dtype=float)
        self._contacts(contacts, np.asarray(forces, dtype=float), friction)

    def add_coasted(self, stretch: Stretch, picks: list[int], losses: list[float]) -> None:
        """The records ``picks`` of a stretch of coasted steps, with the impact losses since
        the record before each (a stretch has no joints)."""
        self._flush()
        s = stretch
        block = {"t": s.t, "poses": s.poses, "velocities": s.velocities, "energy": s.energy,
                 "momentum": s.momentum, "min_gap": s.min_gap}  # fmt: skip
        block = {name: values[picks] for name, values in block.items()}
        block["loss"] = np.asarray(losses, dtype=float)
        block["joints"] = np.zeros((len(picks), len(self.run.joint_names)))
        self.blocks.append(block)
        for i in picks:
            self._contacts(*s.contacts(i))

    def _contacts(self, contacts, forces: np.ndarray, friction) -> None:
        self.run.contacts.append(contacts)
        self.run.contact_forces.append(forces)
        self.run.friction_forces.append(np.zeros(len(forces)) if friction is None else friction)

    def _flush(self) -> None:
        """The records one by one so far as a block."""
        if self.rows["t"]:
            self.blocks.append({k: np.asarray(v, dtype=float) for k, v in self.rows.items()})
            self.rows = {k: [] for k in self.FIELDS}

    def finish(self, world: World, wall: float) -> Run:
        self._flush()
        run, n, rows = self.run, self.n, len(self.run.joint_names)
        tail = {"poses": (n, 3), "velocities": (n, 3), "momentum": (2,), "joints": (rows,)}
        for k in self.FIELDS:
            shape = tail.get(k, ())
            values = [b[k].reshape(len(b["t"]), *shape) for b in self.blocks]
            setattr(run, _RUN_NAMES.get(k, k),
                    np.concatenate(values) if values else np.zeros((0, *shape)))  # fmt: skip
        run.impact_times = np.asarray(world.impact_times, dtype=float)
        run.lift_times = np.asarray(world.lift_times, dtype=float)
        run.rhs_evaluations = world.stepper.evaluations
        run.wall_time = wall
        return run


def _check_arguments(duration: float, dt: float, record_every: int) -> None:
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be a finite number > 0, got {dt}")
    if not (math.isfinite(duration) and duration >= 0):
        raise ValueError(f"duration must be a finite number >= 0, got {duration}")
    if not (isinstance(record_every, int) and record_every >= 1):
        raise ValueError(f"record_every must be an integer >= 1, got {record_every!r}")


def _grid(k: int, steps: int, dt: float, duration: float) -> float:
    """The time of record k: k dt, and the duration at the last. A step goes from the World's
    time to the next grid time, so the World's time is the grid's exactly (for k >= 1 the
    difference of two grid times is exact, Sterbenz) instead of a sum of k rounded steps, and
    the run ends at the duration exactly."""
    return duration if k >= steps else k * dt


def _coaster(world: World):
    """The compiled loop over the World's quiet steps (runtime.step.coast), or None where its
    steps cannot coast (imported here: it compiles in every contact case, as the compiled
    path does, and a scene on the general path imports only its own cases' kernels)."""
    if not (world.stepper.compiled or world.stepper.compiled_friction):
        return None
    from runtime.step.coast import Coaster

    return Coaster(world) if Coaster.applies(world) else None


def simulate(
    scene,
    duration: float | None = None,
    dt: float | None = None,
    method: str | None = None,
    *,
    stabilisation: Stabilisation | None = None,
    resting_speed: float | None = None,
    record_every: int = 1,
    progress: Callable[[float], None] | None = None,
    guards: Guards | None = None,
) -> Run:
    """Run ``scene`` for ``duration`` seconds in steps of ``dt`` (defaults from the scene's
    [simulation] table; stabilisation too). The last step is shortened when the duration is not
    a whole number of steps, so the run ends at the duration. ``progress(fraction)`` is called
    as the run advances: after each step, or once after a stretch of coasted steps.

    Raises SimulationError when a step fails (the contact solver, a non-finite state) or a
    guard trips (runtime.step.guards: penetration, tunnelling, energy growth); its ``run``
    holds what was recorded up to the last good step and its ``state`` the state before the
    failing step.
    """
    defaults = scene.simulation
    duration = defaults.duration if duration is None else float(duration)
    dt = defaults.dt if dt is None else float(dt)
    _check_arguments(duration, dt, record_every)
    options = {} if resting_speed is None else {"resting_speed": float(resting_speed)}
    world = World(scene, method, stabilisation=stabilisation, guards=guards, **options)
    links = world.stepper.links
    joints = links.joints if links is not None else None
    recorder = _Recorder(scene, world.method, dt, [] if joints is None else joints.names)
    steps = max(0, math.ceil(duration / dt - 1e-9))
    start = time.perf_counter()
    lost = 0.0  # at impacts since the last record
    coaster = _coaster(world)
    k, quiet = 0, False
    try:
        while k < steps:
            if coaster is not None and coaster.ready(quiet):  # quiet steps in one compiled loop
                ahead = np.arange(k + 1, min(k + coaster.batch, steps) + 1)
                stretch = coaster.run(np.where(ahead >= steps, duration, ahead * dt))
                if stretch is not None:
                    picks, losses = [], []
                    for i, loss in enumerate(stretch.impact_loss.tolist()):
                        if (k + i) % record_every == 0:
                            picks.append(i)
                            losses.append(lost)
                            lost = 0.0
                        lost += loss
                    recorder.add_coasted(stretch, picks, losses)
                    k, quiet = k + len(stretch), len(stretch) == len(ahead)
                    if progress is not None:
                        progress(min(1.0, k / steps))
                    continue
            h = _grid(k + 1, steps, dt, duration) - world.t
            before = (world.t, world.poses, world.velocities, world.energy())
            report = world.step(h)
            if k % record_every == 0:
                recorder.add(
                    before,
                    report.frame,
                    report.recorded,
                    report.forces,
                    report.tangent_forces,
                    lost,
                    report.joint_forces,
                )
                lost = 0.0
            lost += report.impact_loss
            k, quiet = k + 1, report.quiet
            if progress is not None:
                progress(min(1.0, k / steps))
        frame, solution = world.final_frame()
        state = (world.t, world.poses, world.velocities, world.energy())
        recorder.add(
            state, frame, frame.resting, solution.forces, solution.tangent_forces, lost,
            solution.joint_forces,
        )  # fmt: skip
    except SimulationError as exc:
        exc.run = recorder.finish(world, time.perf_counter() - start)
        raise
    return recorder.finish(world, time.perf_counter() - start)
