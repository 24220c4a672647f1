"""What differs between the copies of an ensemble: per-copy body fields and gravity, checked.

Why: an ensemble (runtime.step.ensemble) runs N copies of one scene that differ in a few
numbers -- a start angle, a restitution, gravity. They are given as a mapping from
``"<body name>.<field>"`` (or ``"scene.gravity"``) to an array whose first axis is N, in the
scene file's terms (docs/scene-format.md): ``position`` and ``velocity`` are those of the shape's
own origin, so a copy equals the scene file with those numbers changed. A vector field may be
given by component, ``"disc.position[0]"``, the other component keeping the scene's value.
Every key and value is checked here with a one-line message naming the key (and the copy).
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass, replace

import numpy as np

from runtime.io.scene_validation import reduced_angle
from runtime.model.scene import Body
from runtime.settings import LARGEST, MAX_ANGLE, SMALLEST

FIELDS = {
    "position": 2,
    "velocity": 2,
    "angle": 1,
    "angular_velocity": 1,
    "mass": 1,
    "restitution": 1,
    "friction": 1,
}
FIXED_FIELDS = ("position", "angle", "restitution", "friction")  # no velocity or mass
MOTION = ("position", "velocity", "angle", "angular_velocity")
_KEY = re.compile(r"(?P<body>.+)\.(?P<field>\w+)(\[(?P<component>\d+)\])?")


class VariationError(ValueError):
    """A bad variation (one line, naming the key)."""


@dataclass(frozen=True)
class Variations:
    """N copies' values: ``bodies[i][field]`` for template body i ((N,) or (N, 2), scene file
    terms), ``gravity`` (N, 2) or None; ``columns``: each key as given with its (N,) or (N, 2)
    values (what a sweep's table lists)."""

    copies: int
    bodies: dict[int, dict[str, np.ndarray]]
    gravity: np.ndarray | None
    columns: dict[str, np.ndarray]

    def body(self, template: Body, index: int, copy: int, name: str) -> Body:
        """Template body ``index`` as copy ``copy`` has it, named ``name``."""
        values = {field: v[copy] for field, v in self.bodies.get(index, {}).items()}
        return varied_body(template, values, name)


def file_values(body: Body) -> dict[str, np.ndarray]:
    """The body's fields as a scene file gives them: position and velocity of the shape's own
    origin (the centre of mass less the lever to it), angle, angular velocity, mass."""
    lever = _lever(body.angle, body.origin)
    w = body.angular_velocity
    return {
        "position": np.asarray(body.position) - lever,
        "velocity": np.asarray(body.velocity) - w * np.array([-lever[1], lever[0]]),
        "angle": np.float64(body.angle),
        "angular_velocity": np.float64(w),
        "mass": np.float64(body.mass),
        "restitution": np.float64(body.restitution),
        "friction": np.float64(body.friction),
    }


def varied_body(body: Body, values: Mapping[str, np.ndarray], name: str) -> Body:
    """``body`` with ``values`` (scene file terms) as Body.from_shape would build it: the centre
    of mass placed from the origin's position and the angle, its velocity from the origin's; a
    new mass scales the inertia (same shape and mass distribution)."""
    changes: dict = {"name": name}
    for field in ("restitution", "friction"):
        if field in values:
            changes[field] = float(values[field])
    if "angle" in values:
        changes["angle"] = reduced_angle(float(values["angle"]))
    if body.fixed:
        if "position" in values:
            changes["position"] = tuple(map(float, values["position"]))
        return replace(body, **changes)
    if "mass" in values:
        mass = float(values["mass"])
        area, second = float(body.shape.area), float(body.shape.second_moment)
        derived = body.inertia == body.mass * second / area
        changes["mass"] = mass
        changes["inertia"] = None if derived else float(body.inertia) * (mass / body.mass)
    if any(field in values for field in MOTION):
        given = {**file_values(body), **values}
        angle = changes.get("angle", body.angle)
        w = float(given["angular_velocity"])
        lever = _lever(angle, body.origin)
        position = np.asarray(given["position"], dtype=float) + lever
        velocity = np.asarray(given["velocity"], dtype=float) + w * np.array([-lever[1], lever[0]])
        changes.update(position=tuple(position.tolist()), velocity=tuple(velocity.tolist()))
        changes["angular_velocity"] = w
    return replace(body, **changes)


def _lever(angle: float, origin) -> np.ndarray:
    """From the shape's own origin to the centre of mass, world axes (Body.from_shape's)."""
    ox, oy = 0.0 - origin[0], 0.0 - origin[1]
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * ox - s * oy, s * ox + c * oy])


def read_variations(scene, variations: Mapping) -> Variations:
    """The checked :class:`Variations` of ``scene`` (see the module docstring)."""
    if not isinstance(variations, Mapping):
        raise VariationError(
            "variations must be a mapping of 'body.field' to arrays (one value per copy), "
            f"got {type(variations).__name__}"
        )
    if not variations:
        raise VariationError(
            "variations is empty: give at least one 'body.field' array (its length is the "
            "number of copies)"
        )
    copies = None
    parts: dict[tuple[int, str], dict[int | None, np.ndarray]] = {}
    columns: dict[str, np.ndarray] = {}
    for key, raw in variations.items():
        index, field, component, size = parse_key(scene, key)
        values = _values(key, raw, 1 if component is not None else size)
        if copies is None:
            copies, first = len(values), key
        elif len(values) != copies:
            raise VariationError(
                f"variations[{key!r}] has {len(values)} values, variations[{first!r}] {copies}: "
                "every array needs one value per copy along its first axis"
            )
        _check_values(key, field, values)
        given = parts.setdefault((index, field), {})
        if (None in given) or (component is None and given) or component in given:
            raise VariationError(f"variations[{key!r}]: {_name(scene, index, field)} given twice")
        given[component] = values
        columns[key] = values
    bodies: dict[int, dict[str, np.ndarray]] = {}
    gravity = None
    for (index, field), given in parts.items():
        if None in given:
            full = given[None]
        else:  # by component: the others keep the scene's value
            base = np.asarray(
                scene.gravity if index < 0 else file_values(scene.bodies[index])[field]
            )
            full = np.tile(np.asarray(base, dtype=float), (copies, 1))
            for component, values in given.items():
                full[:, component] = values
        if index < 0:
            gravity = full
        else:
            bodies.setdefault(index, {})[field] = full
    return Variations(copies, bodies, gravity, columns)


def _name(scene, index: int, field: str) -> str:
    return "scene.gravity" if index < 0 else f"{scene.bodies[index].name}.{field}"


def parse_key(scene, key) -> tuple[int, str, int | None, int]:
    """(template body index or -1 for the scene, field, component or None, the field's size)."""
    match = _KEY.fullmatch(key) if isinstance(key, str) else None
    if match is None:
        raise VariationError(
            f"variations key {key!r} must be '<body name>.<field>' (or '.<field>[i]' for one "
            "component of a vector), or 'scene.gravity'"
        )
    body, field = match["body"], match["field"]
    component = None if match["component"] is None else int(match["component"])
    if body == "scene" and field == "gravity" and "scene" not in scene.names:
        index, size = -1, 2
    else:
        if body not in scene.names:
            raise VariationError(
                f"variations[{key!r}]: no body named {body!r}; bodies: {', '.join(scene.names)}"
            )
        index = scene.index(body)
        if field not in FIELDS:
            raise VariationError(
                f"variations[{key!r}]: unknown field {field!r}; fields: {', '.join(FIELDS)} "
                "(and scene.gravity)"
            )
        if scene.bodies[index].fixed and field not in FIXED_FIELDS:
            raise VariationError(
                f"variations[{key!r}]: {body!r} is fixed: only its {', '.join(FIXED_FIELDS)} "
                "can vary"
            )
        size = FIELDS[field]
    if component is not None and not component < size:
        what = "a number" if size == 1 else f"a vector of {size} components"
        raise VariationError(f"variations[{key!r}]: {field} is {what}: no component {component}")
    return index, field, component, size


def _values(key: str, raw, size: int) -> np.ndarray:
    """``raw`` as an (N,) (size 1) or (N, size) float array."""
    try:
        values = np.array(raw, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise VariationError(
            f"variations[{key!r}] must be an array of numbers, got {type(raw).__name__}"
        ) from None
    want = "(N,)" if size == 1 else f"(N, {size})"
    if values.ndim != (1 if size == 1 else 2) or (size > 1 and values.shape[1] != size):
        raise VariationError(
            f"variations[{key!r}] must have shape {want}: one value per copy along the first "
            f"axis, got shape {values.shape}"
        )
    if len(values) == 0:
        raise VariationError(f"variations[{key!r}] is empty: it needs at least one copy")
    return values


def _check_values(key: str, field: str, values: np.ndarray) -> None:
    """Finite, within the scene file's bounds; mass > 0, restitution in [0, 1], friction >= 0,
    angle below MAX_ANGLE: the first bad one named by its copy."""
    flat = values.reshape(len(values), -1)
    checks = [(np.isfinite(flat), "must be finite"),
              (np.abs(flat) <= LARGEST, f"must be at most {LARGEST:g} in magnitude")]  # fmt: skip
    if field == "mass":
        checks.append((flat >= SMALLEST, f"must be a mass >= {SMALLEST:g}"))
    if field == "restitution":
        checks.append(((flat >= 0) & (flat <= 1), "must be between 0 and 1"))
    if field == "friction":
        checks.append((flat >= 0, "must be >= 0"))
    if field == "angle":
        checks.append((np.abs(flat) < MAX_ANGLE, f"must be below {MAX_ANGLE:.3g} rad"))
    for ok, what in checks:
        bad = np.argwhere(~ok)
        if bad.size:
            copy = int(bad[0][0])
            shown = values[copy].tolist()
            raise VariationError(f"variations[{key!r}][{copy}] = {shown}: {what}")
