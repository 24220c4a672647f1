"""Scenes: the bodies, their initial state and the simulation defaults, read from TOML or a dict.

The engine wants arrays in the conventions of docs/conventions.md (pose of the centre of mass,
geometry in body coordinates, inverse masses 0 for fixed bodies); people want to write a shape
in its own coordinates and place it.  This module is the one place that converts between the
two, and it refuses bad input with a message naming the file, the body and the field (see
docs/scene-format.md), so that a typo never surfaces later as a NaN or a NumPy warning.
"""

from __future__ import annotations

import copy
import math
import re
import tomllib
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from runtime import contacts as _contacts
from runtime import narrowphase as _narrowphase
from runtime.scene_overlap import deepest_overlap
from runtime.scene_validation import (
    SCENE_KEYS,
    SIMULATION_KEYS,
    TOP_LEVEL_KEYS,
    SceneError,
    Table,
    body_label,
    read_bodies,
    read_simulation,
)

__all__ = ["Body", "Scene", "SceneError", "SimulationDefaults", "load_scene", "scene_from_dict"]

Vec2 = tuple[float, float]


def _rotate(angle: float, v: Sequence[float]) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _pair(v: Sequence[float]) -> Vec2:
    return (float(v[0]), float(v[1]))


@dataclass
class Body:
    """A rigid body in the conventions of docs/conventions.md.

    ``shape`` is in body coordinates (origin at the centre of mass for a moving body), and
    ``position``/``velocity`` are those of the centre of mass.  ``origin`` is where the shape's
    own origin (the one it was written in) sits in body coordinates.  A fixed body has infinite
    mass and inertia and is not re-centred: its pose places the shape's own origin.
    Build a body from a shape in its own coordinates with :meth:`Body.from_shape`.
    """

    name: str
    shape: Any
    mass: float = math.inf
    inertia: float | None = None
    position: Vec2 = (0.0, 0.0)
    angle: float = 0.0
    velocity: Vec2 = (0.0, 0.0)
    angular_velocity: float = 0.0
    fixed: bool = False
    restitution: float = 0.0
    origin: Vec2 = (0.0, 0.0)

    def __post_init__(self) -> None:
        self.position = _pair(self.position)
        self.velocity = _pair(self.velocity)
        self.origin = _pair(self.origin)
        self.angle = float(self.angle)
        self.angular_velocity = float(self.angular_velocity)
        if self.fixed:
            if self.velocity != (0.0, 0.0) or self.angular_velocity != 0.0:
                raise ValueError(f"fixed body {self.name!r} must have zero velocity")
            self.mass = math.inf
            self.inertia = math.inf
            return
        self.mass = float(self.mass)
        if not (math.isfinite(self.mass) and self.mass > 0):
            raise ValueError(f"body {self.name!r}: mass must be finite and > 0, got {self.mass}")
        if self.inertia is None:
            self.inertia = self.mass * float(self.shape.second_moment) / float(self.shape.area)
        self.inertia = float(self.inertia)
        if not (math.isfinite(self.inertia) and self.inertia > 0):
            raise ValueError(
                f"body {self.name!r}: inertia must be finite and > 0, got {self.inertia}"
            )

    @classmethod
    def from_shape(
        cls,
        name: str,
        shape: Any,
        *,
        mass: float | None = None,
        density: float | None = None,
        inertia: float | None = None,
        position: Sequence[float] = (0.0, 0.0),
        angle: float = 0.0,
        velocity: Sequence[float] = (0.0, 0.0),
        angular_velocity: float = 0.0,
        fixed: bool = False,
        restitution: float = 0.0,
    ) -> Body:
        """A body from a shape in its own coordinates.

        ``position`` and ``velocity`` are those of the shape's own origin (the point (0, 0) of
        the coordinates the shape was written in); the centre-of-mass state is derived.  A
        moving body needs ``mass`` or ``density``; ``inertia`` defaults to density times the
        shape's second moment.  A fixed body keeps the shape's own coordinates (no mass).
        Unlike :func:`scene_from_dict`, this raises a plain ValueError and checks no overlaps.
        """
        if fixed:
            return cls(
                name, shape, position=position, angle=angle, fixed=True, restitution=restitution
            )
        if (mass is None) == (density is None):
            raise ValueError(f"body {name!r}: give exactly one of mass and density")
        centred, offset = shape.centred()
        if mass is None:
            mass = float(density) * float(centred.area)
        lever = _rotate(angle, offset)  # from the shape origin to the centre of mass, world axes
        com = np.asarray(position, dtype=float) + lever
        com_velocity = np.asarray(velocity, dtype=float) + angular_velocity * np.array(
            [-lever[1], lever[0]]
        )
        return cls(
            name,
            centred,
            mass=mass,
            inertia=inertia,
            position=_pair(com),
            angle=angle,
            velocity=_pair(com_velocity),
            angular_velocity=angular_velocity,
            restitution=restitution,
            origin=(0.0 - float(offset[0]), 0.0 - float(offset[1])),
        )

    @property
    def inverse_mass(self) -> float:
        return 0.0 if self.fixed else 1.0 / self.mass

    @property
    def inverse_inertia(self) -> float:
        return 0.0 if self.fixed else 1.0 / float(self.inertia)

    @property
    def pose(self) -> np.ndarray:
        """``(x, y, th)`` of the centre of mass."""
        return np.array([*self.position, self.angle])

    @property
    def twist(self) -> np.ndarray:
        """``(vx, vy, w)`` of the centre of mass."""
        return np.array([*self.velocity, self.angular_velocity])

    def origin_position(self) -> np.ndarray:
        """World position of the shape's own origin (what a scene file's ``position`` gives)."""
        return np.asarray(self.position) + _rotate(self.angle, self.origin)


@dataclass(frozen=True)
class SimulationDefaults:
    """The ``[simulation]`` table: what the scene should be run with unless told otherwise."""

    duration: float = 2.0
    dt: float = 1e-3
    method: str = "rk4"
    stabilisation: bool = False


@dataclass
class Scene:
    """Bodies, gravity, contact tolerances and simulation defaults."""

    name: str
    bodies: list[Body]
    gravity: Vec2 = (0.0, -9.81)
    contact_tolerance: float = 1e-4
    overlap_tolerance: float = 1e-9
    simulation: SimulationDefaults = field(default_factory=SimulationDefaults)
    source: str = "<dict>"
    description: str = ""

    @property
    def shapes(self) -> list[Any]:
        return [b.shape for b in self.bodies]

    @property
    def fixed(self) -> list[bool]:
        return [b.fixed for b in self.bodies]

    @property
    def names(self) -> list[str]:
        return [b.name for b in self.bodies]

    def index(self, name: str) -> int:
        """Index of the body called ``name``."""
        for i, body in enumerate(self.bodies):
            if body.name == name:
                return i
        raise KeyError(f"{self.source}: no body named {name!r}; bodies: {self.names}")

    def body(self, name: str) -> Body:
        return self.bodies[self.index(name)]

    def poses(self) -> np.ndarray:
        """(n, 3) array of ``(x, y, th)`` of the centres of mass."""
        return np.array([b.pose for b in self.bodies], dtype=float).reshape(-1, 3)

    def velocities(self) -> np.ndarray:
        """(n, 3) array of ``(vx, vy, w)``."""
        return np.array([b.twist for b in self.bodies], dtype=float).reshape(-1, 3)

    @property
    def inverse_masses(self) -> np.ndarray:
        """(n, 3) array ``(1/m, 1/m, 1/I)`` per body; zeros for fixed bodies."""
        rows = [(b.inverse_mass, b.inverse_mass, b.inverse_inertia) for b in self.bodies]
        return np.array(rows, dtype=float).reshape(-1, 3)

    def contact_cases(self) -> set[str]:
        """The contact cases (generated kernels) this scene can produce."""
        return set(_contacts.possible_cases(self.shapes, self.fixed))

    def find_contacts(
        self, poses: np.ndarray | None = None, tolerance: float | None = None
    ) -> list[Any]:
        """Contacts with gap below ``tolerance`` (default the scene's) at ``poses`` (default
        the initial poses)."""
        return _contacts.find_contacts(
            self.shapes,
            self.poses() if poses is None else poses,
            self.fixed,
            self.contact_tolerance if tolerance is None else tolerance,
        )

    def copy(self) -> Scene:
        return copy.deepcopy(self)

    def with_simulation(self, **changes: Any) -> Scene:
        """A copy with some simulation defaults changed, e.g. ``with_simulation(dt=1e-4)``."""
        return replace(self.copy(), simulation=replace(self.simulation, **changes))

    def shifted(self, dx: float, dy: float) -> Scene:
        """A copy with every body (fixed ones too) translated by ``(dx, dy)``."""
        moved = self.copy()
        for body in moved.bodies:
            body.position = (body.position[0] + float(dx), body.position[1] + float(dy))
        return moved


# -- reading ---------------------------------------------------------------------------------


def load_scene(path: str | Path) -> Scene:
    """Read a scene file (TOML, format in docs/scene-format.md); raise SceneError if invalid."""
    source = str(path)
    try:
        text = Path(path).read_bytes().decode("utf-8")
    except FileNotFoundError:
        raise SceneError(f"{source}: file not found") from None
    except UnicodeDecodeError as exc:
        raise SceneError(f"{source}: not UTF-8 text (byte {exc.start})") from None
    except OSError as exc:
        raise SceneError(f"{source}: cannot read the file: {exc.strerror or exc}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = str(exc)
        match = re.fullmatch(r"(.*) \(at line (\d+), column (\d+)\)", message, re.S)
        if match:
            message = f"line {match[2]}, column {match[3]}: TOML syntax error: {match[1]}"
        else:
            message = f"TOML syntax error: {message}"
        raise SceneError(f"{source}: {message}") from None
    return scene_from_dict(data, source=source, default_name=Path(path).stem)


def scene_from_dict(
    data: Mapping[str, Any], source: str = "<dict>", *, default_name: str = "scene"
) -> Scene:
    """Build and check a scene from the same structure as a scene file, e.g.
    ``{"scene": {...}, "simulation": {...}, "body": [{...}, ...]}``."""
    top = Table(data, source, "", field="the scene")
    for key in data:
        for table, keys in (("scene", SCENE_KEYS), ("simulation", SIMULATION_KEYS)):
            if key in keys:
                top.fail(str(key), f"belongs in the [{table}] table; put it after [{table}]")
    top.check_keys(TOP_LEVEL_KEYS)
    scene_table = Table(data.get("scene", {}), source, "[scene]", field="scene")
    scene_table.check_keys(SCENE_KEYS)
    simulation = SimulationDefaults(
        **read_simulation(data.get("simulation", {}), source, SimulationDefaults.duration)
    )
    bodies = []
    for index, spec in enumerate(read_bodies(top)):
        try:
            bodies.append(Body.from_shape(**spec))
        except ValueError as exc:  # e.g. an inertia that comes out non-finite
            key = "inertia" if "inertia" in str(exc) else "mass"
            Table({}, source, body_label(index, spec["name"])).fail(key, str(exc))
    scene = Scene(
        name=scene_table.string("name", default_name),
        description=scene_table.string("description", ""),
        bodies=bodies,
        gravity=scene_table.vector("gravity", (0.0, -9.81)),
        contact_tolerance=scene_table.number("contact_tolerance", 1e-4, check="positive"),
        overlap_tolerance=scene_table.number("overlap_tolerance", 1e-9, check="positive"),
        simulation=simulation,
        source=source,
    )
    _check_tolerances(scene, scene_table)
    _check_overlaps(scene)
    return scene


# A tolerance may be at most this fraction of the half-width of the thinnest moving body.
TOLERANCE_FRACTION = 0.5


def _check_tolerances(scene: Scene, table: Table) -> None:
    """The contact and overlap tolerances are absolute lengths (defaults 1e-4 m and 1e-9 m):
    against a small body they stop being small.  A contact tolerance near a body's size holds
    resting bodies visibly apart (a resting contact is kept up to that gap), and an overlap
    tolerance near it lets overlapping bodies start; both are refused, naming the body."""
    moving = [(k, b) for k, b in enumerate(scene.bodies) if not b.fixed]
    if not moving:
        return
    widths = [(float(_narrowphase.table(b.shape).half_width), k) for k, b in moving]
    half, k = min(widths)
    limit = TOLERANCE_FRACTION * half
    label = body_label(k, scene.bodies[k].name)
    for key, value, effect in (
        ("contact_tolerance", scene.contact_tolerance, "would hold resting bodies that far apart"),
        (
            "overlap_tolerance",
            scene.overlap_tolerance,
            "would let bodies start that deep inside each other",
        ),  # fmt: skip
    ):
        if value > limit:
            given = "" if table.has(key) else " (the default)"
            table.fail(
                key,
                f"{value:g} m{given} is too large for {label}, half-width {half:.6g} m: it "
                f"{effect}; set it to at most {limit:.3g} m (half that half-width)",
            )


def _check_overlaps(scene: Scene) -> None:
    """Refuse bodies that overlap at t = 0 by more than ``scene.overlap_tolerance``: first the
    contacts the engine would see, then deep overlaps that the contact finder leaves out."""
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        found = scene.find_contacts()
        deep = deepest_overlap(scene.shapes, scene.poses(), scene.fixed, scene.overlap_tolerance)
    for contact in found:
        gap = float(contact.gap)
        if gap < -scene.overlap_tolerance or not math.isfinite(gap):
            amount = f"by {-gap:.6g} m" if math.isfinite(gap) else "(coincident features)"
            detail = f"{contact.case} contact at {_point(contact.point)}"
            _overlap_error(scene, int(contact.body1), int(contact.body2), amount, detail)
    if deep is not None:
        i, j, depth, point = deep
        names = scene.bodies[i].name, scene.bodies[j].name
        detail = f"the point {_point(point)} of {names[0]!r} lies inside {names[1]!r}"
        _overlap_error(scene, i, j, f"by at least {depth:.6g} m", detail)


def _point(p: Sequence[float]) -> str:
    return f"({float(p[0]):.6g}, {float(p[1]):.6g})"


def _overlap_error(scene: Scene, i: int, j: int, amount: str, detail: str) -> None:
    where = " and ".join(body_label(k, scene.bodies[k].name) for k in sorted((i, j)))
    moving = j if scene.bodies[i].fixed else i
    message = f"overlap {amount} at t = 0 ({detail}); move {scene.bodies[moving].name!r} away"
    Table({}, scene.source, where).fail("position", message)
