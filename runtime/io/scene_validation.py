"""Checked reading of scene input (TOML tables or plain dicts) into plain Python values.

Scene files are written by hand, so every mistake must come back as one sentence that says
where it is (runtime/io/scene_table.py reads typed values with that context).  This module
knows the tables and keys of a scene, builds each body's shape (wrapping the shape library's
ValueError with the field), checks angles and mass properties; runtime/io/scene_file.py turns
the checked values into bodies and runs the whole-scene checks.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from typing import Any

import numpy as np

from runtime.io.scene_hints import (
    closest,
    degrees_hint,
    looks_like_degrees,
    unknown_type_hint,
)
from runtime.io.scene_links import read_body_damping
from runtime.io.scene_table import (
    REQUIRED,
    SceneError,
    SceneWarning,
    Table,
    body_label,
    describe,
    is_sequence,
    unprintable,
)
from runtime.model import shape_library
from runtime.model.scene import center_of_mass_error
from runtime.settings import MAX_ANGLE
from runtime.step.integrators import METHODS

__all__ = [
    "BODY_KEYS",
    "FIXED_ONLY_SHAPES",
    "REQUIRED",
    "SCENE_KEYS",
    "SHAPE_PARAMETERS",
    "SIMULATION_KEYS",
    "TOP_LEVEL_KEYS",
    "SceneError",
    "SceneWarning",
    "Table",
    "body_label",
    "read_bodies",
    "read_body",
    "read_shape_spec",
    "read_simulation",
]


TOP_LEVEL_KEYS = ("scene", "simulation", "body", "joint", "spring")
SCENE_KEYS = (
    "name",
    "description",
    "gravity",
    "contact_tolerance",
    "overlap_tolerance",
    "mutual_gravity",
)
SIMULATION_KEYS = ("duration", "dt", "method", "stabilisation")
BODY_KEYS = (
    "name",
    "fixed",
    "shape",
    "density",
    "mass",
    "inertia",
    "center_of_mass",
    "position",
    "angle",
    "velocity",
    "angular_velocity",
    "restitution",
    "linear_damping",
    "angular_damping",
    "friction",
)

# Shape type -> its parameters and their kinds: "positive", "nonnegative", "finite" numbers,
# "vector" [x, y], "points" [[x, y], ...], "parts" [{type = ...}, ...] (all required),
# "flag" (optional bool, default false) or "thickness" (optional number > 0).  They are passed
# by keyword to the shape_library constructor of the same name.
SHAPE_PARAMETERS: dict[str, dict[str, str]] = {
    "disc": {"radius": "positive"},
    "polygon": {"points": "points"},
    "rounded_rect": {"width": "positive", "height": "positive", "corner_radius": "nonnegative"},
    "half_disc": {"radius": "positive"},
    "d_shape": {"width": "positive", "height": "positive"},
    "ellipse": {"a": "positive", "b": "positive"},
    "wall": {"start": "vector", "end": "vector", "end_vertices": "flag"},
    "bowl": {
        "radius": "positive",
        "start_angle": "finite",
        "end_angle": "finite",
        "end_vertices": "flag",
        "thickness": "thickness",
    },
    "box_walls": {
        "width": "positive",
        "height": "positive",
        "end_vertices": "flag",
        "thickness": "thickness",
    },
    "frame": {"width": "positive", "height": "positive", "thickness": "positive"},
    "compound": {"parts": "parts"},
}
# Shapes without area: fixed bodies only (a bowl or box with a thickness has area).
FIXED_ONLY_SHAPES = ("wall", "bowl", "box_walls")
# The shapes a compound's parts may be: closed and convex.
PART_SHAPES = ("disc", "polygon", "rounded_rect", "half_disc", "d_shape", "ellipse")


def read_shape_spec(body: Table, *, fixed: bool) -> tuple[str, dict[str, Any]]:
    """The ``shape`` table of a body: its type and checked constructor keyword arguments (a
    compound's ``parts`` already built)."""
    shape = body.subtable("shape", prefix="shape.")
    kind, kwargs = _read_shape_table(shape)
    if not fixed and kind in FIXED_ONLY_SHAPES and "thickness" not in kwargs:
        thicken = "" if kind == "wall" else "give it a 'thickness' (material behind it) or "
        shape.fail(
            "type",
            f"a {kind!r} has no area and cannot move; {thicken}use it on a fixed body "
            "(fixed = true)",
        )
    return kind, kwargs


def _read_shape_table(shape: Table) -> tuple[str, dict[str, Any]]:
    kind = shape.string("type", REQUIRED)
    if kind not in SHAPE_PARAMETERS:
        shape.fail("type", unknown_type_hint(kind, list(SHAPE_PARAMETERS)))
    params = SHAPE_PARAMETERS[kind]
    shape.check_keys(("type", *params))
    kwargs: dict[str, Any] = {}
    for name, kind_of in params.items():
        if kind_of == "points":
            kwargs[name] = shape.points(name)
        elif kind_of == "parts":
            kwargs[name] = _read_parts(shape, name)
        elif kind_of == "vector":
            kwargs[name] = shape.vector(name, REQUIRED)
        elif kind_of == "flag":
            if shape.has(name):
                kwargs[name] = shape.boolean(name)
        elif kind_of == "thickness":
            if shape.has(name):
                kwargs[name] = shape.number(name, check="positive")
        else:
            kwargs[name] = shape.number(name, REQUIRED, check=kind_of)
    return kind, kwargs


def _read_parts(shape: Table, key: str) -> list[Any]:
    """A compound's ``parts``: a list of shape tables of closed convex shapes, each built."""
    value = shape.data.get(key, REQUIRED)
    if value is REQUIRED:
        shape.fail(key, "missing required field")
    if not is_sequence(value) or len(value) == 0:
        shape.fail(
            key, f"expected a list of shape tables [{{ type = ... }}, ...], got {describe(value)}"
        )
    parts = []
    for k, raw in enumerate(value):
        where = f"{key}[{k}]"
        part = Table(
            raw, shape.source, shape.where, f"{shape.prefix}{where}.", shape.prefix + where
        )
        kind = part.string("type", REQUIRED)
        if kind in SHAPE_PARAMETERS and kind not in PART_SHAPES:
            part.fail(
                "type",
                f"a part must be a closed convex shape ({', '.join(PART_SHAPES)}), not {kind!r}",
            )
        kind, kwargs = _read_shape_table(part)
        parts.append(_build_shape(part, kind, kwargs))
    return parts


def _build_shape(table: Table, kind: str, kwargs: dict[str, Any]) -> Any:
    """The shape_library constructor's shape of a shape table (its fields ``table.prefix`` +
    parameter); a ValueError names the parameter it is about."""
    at = Table({}, table.source, table.where)
    degrees = [k for k in ("start_angle", "end_angle") if looks_like_degrees(kwargs.get(k, 0.0))]
    try:
        shape = getattr(shape_library, kind)(**kwargs)
    except ValueError as exc:
        hint = f"; {degrees_hint([kwargs[k] for k in degrees])}" if degrees else ""
        about = _shape_field(str(exc), kwargs)
        at.fail(table.prefix + about if about else table.prefix.rstrip("."), f"{exc}{hint}")
    except ArithmeticError as exc:  # e.g. OverflowError from math.* on extreme sizes
        at.fail(table.prefix.rstrip("."), f"{kind}: its size is out of range ({exc})")
    for key in degrees:
        at.warn(table.prefix + key, degrees_hint([kwargs[key]]))
    return shape


def read_simulation(data: Any, source: str, default_duration: float) -> dict[str, Any]:
    """The ``[simulation]`` table as keyword arguments of SimulationDefaults."""
    sim = Table(data, source, "[simulation]", field="simulation")
    sim.check_keys(SIMULATION_KEYS)
    values: dict[str, Any] = {}
    for key in ("duration", "dt"):
        if sim.has(key):
            values[key] = sim.number(key, check="positive")
    if "dt" in values and values["dt"] > values.get("duration", default_duration):
        duration = values.get("duration", default_duration)
        sim.fail("dt", f"must not exceed duration ({duration}), got {values['dt']}")
    if sim.has("method"):
        method = values["method"] = sim.string("method").lower()
        if method not in METHODS:
            sim.fail("method", f"unknown method {method!r}; {closest(method, METHODS, 'methods')}")
    if sim.has("stabilisation"):
        values["stabilisation"] = sim.boolean("stabilisation")
    return values


def read_bodies(top: Table) -> list[dict[str, Any]]:
    """The ``[[body]]`` tables as keyword arguments of ``Body.from_shape``."""
    raw_bodies = top.data.get("body")
    if raw_bodies is None:
        top.fail("body", "missing: a scene needs at least one [[body]] table")
    if isinstance(raw_bodies, Mapping):
        top.fail("body", "expected an array of tables: write [[body]], not [body]")
    if not is_sequence(raw_bodies) or len(raw_bodies) == 0:
        top.fail(
            "body", f"expected a non-empty array of [[body]] tables, got {describe(raw_bodies)}"
        )
    specs: list[dict[str, Any]] = []
    for index, raw in enumerate(raw_bodies):
        spec = read_body(raw, index, top.source)
        for other_index, other in enumerate(specs):
            if other["name"] == spec["name"]:
                message = f"duplicate name, also used by {body_label(other_index)}"
                Table({}, top.source, body_label(index, spec["name"])).fail("name", message)
        specs.append(spec)
    return specs


def read_body(raw: Any, index: int, source: str) -> dict[str, Any]:
    """One ``[[body]]`` table, checked, with its shape built (not yet centred)."""
    name = raw.get("name") if isinstance(raw, Mapping) else None
    printable = isinstance(name, str) and name.strip() and unprintable(name) is None
    label = body_label(index, name if printable else None)
    table = Table(raw, source, label, field="")
    table.check_keys(BODY_KEYS)
    name = table.name("name", f"body{index + 1}")
    fixed = table.boolean("fixed", False)
    kind, kwargs = read_shape_spec(table, fixed=fixed)
    shape = _build_shape(table.subtable("shape", prefix="shape."), kind, kwargs)
    spec: dict[str, Any] = {
        "name": name,
        "shape": shape,
        "fixed": fixed,
        "position": table.vector("position", (0.0, 0.0) if fixed else REQUIRED),
        "angle": _read_angle(table),
        "restitution": table.number("restitution", 0.0, check="unit"),
        **read_body_damping(table, fixed),
        "friction": table.number("friction", 0.0, check="nonnegative"),
    }
    if fixed:
        for key in ("mass", "density", "inertia", "center_of_mass"):
            if table.has(key):
                table.fail(key, "a fixed body has infinite mass; remove this field")
        if table.vector("velocity", (0.0, 0.0)) != (0.0, 0.0):
            table.fail("velocity", "a fixed body cannot move; remove this field")
        if table.number("angular_velocity", 0.0) != 0.0:
            table.fail("angular_velocity", "a fixed body cannot move; remove this field")
        return spec
    if table.has("mass") and table.has("density"):
        table.fail("mass", "give either 'mass' or 'density', not both")
    if not (table.has("mass") or table.has("density")):
        table.fail("mass", "missing required field: a moving body needs 'mass' or 'density'")
    for key in ("mass", "density", "inertia"):
        spec[key] = table.number(key, check="positive", bounded=False) if table.has(key) else None
    area = float(shape.area)
    if not (math.isfinite(area) and area > 0):
        table.fail("shape", f"a moving body needs a shape with area > 0, got area {area}")
    if table.has("center_of_mass"):
        spec["center_of_mass"] = table.vector("center_of_mass")
        problem = center_of_mass_error(shape, spec["center_of_mass"])
        if problem:
            table.fail("center_of_mass", problem)
    spec["velocity"] = table.vector("velocity", (0.0, 0.0))
    spec["angular_velocity"] = table.number("angular_velocity", 0.0)
    _check_mass_properties(table, spec, shape)
    return spec


def _read_angle(table: Table) -> float:
    """The body's angle, reduced to (-pi, pi] (the engine's sin and cos then see the angle
    exactly; 1e12 rad used to give micrometres of unreported penetration); refused where
    doubles are too far apart to say which angle was meant; a warning if it looks like
    degrees."""
    angle = table.number("angle", 0.0)
    if abs(angle) >= MAX_ANGLE:
        table.fail(
            "angle",
            f"must be below {MAX_ANGLE:.3g} rad in magnitude, got {angle:g}: doubles there are "
            f"{math.ulp(angle):g} rad apart, so the angle meant is lost; give it modulo 2 pi",
        )
    if looks_like_degrees(angle):
        table.warn("angle", degrees_hint([angle]))
    return reduced_angle(angle)


def reduced_angle(angle: float) -> float:
    """``angle`` (rad, below MAX_ANGLE in magnitude) reduced to (-pi, pi], exactly as read."""
    if -math.pi < angle <= math.pi:
        return angle
    reduced = math.atan2(math.sin(angle), math.cos(angle))
    return math.pi if reduced == -math.pi else reduced


def _check_mass_properties(table: Table, spec: Mapping[str, Any], shape: Any) -> None:
    """Mass and inertia (given, or from density x area and mass x second moment / area) must be
    positive with finite inverses (the engine uses 1/m and 1/I), and the body's kinetic energy
    finite: otherwise the first step would produce inf or NaN."""
    area = float(shape.area)
    second_moment = shape.second_moment_about(spec.get("center_of_mass", shape.centroid))
    with np.errstate(all="ignore"):
        mass = spec["mass"] if spec["mass"] is not None else spec["density"] * area
        inertia = spec["inertia"]
        if inertia is None:
            inertia = mass * second_moment / area
        vx, vy = spec["velocity"]
        w = spec["angular_velocity"]
        linear, angular = 0.5 * mass * (vx * vx + vy * vy), 0.5 * inertia * w * w

    def usable(x: float) -> bool:
        return math.isfinite(x) and x > 0 and math.isfinite(1.0 / x)

    need = "must be finite and > 0 with a finite inverse"
    if not usable(mass):
        if spec["mass"] is not None:
            table.fail("mass", f"{need} (1/mass), got {mass:g}")
        table.fail("density", f"gives the mass density x area = {mass:g} kg, which {need}")
    if not usable(inertia):
        if spec["inertia"] is not None:
            table.fail("inertia", f"{need} (1/inertia), got {inertia:g}")
        given = "mass" if spec["mass"] is not None else "density"
        table.fail(
            given,
            f"gives the inertia mass x second moment / area = {inertia:g} kg m^2, which {need}; "
            "give 'inertia' or change the mass or size",
        )
    if not math.isfinite(linear):
        table.fail("velocity", f"the kinetic energy 1/2 m v^2 overflows (mass {mass:g} kg)")
    if not math.isfinite(angular):
        table.fail(
            "angular_velocity", f"the kinetic energy 1/2 I w^2 overflows (inertia {inertia:g})"
        )


def _shape_field(message: str, kwargs: Mapping[str, Any]) -> str:
    """The parameter a shapes-constructor error is about: the one named first in its message
    (they read "polygon: points must be ...")."""
    found = [
        (m.start(), name)
        for name in kwargs
        if (m := re.search(rf"\b{re.escape(name)}\b", message)) is not None
    ]
    return min(found)[1] if found else ""
