"""Scenes: the bodies, their initial state and the simulation defaults.

The engine wants arrays in the conventions of docs/conventions.md (pose of the centre of mass,
geometry in body coordinates, inverse masses 0 for fixed bodies); people want to write a shape
in its own coordinates and place it.  :class:`Body` converts between the two; reading and
checking scene files is runtime.io.scene_file.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from runtime.collide import contacts as _contacts
from runtime.collide.contact_set import Contacts
from runtime.collide.finder import ContactFinder
from runtime.model.links import WORLD, Joint, Spring
from runtime.model.regions import overlap_depth
from runtime.settings import JOIN_EPS

__all__ = ["Body", "Scene", "SimulationDefaults", "center_of_mass_error"]

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
    linear_damping: float = 0.0  # 1/s: force -k m v
    angular_damping: float = 0.0  # 1/s: torque -k I w
    friction: float = 0.0  # Coulomb coefficient mu >= 0 (sticking and sliding), fixed bodies too

    def __post_init__(self) -> None:
        self.position = _pair(self.position)
        self.velocity = _pair(self.velocity)
        self.origin = _pair(self.origin)
        self.angle = float(self.angle)
        self.angular_velocity = float(self.angular_velocity)
        self.friction = float(self.friction)
        if not (math.isfinite(self.friction) and self.friction >= 0):
            raise ValueError(
                f"body {self.name!r}: friction must be finite and >= 0, got {self.friction}"
            )
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
        center_of_mass: Sequence[float] | None = None,
        linear_damping: float = 0.0,
        angular_damping: float = 0.0,
        friction: float = 0.0,
    ) -> Body:
        """A body from a shape in its own coordinates.

        ``position`` and ``velocity`` are those of the shape's own origin (the point (0, 0) of
        the coordinates the shape was written in); the centre-of-mass state is derived.  A
        moving body needs ``mass`` or ``density``; ``inertia`` defaults to density times the
        shape's second moment.  ``center_of_mass`` (shape coordinates, default the centroid)
        places the centre of mass elsewhere, e.g. for a weighted body; it must lie in the
        shape's convex hull (no mass on the shape can put it outside), and the default inertia
        is then the shape's about that point (parallel-axis theorem, ``m (J_c / A + |d|^2)``).
        A fixed body keeps the shape's own coordinates (no mass).  Unlike
        :func:`scene_from_dict`, this raises a plain ValueError and checks no overlaps.
        """
        if fixed:
            if center_of_mass is not None:
                raise ValueError(
                    f"body {name!r}: a fixed body has no center_of_mass (its mass "
                    "is infinite); remove it"
                )
            return cls(
                name, shape, position=position, angle=angle, fixed=True,
                restitution=restitution, friction=friction,
            )  # fmt: skip
        if (mass is None) == (density is None):
            raise ValueError(f"body {name!r}: give exactly one of mass and density")
        problem = None if center_of_mass is None else center_of_mass_error(shape, center_of_mass)
        if problem:
            raise ValueError(f"body {name!r}: center_of_mass {problem}")
        centred, offset = shape.centred(center_of_mass)
        if mass is None:
            mass = float(density) * float(centred.area)
        if inertia is None and center_of_mass is not None:
            inertia = float(mass) * shape.second_moment_about(offset) / float(shape.area)
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
            linear_damping=float(linear_damping),
            angular_damping=float(angular_damping),
            friction=friction,
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


def center_of_mass_error(shape: Any, point: Sequence[float]) -> str | None:
    """What is wrong with a centre of mass at ``point`` (shape coordinates), or None: outside
    the shape's convex hull no positive mass on the shape can put it (a point written in world
    coordinates, or a typo)."""
    x, y = float(point[0]), float(point[1])
    depth = overlap_depth(shape, (x, y)) if math.isfinite(x) and math.isfinite(y) else -math.inf
    if depth >= -JOIN_EPS * shape.bounding_radius:
        return None
    return (
        f"({x:g}, {y:g}) is {-depth:.3g} m outside the shape's convex hull, where no mass on "
        "the shape can put it; give it in the shape's own coordinates"
    )


@dataclass(frozen=True)
class SimulationDefaults:
    """The ``[simulation]`` table: what the scene should be run with unless told otherwise."""

    duration: float = 2.0
    dt: float = 1e-3
    method: str = "rk4"
    stabilisation: bool = False


@dataclass
class Scene:
    """Bodies, gravity, contact tolerances and simulation defaults; ``groups``: a collision
    group per body or None (runtime.collide.finder.ContactFinder: bodies of two different
    groups never touch, group -1 touches all; how the copies of an ensemble share a scene)."""

    name: str
    bodies: list[Body]
    gravity: Vec2 = (0.0, -9.81)
    contact_tolerance: float = 1e-4
    overlap_tolerance: float = 1e-9
    simulation: SimulationDefaults = field(default_factory=SimulationDefaults)
    source: str = "<dict>"
    description: str = ""
    groups: list[int] | None = None
    joints: list[Joint] = field(default_factory=list)
    springs: list[Spring] = field(default_factory=list)
    mutual_gravity: float = 0.0

    @property
    def joined_pairs(self) -> tuple[tuple[int, int], ...]:
        """The pairs of moving bodies a joint links, (lower, higher) index: they never touch
        each other (as Box2D's joints by default), so a pinned chain's links may overlap."""
        pairs = {
            (min(j.body1, j.body2), max(j.body1, j.body2)) for j in self.joints if j.body2 >= 0
        }
        return tuple(sorted(pairs))

    @property
    def linked(self) -> bool:
        """Whether anything but gravity and contacts acts: joints, springs, damping or mutual
        gravity (the engine then takes the general path, runtime.solve.linked_forces)."""
        return bool(self.joints or self.springs or self.mutual_gravity or self.damped)

    @property
    def damped(self) -> bool:
        """Whether a moving body has linear or angular damping."""
        return any(b.linear_damping or b.angular_damping for b in self.bodies if not b.fixed)

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

    @property
    def friction(self) -> np.ndarray:
        """(n,) Coulomb coefficient per body; a contact's is sqrt(mu1 mu2)."""
        return np.array([b.friction for b in self.bodies], dtype=float)

    def contact_cases(self) -> set[str]:
        """The contact cases (generated kernels) this scene can produce."""
        return set(_contacts.possible_cases(self.shapes, self.fixed))

    def contact_finder(self) -> ContactFinder:
        """The contact finder of the bodies as they are now (kept while they stay the same)."""
        return _contacts.finder_for(self.shapes, self.fixed, self.groups, self.joined_pairs)

    def contacts(
        self,
        poses: np.ndarray | None = None,
        tolerance: float | None = None,
        margins: np.ndarray | None = None,
    ) -> Contacts:
        """Contacts with gap below ``tolerance`` (default the scene's contact tolerance; plus
        ``margins[i] + margins[j]`` for bodies i, j if given) at ``poses`` (default the initial
        poses)."""
        return self.contact_finder().find(
            self.poses() if poses is None else poses,
            self.contact_tolerance if tolerance is None else tolerance,
            margins,
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
        moved.joints = [_shift_world_end(j, dx, dy) for j in moved.joints]
        moved.springs = [_shift_world_end(s, dx, dy) for s in moved.springs]
        return moved


def _shift_world_end(link, dx: float, dy: float):
    """A link with its world anchor (if any) translated by (dx, dy)."""
    if link.body2 != WORLD:
        return link
    return replace(link, anchor2=(link.anchor2[0] + float(dx), link.anchor2[1] + float(dy)))
