"""Checked reading of scene input (TOML tables or plain dicts) into plain Python values.

Scene files are written by hand, so every mistake must come back as one sentence that says
where it is: the file, the body (name and 1-based position among the ``[[body]]`` tables) and
the field.  This module does the type and range checks, builds each body's shape (wrapping the
shapes module's ValueError with that context) and produces the messages; runtime/scene.py
turns the checked values into bodies and checks overlaps.
"""

from __future__ import annotations

import math
import numbers
import re
import reprlib
import sys
import unicodedata
import warnings
from collections.abc import Mapping, Sequence
from typing import Any, NoReturn

import numpy as np

from runtime.io.scene_hints import (
    closest,
    degrees_hint,
    looks_like_degrees,
    unknown_key_hint,
    unknown_type_hint,
)
from runtime.model import shape_library
from runtime.settings import LARGEST, MAX_ANGLE, SMALLEST
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


class SceneError(ValueError):
    """Invalid scene input; the message names the file, the body and the field."""


class SceneWarning(UserWarning):
    """Valid scene input that is probably not what was meant (an angle in degrees); the
    message has the form of a SceneError's."""


TOP_LEVEL_KEYS = ("scene", "simulation", "body")
SCENE_KEYS = ("name", "description", "gravity", "contact_tolerance", "overlap_tolerance")
SIMULATION_KEYS = ("duration", "dt", "method", "stabilisation")
BODY_KEYS = (
    "name",
    "fixed",
    "shape",
    "density",
    "mass",
    "inertia",
    "position",
    "angle",
    "velocity",
    "angular_velocity",
    "restitution",
)

# Shape type -> its parameters and their kinds: "positive", "nonnegative", "finite" numbers,
# "vector" [x, y], "points" [[x, y], ...] (all required) or "flag" (optional bool, default
# false).  They are passed by keyword to the shape_library constructor of the same name.
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
    },
    "box_walls": {"width": "positive", "height": "positive", "end_vertices": "flag"},
}
# Shapes without area (walls) or with a concave edge (bowl): fixed bodies only.
FIXED_ONLY_SHAPES = ("wall", "bowl", "box_walls")


def body_label(index: int, name: str | None = None) -> str:
    """``body 'disc' (#2)`` for the body at 0-based ``index``; messages count from 1."""
    if name is None:
        return f"body #{index + 1}"
    return f"body {name!r} (#{index + 1})"


_SHORT = reprlib.Repr()  # bounded depth and length: a value nested 5,000 deep is "[[[...]]]"
_SHORT.maxlevel, _SHORT.maxstring, _SHORT.maxother = 3, 40, 40


def _describe(value: Any) -> str:
    """A short description of a bad value for an error message."""
    if isinstance(value, str):
        return f"the string {_SHORT.repr(value)}"
    if isinstance(value, Mapping):
        return "a table"
    if isinstance(value, bool):
        return f"the boolean {str(value).lower()}"
    text = _SHORT.repr(value.tolist() if isinstance(value, np.ndarray) else value)
    return text if len(text) <= 60 else text[:57] + "..."


def _unprintable(text: str) -> str | None:
    """The first control, format or line-separator character of ``text``, if any."""
    return next(
        (c for c in text if unicodedata.category(c) in ("Cc", "Cf", "Cs", "Zl", "Zp")), None
    )


def _is_number(value: Any) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


def _is_sequence(value: Any) -> bool:
    return isinstance(value, Sequence | np.ndarray) and not isinstance(value, str | bytes)


class Table:
    """A mapping being read, with the context that error messages need.

    ``where`` is the part of the message between the file and the field, e.g. ``[scene]`` or
    ``body 'disc' (#2)``; ``prefix`` is prepended to field names (``shape.`` inside a shape).
    """

    def __init__(self, data: Any, source: str, where: str, prefix: str = "", field: str = ""):
        self.source = source
        self.where = where
        self.prefix = ""  # the field of the table itself is named without the prefix
        if not isinstance(data, Mapping):
            self.fail(field, f"expected a table, got {_describe(data)}")
        self.prefix = prefix
        self.data: Mapping[str, Any] = data

    # -- errors -------------------------------------------------------------------------
    def fail(self, field: str, message: str) -> NoReturn:
        raise SceneError(self._located(field, message)) from None  # one line, no chained trace

    def warn(self, field: str, message: str) -> None:
        """Warn (SceneWarning), attributed to the line that called the loader."""
        frame, level = sys._getframe(0), 1
        while frame.f_back is not None and frame.f_globals["__name__"].startswith("runtime.io"):
            frame, level = frame.f_back, level + 1
        warnings.warn(SceneWarning(self._located(field, message)), stacklevel=level)

    def _located(self, field: str, message: str) -> str:
        parts = [self.source]
        if self.where:
            parts.append(self.where)
        if field:
            parts.append(f"field {self.prefix + field!r}")
        parts.append(message)
        return ": ".join(parts)

    def check_keys(self, valid: Sequence[str]) -> None:
        """Reject keys that are not in ``valid``, saying why (runtime/io/scene_hints.py)."""
        for key in self.data:
            if key not in valid:
                self.fail(str(key), unknown_key_hint(str(key), valid))

    def has(self, key: str) -> bool:
        return key in self.data

    def _get(self, key: str, default: Any) -> Any:
        if key in self.data:
            return self.data[key]
        if default is _REQUIRED:
            self.fail(key, "missing required field")
        return default

    # -- typed readers ------------------------------------------------------------------
    def number(
        self, key: str, default: Any = None, *, check: str = "finite", bounded: bool = True
    ) -> float:
        """A finite float; ``check`` is "finite", "positive", "nonnegative" or "unit";
        ``bounded``: also within [-LARGEST, LARGEST] and, if positive, at least SMALLEST."""
        return self.check_number(key, self._get(key, default), check, bounded=bounded)

    def check_number(
        self, key: str, value: Any, check: str = "finite", *, bounded: bool = True
    ) -> float:
        if not _is_number(value):
            self.fail(key, f"expected a number, got {_describe(value)}")
        try:
            x = float(value)
        except OverflowError:  # a Python int beyond the float range
            self.fail(key, f"must be finite, got {_describe(value)}")
        if not math.isfinite(x):
            self.fail(key, f"must be finite, got {x}")
        if check == "positive" and not x > 0:
            self.fail(key, f"must be > 0, got {x}")
        if check == "nonnegative" and not x >= 0:
            self.fail(key, f"must be >= 0, got {x}")
        if check == "unit" and not 0 <= x <= 1:
            self.fail(key, f"must be between 0 and 1, got {x}")
        if bounded and abs(x) > LARGEST:
            self.fail(key, f"must be at most {LARGEST:g} in magnitude, got {x:g}")
        if bounded and check == "positive" and x < SMALLEST:
            self.fail(key, f"must be at least {SMALLEST:g}, got {x:g}")
        return x

    def vector(self, key: str, default: Any = None) -> tuple[float, float]:
        """A pair of finite floats ``[x, y]``."""
        return self.check_vector(key, self._get(key, default))

    def check_vector(self, key: str, value: Any) -> tuple[float, float]:
        if not _is_sequence(value) or len(value) != 2:
            self.fail(key, f"expected a list of 2 numbers [x, y], got {_describe(value)}")
        x = self.check_number(f"{key}[0]", value[0])
        y = self.check_number(f"{key}[1]", value[1])
        return (x, y)

    def points(self, key: str) -> list[tuple[float, float]]:
        """A list of at least three ``[x, y]`` points."""
        value = self._get(key, _REQUIRED)
        if not _is_sequence(value) or len(value) < 3:
            self.fail(
                key, f"expected a list of at least 3 points [[x, y], ...], got {_describe(value)}"
            )
        points = [self.check_vector(f"{key}[{i}]", p) for i, p in enumerate(value)]
        for i, p in enumerate(points):
            if p in points[:i]:
                j = points.index(p)
                self.fail(f"{key}[{i}]", f"repeats point {j}, {list(p)}; corners must be distinct")
        span = max(max(x for x, _ in points) - min(x for x, _ in points),
                   max(y for _, y in points) - min(y for _, y in points))  # fmt: skip
        if span < SMALLEST:
            self.fail(key, f"the points span only {span:g}; they must span at least {SMALLEST:g}")
        return points

    def string(self, key: str, default: Any = None) -> str:
        value = self._get(key, default)
        if not isinstance(value, str) or (key in self.data and not value.strip()):
            self.fail(key, f"expected a non-empty string, got {_describe(value)}")
        return value

    def name(self, key: str, default: str) -> str:
        """A name: a non-empty string without control or format characters, which would
        reach a terminal raw (escape codes) or hide text (bidirectional overrides)."""
        value = self.string(key, default)
        bad = _unprintable(value)
        if bad is not None:
            given = "" if self.has(key) else f" (the default, {_SHORT.repr(value)})"
            self.fail(key, f"contains the non-printing character U+{ord(bad):04X}{given}; "
                           "a name must be printable text")  # fmt: skip
        return value

    def boolean(self, key: str, default: Any = None) -> bool:
        value = self._get(key, default)
        if not isinstance(value, bool | np.bool_):
            self.fail(key, f"expected true or false, got {_describe(value)}")
        return bool(value)

    def subtable(self, key: str, prefix: str = "") -> Table:
        return Table(self._get(key, _REQUIRED), self.source, self.where, prefix, key)


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


_REQUIRED: Any = _Required()
REQUIRED: Any = _REQUIRED


def read_shape_spec(body: Table, *, fixed: bool) -> tuple[str, dict[str, Any]]:
    """The ``shape`` table of a body: its type and checked constructor keyword arguments."""
    shape = body.subtable("shape", prefix="shape.")
    kind = shape.string("type", REQUIRED)
    if kind not in SHAPE_PARAMETERS:
        shape.fail(
            "type",
            unknown_type_hint(kind, list(SHAPE_PARAMETERS)),
        )
    params = SHAPE_PARAMETERS[kind]
    shape.check_keys(("type", *params))
    if not fixed and kind in FIXED_ONLY_SHAPES:
        if kind == "bowl":
            reason = "a concave edge (bowl) on a moving body is not supported"
        else:
            reason = f"a {kind!r} has no area and cannot move"
        shape.fail("type", f"{reason}; use it on a fixed body (fixed = true)")
    kwargs: dict[str, Any] = {}
    for name, kind_of in params.items():
        if kind_of == "points":
            kwargs[name] = shape.points(name)
        elif kind_of == "vector":
            kwargs[name] = shape.vector(name, REQUIRED)
        elif kind_of == "flag":
            if shape.has(name):
                kwargs[name] = shape.boolean(name)
        else:
            kwargs[name] = shape.number(name, REQUIRED, check=kind_of)
    return kind, kwargs


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
    if not _is_sequence(raw_bodies) or len(raw_bodies) == 0:
        top.fail(
            "body", f"expected a non-empty array of [[body]] tables, got {_describe(raw_bodies)}"
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
    printable = isinstance(name, str) and name.strip() and _unprintable(name) is None
    label = body_label(index, name if printable else None)
    table = Table(raw, source, label, field="")
    table.check_keys(BODY_KEYS)
    name = table.name("name", f"body{index + 1}")
    fixed = table.boolean("fixed", False)
    kind, kwargs = read_shape_spec(table, fixed=fixed)
    degrees = [k for k in ("start_angle", "end_angle") if looks_like_degrees(kwargs.get(k, 0.0))]
    try:
        shape = getattr(shape_library, kind)(**kwargs)
    except ValueError as exc:
        hint = f"; {degrees_hint([kwargs[k] for k in degrees])}" if degrees else ""
        table.fail(_shape_field(str(exc), kwargs), f"{exc}{hint}")
    except ArithmeticError as exc:  # e.g. OverflowError from math.* on extreme sizes
        table.fail("shape", f"{kind}: its size is out of range ({exc})")
    for key in degrees:
        table.warn(f"shape.{key}", degrees_hint([kwargs[key]]))
    spec: dict[str, Any] = {
        "name": name,
        "shape": shape,
        "fixed": fixed,
        "position": table.vector("position", (0.0, 0.0) if fixed else REQUIRED),
        "angle": _read_angle(table),
        "restitution": table.number("restitution", 0.0, check="unit"),
    }
    if fixed:
        for key in ("mass", "density", "inertia"):
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
    if any(getattr(edge, "radius", 0.0) < 0 for edge in shape.edges):
        table.fail("shape", "a concave edge on a moving body is not supported; make it fixed")
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
    if -math.pi < angle <= math.pi:
        return angle
    reduced = math.atan2(math.sin(angle), math.cos(angle))
    return math.pi if reduced == -math.pi else reduced


def _check_mass_properties(table: Table, spec: Mapping[str, Any], shape: Any) -> None:
    """Mass and inertia (given, or from density x area and mass x second moment / area) must be
    positive with finite inverses (the engine uses 1/m and 1/I), and the body's kinetic energy
    finite: otherwise the first step would produce inf or NaN."""
    area, second_moment = float(shape.area), float(shape.second_moment)
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
    """The ``shape.<parameter>`` a shapes-constructor error is about: the parameter named
    first in its message (they read "polygon: points must be ...")."""
    found = [
        (m.start(), name)
        for name in kwargs
        if (m := re.search(rf"\b{re.escape(name)}\b", message)) is not None
    ]
    return f"shape.{min(found)[1]}" if found else "shape"
