"""Bad input gets a clear error; a failing run keeps what it had (issue: reliability).

Complements tests/runtime/test_scene.py (most scene-file mistakes), tests/runtime/test_cli.py
(the ``simulate`` command) and tests/derive/test_regenerate.py (``regenerate-equations``): the
cases here are the ones those files do not test, plus the runtime failures.

* Scene files: ``SCENE_CASES`` is the catalogue of docs/bad-input.md (every row there is
  produced by this list; ``test_docs_table_is_current`` keeps them equal, and
  ``python tests/runtime/test_bad_input.py`` prints the table afresh). Each case is written to
  a file ``bad.toml`` and loaded; the message must be one line naming the file and the body
  or table and field, and contain the listed parts.
* CLI: a scene path that is a directory or not UTF-8 text, ``regenerate-equations --cases ,``.
* Runtime: the contact solver failing (monkeypatched, and a truly infeasible contact set), a
  non-finite state or contact terms, a tunnelling time step, an energy blow-up (the guards of
  runtime/guards.py): a SimulationError naming the step, the time and the contacts, with
  ``.state`` the state at the start of the failing step and ``.run`` the steps before it.
"""

from __future__ import annotations

import contextlib
import dataclasses
import io
import math
import os
import re
import sys
import tempfile
import textwrap
import threading
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import runtime
from runtime import settings
from runtime.io.scene_file import SceneError, load_scene, scene_from_dict
from runtime.model import shapes
from runtime.solve.forces import ContactForces
from runtime.solve.lcp import ContactSolverError

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
DOC = ROOT / "docs" / "bad-input.md"

# -- scene files --------------------------------------------------------------------------------

HEADER = """\
[scene]
name = "bad"
{scene}
[simulation]
duration = 1.0
dt = 0.001
{simulation}
[[body]]
name = "floor"
fixed = true
shape = {{ type = "wall", start = [-2.0, 0.0], end = [2.0, 0.0] }}
"""

DISC = {
    "name": '"disc"',
    "shape": '{ type = "disc", radius = 0.1 }',
    "density": "1000.0",
    "position": "[0.0, 0.5]",
}


def scene_text(
    *, scene: str = "", simulation: str = "", drop: tuple = (), more: str = "", **fields: str
) -> str:
    """The good scene (a floor and a disc 0.4 m above it) with the disc's fields changed
    (``fields``: TOML text of the new values), some dropped, lines added to the tables, and
    more bodies after it."""
    body = {**DISC, **fields}
    for key in drop:
        body.pop(key)
    lines = "\n".join(f"{k} = {v}" for k, v in body.items())
    text = HEADER.format(scene=scene, simulation=simulation) + "\n[[body]]\n" + lines + "\n"
    return text + textwrap.dedent(more)


@dataclass(frozen=True)
class Case:
    """One bad scene file: ``what`` (the doc's wording), ``snippet`` (the bad part as written),
    the file's bytes, and the parts its message must contain (empty: asserted elsewhere, in
    tests/runtime/test_scene.py, and here only for the general form and the doc)."""

    category: str
    what: str
    snippet: str
    content: str | bytes
    parts: tuple[str, ...] = ()


def _moving(name: str, shape: str, position: str, extra: str = "") -> str:
    return f"""
    [[body]]
    name = "{name}"
    shape = {shape}
    density = 1000.0
    position = {position}
    {extra}
    """


GRAIN = '{ type = "disc", radius = 1e-4 }'
JOINT = """[[joint]]
type = "{type}"
body1 = "disc"
body2 = "{body2}"
anchor1 = [0.0, 0.0]
anchor2 = {anchor2}
"""
SPRING = """[[spring]]
body1 = "disc"
body2 = "world"
rest_length = 0.2
stiffness = {stiffness}
damping = {damping}
"""

SCENE_CASES: list[Case] = [
    # unknown keys
    Case("unknown keys", "misspelt body key", "positon = [0.0, 0.5]",
         scene_text(positon="[0.0, 0.5]")),
    Case("unknown keys", "unknown key in [simulation]", "[simulation] timestep = 0.001",
         scene_text(simulation="timestep = 0.001"),
         ("[simulation]: field 'timestep'", "unknown key", "valid keys: 'duration', 'dt'")),
    Case("unknown keys", "[[bodies]] instead of [[body]]", "[[bodies]]",
         scene_text().replace("[[body]]\nname = \"disc\"", "[[bodies]]\nname = \"disc\""),
         ("field 'bodies'", "unknown key", "did you mean 'body'?")),
    Case("unknown keys", "misspelt shape parameter", 'shape = { type = "disc", radus = 0.1 }',
         scene_text(shape='{ type = "disc", radus = 0.1 }')),
    Case("unknown keys", "empty key", 'shape = { type = "disc", radius = 0.1, "" = 1 }',
         scene_text(shape='{ type = "disc", radius = 0.1, "" = 1 }'),
         ("field 'shape.\"\"'", "unknown key")),
    # keys naming features the engine lacks, or another engine's word for a valid one
    Case("unsupported", "rolling resistance", "rolling_resistance = 0.01",
         scene_text(rolling_resistance="0.01"),
         ("body 'disc' (#2): field 'rolling_resistance'", "rolling resistance is not supported",
          "'friction'", "remove this key")),
    Case("unsupported", "another engine's word for friction", "mu = 0.5",
         scene_text(mu="0.5"), ("field 'mu'", "did you mean 'friction'?")),
    Case("unsupported", "another engine's word for restitution", "bounciness = 0.5",
         scene_text(bounciness="0.5"), ("field 'bounciness'", "did you mean 'restitution'?")),
    Case("unsupported", "another engine's shape type", 'shape = { type = "circle", radius = 0.1 }',
         scene_text(shape='{ type = "circle", radius = 0.1 }'),
         ("field 'shape.type'", "unknown shape type 'circle'; use disc")),
    # joints, springs, damping, mutual gravity (issue #16)
    Case("links", "a joint to a body that is not there", '[[joint]] body2 = "rope"',
         scene_text() + JOINT.format(type="pin", body2="rope", anchor2="[0.0, 0.5]"),
         ("joint #1: field 'body2'", "no body named 'rope'")),
    Case("links", "a joint of a body with itself", '[[joint]] body1 = body2 = "disc"',
         scene_text() + JOINT.format(type="pin", body2="disc", anchor2="[0.0, 0.0]"),
         ("joint #1: field 'body2'", "links the body to itself")),
    Case("links", "a joint between two fixed ends", '[[joint]] body1 = "floor", body2 = "world"',
         scene_text() + JOINT.replace('"disc"', '"floor"').format(
             type="pin", body2="world", anchor2="[0.0, 0.0]"),
         ("joint #1: field 'body2'", "both ends are fixed")),
    Case("links", "unknown key in a joint", '[[joint]] bodies = ["floor", "disc"]',
         scene_text() + '[[joint]]\nbodies = ["floor", "disc"]\n',
         ("joint #1: field 'bodies'", "unknown key")),
    Case("links", "unknown joint type", '[[joint]] type = "hinge"',
         scene_text() + JOINT.format(type="hinge", body2="world", anchor2="[0.0, 0.5]"),
         ("joint #1: field 'type'", "unknown joint type 'hinge'")),
    Case("links", "a pin whose anchors are apart", '[[joint]] type = "pin", anchor2 = [0, 1]',
         scene_text() + JOINT.format(type="pin", body2="world", anchor2="[0.0, 1.0]"),
         ("joint #1: field 'anchor2'", "0.5 m apart at t = 0")),
    Case("links", "a motor on a joint", "motor = 1.0",
         scene_text() + JOINT.format(type="pin", body2="world", anchor2="[0.0, 0.5]")
         + "motor = 1.0\n", ("joint #1: field 'motor'", "motors are not supported yet")),
    Case("links", "negative spring stiffness", "[[spring]] stiffness = -5.0",
         scene_text() + SPRING.format(stiffness="-5.0", damping="0.0"),
         ("spring #1: field 'stiffness'", "must be >= 0, got -5.0")),
    Case("links", "NaN spring damping", "[[spring]] damping = nan",
         scene_text() + SPRING.format(stiffness="5.0", damping="nan"),
         ("spring #1: field 'damping'", "must be finite, got nan")),
    Case("links", "spring without a stiffness", "[[spring]] (no stiffness)",
         scene_text() + SPRING.format(stiffness="5.0", damping="0.0").replace(
             "stiffness = 5.0\n", ""),
         ("spring #1: field 'stiffness'", "missing required field")),
    Case("links", "[spring] instead of [[spring]]", "[spring]",
         scene_text() + "[spring]\nstiffness = 5.0\n",
         ("field 'spring'", "write [[spring]], not [spring]")),
    Case("links", "negative linear damping", "linear_damping = -0.1",
         scene_text(linear_damping="-0.1"),
         ("body 'disc' (#2): field 'linear_damping'", "must be >= 0, got -0.1")),
    Case("links", "infinite angular damping", "angular_damping = inf",
         scene_text(angular_damping="inf"),
         ("body 'disc' (#2): field 'angular_damping'", "must be finite, got inf")),
    Case("links", "mutual gravity as a flag", "[scene] mutual_gravity = true",
         scene_text(scene="mutual_gravity = true"),
         ("[scene]: field 'mutual_gravity'", "expected a number, got the boolean true")),
    Case("links", "negative mutual gravity", "[scene] mutual_gravity = -1.0",
         scene_text(scene="mutual_gravity = -1.0"),
         ("[scene]: field 'mutual_gravity'", "must be >= 0, got -1.0")),
    # missing fields
    Case("missing fields", "shape without a type", "shape = { radius = 0.1 }",
         scene_text(shape="{ radius = 0.1 }"),
         ("body 'disc' (#2): field 'shape.type'", "missing required field")),
    Case("missing fields", "polygon without points", 'shape = { type = "polygon" }',
         scene_text(shape='{ type = "polygon" }'),
         ("body 'disc' (#2): field 'shape.points'", "missing required field")),
    Case("missing fields", "wall without an end", 'shape = { type = "wall", start = [0, 1] }',
         scene_text(drop=("density",), fixed="true",
                    shape='{ type = "wall", start = [0.0, 1.0] }'),
         ("body 'disc' (#2): field 'shape.end'", "missing required field")),
    Case("missing fields", "moving body without position", "(no position)",
         scene_text(drop=("position",))),
    Case("missing fields", "neither mass nor density", "(no mass, no density)",
         scene_text(drop=("density",))),
    Case("missing fields", "empty file", "(empty)", "",
         ("field 'body'", "missing: a scene needs at least one [[body]] table")),
    # wrong types
    Case("wrong types", "string for a number", 'shape = { type = "disc", radius = "0.1" }',
         scene_text(shape='{ type = "disc", radius = "0.1" }')),
    Case("wrong types", "string for friction", 'friction = "high"',
         scene_text(friction='"high"'),
         ("body 'disc' (#2): field 'friction'", "expected a number, got the string 'high'")),
    Case("wrong types", "number for a name", "name = 5", scene_text(name="5"),
         ("body #2: field 'name'", "expected a non-empty string, got 5")),
    Case("wrong types", "angle with a unit", 'angle = "30deg"', scene_text(angle='"30deg"'),
         ("field 'angle'", "expected a number, got the string '30deg'")),
    Case("wrong types", "three-component vector", "velocity = [1.0, 0.0, 0.0]",
         scene_text(velocity="[1.0, 0.0, 0.0]"),
         ("field 'velocity'", "expected a list of 2 numbers [x, y], got [1.0, 0.0, 0.0]")),
    Case("wrong types", "table for the points", 'points = { a = 1 }',
         scene_text(shape='{ type = "polygon", points = { a = 1 } }'),
         ("field 'shape.points'", "expected a list of at least 3 points")),
    Case("wrong types", "string for gravity", '[scene] gravity = "down"',
         scene_text(scene='gravity = "down"'),
         ("[scene]: field 'gravity'", "expected a list of 2 numbers", "'down'")),
    Case("wrong types", "number for a flag", "fixed = 1", scene_text(fixed="1")),
    Case("wrong types", "a body that is not a table", "body = [1, 2]",
         'body = [1, 2]\n', ("body #1", "expected a table, got 1")),
    # NaN and infinity
    Case("NaN/inf", "NaN mass", "mass = nan", scene_text(drop=("density",), mass="nan"),
         ("body 'disc' (#2): field 'mass'", "must be finite, got nan")),
    Case("NaN/inf", "infinite density", "density = inf", scene_text(density="inf"),
         ("field 'density'", "must be finite, got inf")),
    Case("NaN/inf", "-inf spin", "angular_velocity = -inf",
         scene_text(angular_velocity="-inf"),
         ("field 'angular_velocity'", "must be finite, got -inf")),
    Case("NaN/inf", "NaN in a polygon corner",
         'points = [[0, 0], [nan, 0], [0, 1]]',
         scene_text(shape='{ type = "polygon", points = [[0, 0], [nan, 0], [0, 1]] }'),
         ("field 'shape.points[1][0]'", "must be finite, got nan")),
    Case("NaN/inf", "NaN friction", "friction = nan", scene_text(friction="nan"),
         ("body 'disc' (#2): field 'friction'", "must be finite, got nan")),
    Case("NaN/inf", "infinite friction on a fixed body", "friction = inf",
         scene_text().replace('fixed = true', 'fixed = true\nfriction = inf'),
         ("body 'floor' (#1): field 'friction'", "must be finite, got inf")),
    Case("NaN/inf", "NaN time step", "[simulation] dt = nan",
         scene_text().replace("dt = 0.001", "dt = nan"),
         ("[simulation]: field 'dt'", "must be finite, got nan")),
    # zero or negative
    Case("zero/negative", "negative mass", "mass = -2.0",
         scene_text(drop=("density",), mass="-2.0"),
         ("body 'disc' (#2): field 'mass'", "must be > 0, got -2.0")),
    Case("zero/negative", "negative friction", "friction = -0.3", scene_text(friction="-0.3"),
         ("body 'disc' (#2): field 'friction'", "must be >= 0, got -0.3")),
    Case("zero/negative", "zero density", "density = 0.0", scene_text(density="0.0"),
         ("field 'density'", "must be > 0, got 0.0")),
    Case("zero/negative", "negative radius", 'radius = -1.0',
         scene_text(shape='{ type = "disc", radius = -1.0 }')),
    Case("zero/negative", "zero width",
         'shape = { type = "rounded_rect", width = 0, height = 0.1, corner_radius = 0 }',
         scene_text(shape='{ type = "rounded_rect", width = 0, height = 0.1, corner_radius = 0 }'),
         ("field 'shape.width'", "must be > 0, got 0.0")),
    Case("zero/negative", "negative half-disc radius",
         'shape = { type = "half_disc", radius = -0.1 }',
         scene_text(shape='{ type = "half_disc", radius = -0.1 }'),
         ("field 'shape.radius'", "must be > 0, got -0.1")),
    Case("zero/negative", "negative corner radius",
         'shape = { type = "rounded_rect", width = 0.2, height = 0.1, corner_radius = -0.01 }',
         scene_text(
             shape='{ type = "rounded_rect", width = 0.2, height = 0.1, corner_radius = -0.01 }'
         ),
         ("field 'shape.corner_radius'", "must be >= 0, got -0.01")),
    Case("zero/negative", "negative inertia", "inertia = -1.0", scene_text(inertia="-1.0"),
         ("field 'inertia'", "must be > 0, got -1.0")),
    Case("zero/negative", "zero duration", "[simulation] duration = 0",
         scene_text().replace("duration = 1.0", "duration = 0"),
         ("[simulation]: field 'duration'", "must be > 0, got 0.0")),
    Case("zero/negative", "negative tolerance", "[scene] overlap_tolerance = -1e-9",
         scene_text(scene="overlap_tolerance = -1e-9"),
         ("[scene]: field 'overlap_tolerance'", "must be > 0")),
    # numbers out of range: squares and fourth powers would overflow or underflow
    Case("out of range", "mass whose inverse overflows", "mass = 5e-324",
         scene_text(drop=("density",), mass="5e-324"),
         ("field 'mass'", "finite inverse (1/mass), got 4.94066e-324")),
    Case("out of range", "density whose inertia underflows",
         'density = 1e-290, radius = 1e-8',
         scene_text(density="1e-290", shape='{ type = "disc", radius = 1e-8 }',
                    position="[0.0, 0.5]"),
         ("field 'density'", "gives the inertia", "give 'inertia'")),
    Case("out of range", "huge polygon", "points = [[0, 0], [1e200, 0], [0, 1e200]]",
         scene_text(shape='{ type = "polygon", points = [[0, 0], [1e200, 0], [0, 1e200]] }'),
         ("field 'shape.points[1][0]'", "must be at most 1e+50 in magnitude, got 1e+200")),
    Case("out of range", "huge radius", "radius = 1e60",
         scene_text(shape='{ type = "disc", radius = 1e60 }'),
         ("field 'shape.radius'", "must be at most 1e+50")),
    Case("out of range", "tiny polygon", "points = [[0, 0], [1e-60, 0], [0, 1e-60]]",
         scene_text(shape='{ type = "polygon", points = [[0, 0], [1e-60, 0], [0, 1e-60]] }'),
         ("field 'shape.points'", "span only 1e-60")),
    Case("out of range", "kinetic energy overflows", "density = 1e300, velocity = [1e10, 0]",
         scene_text(density="1e300", velocity="[1e10, 0.0]"),
         ("field 'velocity'", "kinetic energy 1/2 m v^2 overflows")),
    Case("out of range", "potential energy overflows", "mass = 1e300, position = [0, 1e9]",
         scene_text(drop=("density",), mass="1e300", position="[0.0, 1e9]"),
         ("body 'disc' (#2): field 'position'", "its potential energy overflows float64 (mass "
          "1e+300 kg at (0, 1e+09) m)")),
    Case("out of range", "momentum overflows", "mass = 1.5e308, velocity = [1.5, 0]",
         scene_text(drop=("density",), mass="1.5e308", velocity="[1.5, 0.0]"),
         ("field 'velocity'", "its momentum overflows float64")),
    # shapes
    Case("shapes", "non-convex polygon", "points = [[0, 0], [1, 0], [0.2, 0.2], [0, 1]]",
         scene_text(shape='{ type = "polygon", points = [[0, 0], [1, 0], [0.2, 0.2], [0, 1]] }',
                    position="[0.0, 1.0]")),
    Case("shapes", "self-intersecting polygon (bow tie)",
         "points = [[0, 0], [1, 1], [1, 0], [0, 1]]",
         scene_text(shape='{ type = "polygon", points = [[0, 0], [1, 1], [1, 0], [0, 1]] }',
                    position="[0.0, 1.0]")),
    Case("shapes", "self-intersecting polygon (pentagram)",
         "points = 5 corners of a star, in star order",
         scene_text(shape="{ type = \"polygon\", points = [[0, 1], [-0.588, -0.809], "
                          "[0.951, 0.309], [-0.951, 0.309], [0.588, -0.809]] }",
                    position="[0.0, 1.5]"),
         ("field 'shape.points'", "self-intersecting (winding again at vertex")),
    Case("shapes", "repeated corner", "points = [[0, 0], [1, 0], [1, 0], [0, 1]]",
         scene_text(shape='{ type = "polygon", points = [[0, 0], [1, 0], [1, 0], [0, 1]] }',
                    position="[0.0, 1.0]"),
         ("field 'shape.points[2]'", "repeats point 1, [1.0, 0.0]")),
    Case("shapes", "collinear corners", "points = [[0, 0], [0.5, 0], [1, 0], [0, 1]]",
         scene_text(shape='{ type = "polygon", points = [[0, 0], [0.5, 0], [1, 0], [0, 1]] }',
                    position="[0.0, 1.0]"),
         ("field 'shape.points'", "strictly convex; vertex 1 (0.5, 0.0) is collinear")),
    Case("shapes", "two points", "points = [[0, 0], [1, 0]]",
         scene_text(shape='{ type = "polygon", points = [[0, 0], [1, 0]] }'),
         ("field 'shape.points'", "at least 3 points")),
    Case("shapes", "corner radius too large",
         "width = 1.0, height = 0.2, corner_radius = 0.2",
         scene_text(shape='{ type = "rounded_rect", width = 1.0, height = 0.2, '
                          'corner_radius = 0.2 }')),
    Case("shapes", "D-shape narrower than its arc", "width = 0.01, height = 0.2",
         scene_text(shape='{ type = "d_shape", width = 0.01, height = 0.2 }'),
         ("field 'shape.width'", "width must be >= 0.1 (the front's radius), got 0.01")),
    Case("shapes", "needle ellipse", "a = 1.0, b = 1e-16",
         scene_text(shape='{ type = "ellipse", a = 1.0, b = 1e-16 }'),
         ("field 'shape.a'", "a / b must be at most 1e+06, got 1e+16", "b^2/a = 1e-32 m")),
    Case("shapes", "wall of zero length", "start = [1, 0], end = [1, 0]",
         scene_text(drop=("density",), fixed="true",
                    shape='{ type = "wall", start = [1.0, 0.0], end = [1.0, 0.0] }'),
         ("field 'shape.start'", "start and end must differ")),
    # arcs
    Case("arcs", "bowl ending before it starts", "start_angle = 0.0, end_angle = -1.0",
         scene_text(drop=("density",), fixed="true",
                    shape='{ type = "bowl", radius = 1.0, start_angle = 0.0, end_angle = -1.0 }'),
         ("field 'shape.end_angle'", "must exceed the start angle 0.0 by at most 2 pi")),
    Case("arcs", "bowl of more than a full turn", "start_angle = 0.0, end_angle = 7.0",
         scene_text(drop=("density",), fixed="true",
                    shape='{ type = "bowl", radius = 1.0, start_angle = 0.0, end_angle = 7.0 }'),
         ("field 'shape.end_angle'", "by at most 2 pi, got 7.0")),
    Case("arcs", "bowl in degrees", "start_angle = 0, end_angle = 180",
         scene_text(drop=("density",), fixed="true",
                    shape='{ type = "bowl", radius = 1.0, start_angle = 0, end_angle = 180 }'),
         ("field 'shape.end_angle'", "got 180.0; angles are in radians: 180 looks like degrees "
          "(180 deg = 3.14159 rad)")),
    Case("arcs", "bowl in degrees, both ends", "start_angle = -150, end_angle = -30",
         scene_text(drop=("density",), fixed="true",
                    shape='{ type = "bowl", radius = 1.0, start_angle = -150, end_angle = -30 }'),
         ("-150 and -30 look like degrees (-150 and -30 deg = -2.61799 and -0.523599 rad)",)),
    Case("out of range", "an angle beyond any precision", "angle = 1e15", scene_text(angle="1e15"),
         ("field 'angle'", "must be below 5.63e+14 rad in magnitude, got 1e+15: doubles there are "
          "0.125 rad apart")),
    # compound bodies, cups, centre of mass
    Case("compound", "overlapping parts",
         'parts = [{ type = "disc", radius = 0.1 }, { type = "polygon", ... }]',
         scene_text(shape='{ type = "compound", parts = [{ type = "disc", radius = 0.1 }, '
                          '{ type = "polygon", points = [[0.05, -0.05], [0.3, -0.05], '
                          '[0.3, 0.05], [0.05, 0.05]] }] }'),
         ("field 'shape.parts'", "parts[0] and parts[1] overlap by 0.05 m; parts may touch but "
          "not overlap")),
    Case("compound", "a part that is not closed and convex", 'parts = [{ type = "wall", ... }]',
         scene_text(shape='{ type = "compound", parts = [{ type = "wall", start = [0, 0], '
                          'end = [1, 0] }] }'),
         ("field 'shape.parts[0].type'", "a part must be a closed convex shape (disc, polygon")),
    Case("compound", "no parts", "parts = []",
         scene_text(shape='{ type = "compound", parts = [] }'),
         ("field 'shape.parts'", "expected a list of shape tables")),
    Case("compound", "a typo inside a part", 'parts = [{ type = "disc", radus = 0.1 }]',
         scene_text(shape='{ type = "compound", parts = [{ type = "disc", radus = 0.1 }] }'),
         ("field 'shape.parts[0].radus'", "unknown key; did you mean 'radius'?")),
    Case("compound", "a cup deeper than half a turn", "thickness = 0.1, end_angle - start_angle > pi",
         scene_text(shape='{ type = "bowl", radius = 1.0, start_angle = -3.5, end_angle = 0.2, '
                          'thickness = 0.1 }'),
         ("field 'shape.end_angle'", "must be at most pi (or a full turn) for a bowl with "
          "thickness")),
    Case("compound", "centre of mass outside the body", "center_of_mass = [1.0, 0.0]",
         scene_text(center_of_mass="[1.0, 0.0]"),
         ("field 'center_of_mass'", "(1, 0) is 0.9 m outside the shape's convex hull")),
    Case("compound", "centre of mass of a fixed body", "fixed = true, center_of_mass = [0, 0]",
         scene_text(drop=("density",), fixed="true", center_of_mass="[0.0, 0.0]"),
         ("field 'center_of_mass'", "a fixed body has infinite mass; remove this field")),
    # moving or fixed
    Case("moving/fixed", "bowl without thickness on a moving body",
         'shape = { type = "bowl", ... }, not fixed',
         scene_text(shape='{ type = "bowl", radius = 1.0, start_angle = -2.5, '
                          'end_angle = -0.6 }')),
    Case("moving/fixed", "box on a moving body", 'shape = { type = "box_walls", ... }',
         scene_text(shape='{ type = "box_walls", width = 1.0, height = 1.0 }'),
         ("field 'shape.type'", "a 'box_walls' has no area and cannot move", "fixed = true")),
    Case("moving/fixed", "density on a fixed body", "fixed = true, density = 1000.0",
         scene_text(fixed="true"),
         ("field 'density'", "a fixed body has infinite mass; remove this field")),
    Case("moving/fixed", "spin on a fixed body", "fixed = true, angular_velocity = 1.0",
         scene_text(drop=("density",), fixed="true", angular_velocity="1.0"),
         ("field 'angular_velocity'", "a fixed body cannot move")),
    # overlaps at t = 0
    Case("overlap at t = 0", "disc sunk into the floor", "position = [0.0, 0.05]",
         scene_text(position="[0.0, 0.05]")),
    Case("overlap at t = 0", "polygon corner through the floor",
         "a triangle with a corner 0.02 m below y = 0",
         scene_text(shape='{ type = "polygon", points = [[0, -0.02], [0.3, 0.2], [-0.3, 0.2]] }',
                    position="[0.0, 0.0]"),
         ("body 'floor' (#1) and body 'disc' (#2): field 'position'",
          "overlap by 0.02 m at t = 0 (vertex_edge contact at (0, -0.02))",
          "move 'disc' away")),
    Case("overlap at t = 0", "two moving bodies", "a box 0.03 m into a disc",
         scene_text(more=_moving("box", '{ type = "rounded_rect", width = 0.2, height = 0.2, '
                                        'corner_radius = 0.0 }', "[0.17, 0.5]")),
         ("body 'disc' (#2) and body 'box' (#3): field 'position'", "overlap by 0.03 m")),
    Case("overlap at t = 0", "a pebble inside a disc", "pebble at the disc's centre",
         scene_text(more=_moving("pebble", '{ type = "disc", radius = 0.02 }', "[0.0, 0.5]")),
         ("body 'disc' (#2) and body 'pebble' (#3)", "overlap by at least",
          "lies inside")),
    # one-sided walls, bowls and boxes with a body at their back
    Case("facing", "floor drawn right to left", "start = [2, 0], end = [-2, 0], disc on it",
         scene_text(position="[0.0, 0.1]").replace("start = [-2.0, 0.0], end = [2.0, 0.0]",
                                                   "start = [2.0, 0.0], end = [-2.0, 0.0]"),
         ("body 'floor' (#1): field 'shape': body 'disc' (#2) is at the back of this wall (its "
          "centre 0.1 m behind it)", "swap start and end to make it face 'disc'")),
    Case("facing", "disc under a bowl", "a bowl of radius 1 centred at y = 1.7, the disc 0.2 m below it",
         scene_text(more='''
             [[body]]
             name = "bowl"
             fixed = true
             position = [0.0, 1.7]
             shape = { type = "bowl", radius = 1.0, start_angle = -2.5, end_angle = -0.6 }
             '''),
         ("body 'bowl' (#3): field 'shape': body 'disc' (#2) is outside this bowl",
          "a bowl holds bodies inside its circle")),
    Case("facing", "disc under a box", "box_walls at y = 0.6, the disc below its floor",
         scene_text(more='''
             [[body]]
             name = "box"
             fixed = true
             position = [0.0, 0.6]
             shape = { type = "box_walls", width = 1.0, height = 0.5 }
             '''),
         ("body 'box' (#3): field 'shape': body 'disc' (#2) is outside this box (its centre "
          "0.1 m behind its floor): box walls face inwards",)),
    # tolerances against the bodies' size
    Case("tolerances", "default contact tolerance, 0.1 mm grain", "radius = 1e-4",
         scene_text(shape=GRAIN, position="[0.0, 0.01]"),
         ("[scene]: field 'contact_tolerance'", "0.0001 m (the default) is too large for "
          "body 'disc' (#2)", "set it to at most")),
    Case("tolerances", "a body too small for any tolerance", "radius = 1e-50",
         scene_text(shape='{ type = "disc", radius = 1e-50 }', position="[0.0, 0.01]"),
         ("body 'disc' (#2): field 'shape'", "is below 2e-50 m, the smallest moving body")),
    Case("tolerances", "both defaults too large", "radius = 1e-9",
         scene_text(shape='{ type = "disc", radius = 1e-9 }', position="[0.0, 0.01]"),
         ("set it to at most 5e-10 m", "and overlap_tolerance (1e-09 m) too")),
    Case("tolerances", "overlap tolerance as large as a body", "overlap_tolerance = 0.06",
         scene_text(scene="overlap_tolerance = 0.06"),
         ("[scene]: field 'overlap_tolerance'", "would let bodies start that deep inside")),
    # the file itself
    Case("file", "not UTF-8", "a Latin-1 byte in a comment",
         scene_text().encode() + b"# caf\xe9\n", ("not UTF-8 text (byte",)),
    Case("file", "key given twice", "radius twice in one table",
         scene_text(shape='{ type = "disc", radius = 0.1, radius = 0.2 }'),
         ("line 15, column 52: TOML syntax error: Duplicate inline table key 'radius'",)),
    Case("file", "TOML syntax error", 'shape = { type = "disc" radius = 0.1 }',
         scene_text(shape='{ type = "disc" radius = 0.1 }')),
    Case("file", "nested 500 deep", "deep = [[[ ... ]]] (500 levels)",
         scene_text() + "deep = " + "[" * 500 + "]" * 500 + "\n",
         ("TOML nested too deeply",)),
    Case("file", "larger than the size cap", "10 MiB of comments and one byte more",
         b"#" * (10 * 2**20) + b"\n", ("larger than 10 MiB, the limit of a scene file",)),
    Case("names", "terminal escape code in a body name", r'name = "\u001b[31mdisc"',
         scene_text(name=r'"\u001b[31mdisc"'),
         ("body #2: field 'name'", "contains the non-printing character U+001B",
          "a name must be printable text")),
    Case("names", "terminal escape code in the scene name", r'[scene] name = "\u001b]0;x\u0007"',
         scene_text().replace('name = "bad"', r'name = "\u001b]0;x\u0007"'),
         ("[scene]: field 'name'", "contains the non-printing character U+001B")),
    Case("names", "right-to-left override in a body name", r'name = "disc\u202e"',
         scene_text(name=r'"disc\u202e"'), ("body #2: field 'name'", "U+202E")),
]  # fmt: skip

CASE_IDS = [f"{c.category}: {c.what}" for c in SCENE_CASES]


def scene_message(case: Case, directory: Path) -> str:
    """The SceneError message of loading the case as ``bad.toml`` from ``directory``."""
    path = directory / "bad.toml"
    path.write_bytes(case.content if isinstance(case.content, bytes) else case.content.encode())
    cwd = os.getcwd()
    os.chdir(directory)
    try:
        load_scene("bad.toml")
    except SceneError as exc:
        assert exc.__cause__ is None and exc.__suppress_context__, "chained traceback"
        return str(exc)
    finally:
        os.chdir(cwd)
    raise AssertionError(f"{case.what}: no SceneError")


@pytest.mark.parametrize("case", SCENE_CASES, ids=CASE_IDS)
def test_bad_scene_file_is_refused_naming_file_body_and_field(tmp_path, case):
    message = scene_message(case, tmp_path)
    assert message.startswith("bad.toml: ") and "\n" not in message, message
    located = re.search(
        r"body (#\d+|'[^']*' \(#\d+\))|\[scene\]|\[simulation\]|(joint|spring) #\d+", message
    )
    file_level = ("TOML", "UTF-8", "field 'b", "cannot read the file")
    top_level = message.startswith("bad.toml: field '")  # a key outside every table
    assert located or top_level or any(word in message for word in file_level), message
    for part in case.parts:
        assert part in message, (part, message)


def test_overlap_depth_is_the_true_depth():
    """The reported depth is the geometric one (a 0.2 box centred 0.17 m from a disc of radius
    0.1: 0.1 + 0.1 - 0.17 = 0.03 m), rounded to 6 significant digits."""
    data = {
        "body": [
            {"name": "disc", "shape": {"type": "disc", "radius": 0.1}, "density": 1.0,
             "position": [0.0, 0.0]},
            {"name": "box", "shape": {"type": "rounded_rect", "width": 0.2, "height": 0.2,
             "corner_radius": 0.0}, "density": 1.0, "position": [0.123456, 0.0]},
        ],
        "scene": {"gravity": [0.0, 0.0]},
    }  # fmt: skip
    with pytest.raises(SceneError, match=r"overlap by 0\.076544 m at t = 0"):
        scene_from_dict(data, source="x")


def test_arc_whose_end_is_off_the_next_edge_is_refused_by_the_shape_api():
    """A scene file gives arcs by centre, radius and angles, so their end points are on their
    circle by construction; a shape built in Python from edges is checked where edges meet."""
    arc = shapes.Arc((0.0, 0.0), 1.0, 0.0, math.pi)  # ends at (1, 0) and (-1, 0)
    with pytest.raises(ValueError, match=r"edge 0 ends at \(-1\.0, .*\) but edge 1 starts at"):
        shapes.shape_from_edges([arc, shapes.Segment((-0.9, 0.0), (1.0, 0.0))])
    with pytest.raises(ValueError, match="radius must be non-zero"):
        shapes.Arc((0.0, 0.0), 0.0, 0.0, 1.0)


def test_a_refused_value_never_escapes_as_another_exception(tmp_path):
    """Values that used to escape as OverflowError (math.* on huge sizes) or pass into the
    engine as 1/I = inf (a subnormal inertia) are SceneErrors."""
    for shape in ({"type": "disc", "radius": 1e200}, {"type": "half_disc", "radius": 1e170}):
        with pytest.raises(SceneError, match="field 'shape.radius'"):
            scene_from_dict({"body": [{"name": "b", "shape": shape, "density": 1.0,
                                       "position": [0, 0]}]})  # fmt: skip
    with pytest.raises(SceneError, match=r"field 'inertia'.*finite inverse"):
        scene_from_dict({"body": [{"name": "b", "shape": {"type": "disc", "radius": 0.1},
                                   "density": 1.0, "inertia": 5e-324, "position": [0, 0]}]})  # fmt: skip
    with pytest.raises(SceneError, match="field 'shape.radius': must be finite"):
        scene_from_dict({"body": [{"name": "b", "shape": {"type": "disc", "radius": 10**400},
                                   "density": 1.0, "position": [0, 0]}]})  # fmt: skip


def _loads_within(path, seconds: float = 5.0) -> str:
    """The SceneError message of ``load_scene(path)``, failing (not hanging) if it blocks."""
    result: list[str] = []

    def load() -> None:
        try:
            load_scene(path)
            result.append("loaded")
        except SceneError as exc:
            assert exc.__suppress_context__
            result.append(str(exc))

    worker = threading.Thread(target=load, daemon=True)
    worker.start()
    worker.join(seconds)
    assert result, f"load_scene({path}) blocked for {seconds} s"
    return result[0]


def test_a_scene_path_that_is_not_a_regular_file_is_refused_without_reading(tmp_path):
    """Issue #13: /dev/zero was read forever and a FIFO blocked the open; both are refused
    before reading, naming the path and what it is."""
    fifo = tmp_path / "pipe.toml"
    os.mkfifo(fifo)
    assert (
        _loads_within(fifo)
        == f"{fifo}: cannot read the file: a FIFO (named pipe), not a regular file"
    )
    assert (
        _loads_within(tmp_path)
        == f"{tmp_path}: cannot read the file: a directory, not a regular file"
    )
    if Path("/dev/zero").exists():
        assert _loads_within("/dev/zero") == (
            "/dev/zero: cannot read the file: a character device, not a regular file"
        )


def test_symbolic_link_loop_and_dangling_link_are_named(tmp_path):
    """Issue #13: a loop of links was reported as "not found"."""
    (tmp_path / "a.toml").symlink_to(tmp_path / "b.toml")
    (tmp_path / "b.toml").symlink_to(tmp_path / "a.toml")
    (tmp_path / "gone.toml").symlink_to(tmp_path / "missing.toml")
    loop, gone = tmp_path / "a.toml", tmp_path / "gone.toml"
    assert _loads_within(loop) == f"{loop}: cannot read the file: a loop of symbolic links"
    assert _loads_within(gone) == f"{gone}: file not found (a symbolic link to a missing file)"


def test_a_utf8_byte_order_mark_is_accepted_and_bad_bytes_after_it_counted_from_the_start(
    tmp_path,
):
    """Issue #13: a BOM (Windows editors write one) was a TOML syntax error."""
    source = SCENES / "disc_in_bowl.toml"
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + source.read_bytes())
    with_bom, plain = load_scene(path), load_scene(source)
    assert with_bom.names == plain.names and with_bom.name == plain.name
    np.testing.assert_array_equal(with_bom.poses(), plain.poses())
    path.write_bytes(b"\xef\xbb\xbf# caf\xe9\n")
    with pytest.raises(SceneError, match=r"not UTF-8 text \(byte 8\)$"):
        load_scene(path)


def test_values_nested_thousands_deep_in_a_dict_are_described_briefly():
    """The dict API reaches the checks without tomllib: a 5,000-deep list used to raise
    RecursionError while its repr was built for the message."""
    deep: object = 1.0
    for _ in range(5000):
        deep = [deep]
    body = {"name": "d", "shape": {"type": "disc", "radius": 0.1}, "density": 1.0, "position": deep}
    with pytest.raises(SceneError) as err:
        scene_from_dict({"body": [body]})
    assert str(err.value) == (
        "<dict>: body 'd' (#1): field 'position': expected a list of 2 numbers [x, y], "
        "got [[[[...]]]]"
    )


# -- the table in docs/bad-input.md --------------------------------------------------------------

TABLE_START, TABLE_END = "<!-- scene-errors:start -->", "<!-- scene-errors:end -->"


def _cell(text: str) -> str:
    return text.replace("|", "\\|")


def scene_table(directory: Path) -> str:
    """The Markdown table of SCENE_CASES and their messages (docs/bad-input.md)."""
    rows = ["| what | as written | message |", "|---|---|---|"]
    for case in SCENE_CASES:
        message = scene_message(case, directory)
        rows.append(f"| {case.category}: {case.what} | `{_cell(case.snippet)}` | "
                    f"`{_cell(message)}` |")  # fmt: skip
    return "\n".join(rows)


def test_docs_table_is_current(tmp_path):
    text = DOC.read_text()
    table = text.split(TABLE_START, 1)[1].split(TABLE_END, 1)[0].strip()
    assert table == scene_table(tmp_path), (
        "docs/bad-input.md is stale: run `python tests/runtime/test_bad_input.py` and paste "
        "its table between the scene-errors markers"
    )


# -- CLI ------------------------------------------------------------------------------------------


def test_simulate_refuses_a_directory_as_scene(tmp_path, capsys):
    from runtime.app import cli

    assert cli.main([str(tmp_path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"scene file '{tmp_path}' is a directory" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_simulate_reports_a_non_utf8_scene_in_one_line(tmp_path, capsys):
    from runtime.app import cli

    path = tmp_path / "latin1.toml"
    path.write_bytes(scene_text().encode() + b"# caf\xe9\n")
    assert cli.main([str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{path}: not UTF-8 text (byte" in err and len(err.splitlines()) == 1
    assert "Traceback" not in err and not (tmp_path / "out").exists()


def test_regenerate_with_an_empty_case_list_is_refused(tmp_path):
    from derive import cli

    args = ["--cases", ",", "--no-pdf", "--code-dir", str(tmp_path / "g")]
    with pytest.raises(SystemExit, match="valid cases"):
        with contextlib.redirect_stdout(io.StringIO()):
            cli.main([*args, "--docs-dir", str(tmp_path)])


# -- runtime failures -----------------------------------------------------------------------------

MESSAGE = re.compile(r"^step (\d+) at t = (\S+) s ")


def _small_scene():
    """A disc resting on a floor and a second one falling onto it: contacts from step 0."""
    return scene_from_dict(
        {
            "body": [
                {"name": "floor", "fixed": True,
                 "shape": {"type": "wall", "start": [-1.0, 0.0], "end": [1.0, 0.0]}},
                {"name": "resting", "shape": {"type": "disc", "radius": 0.1}, "density": 1000.0,
                 "position": [0.0, 0.1]},
                {"name": "falling", "shape": {"type": "disc", "radius": 0.05},
                 "density": 500.0, "position": [0.3, 0.3], "velocity": [0.0, -1.0]},
            ],
            "simulation": {"duration": 0.02, "dt": 0.001},
        },
        source="small",
    )  # fmt: skip


def _fail_from(monkeypatch, call: int, make_error):
    """Make the forces stage (ContactForces.solve) raise (or return garbage) from its
    ``call``-th call on (every stage the general way: settings.COMPILED off)."""
    monkeypatch.setattr(settings, "COMPILED", False)
    real = ContactForces.solve
    calls = {"n": 0}

    def solve(self, problem, rows):
        calls["n"] += 1
        if calls["n"] >= call:
            return make_error(real(self, problem, rows))
        return real(self, problem, rows)

    monkeypatch.setattr(ContactForces, "solve", solve)


def _check_failure(exc, reference, bodies: tuple[str, ...]) -> int:
    """The message names the step, the time and the contacts' bodies; .run holds the steps
    before the failing one (and perhaps its start), identical to an undisturbed run; .state is
    the state at the start of the failing step. Returns the step."""
    message = str(exc)
    match = MESSAGE.match(message)
    assert match, message
    k, t = int(match[1]), float(match[2])
    assert t == pytest.approx(k * reference.dt, rel=1e-6)
    for name in bodies:
        assert name in message.split("contacts:", 1)[1], message
    run = exc.run
    assert len(run.t) in (k, k + 1)  # the failing step's start state may be recorded too
    for got, want in zip(run.poses, reference.poses[: len(run.t)], strict=True):
        np.testing.assert_array_equal(got, want)
    poses, velocities = exc.state
    np.testing.assert_array_equal(poses, reference.poses[k])
    assert np.all(np.isfinite(velocities)) and velocities.shape == poses.shape
    return k


def test_contact_solver_failure_is_a_simulation_error_keeping_the_state(monkeypatch):
    monkeypatch.setattr(settings, "COMPILED", False)
    reference = runtime.simulate(_small_scene())
    sample = {"n": 0}
    real = ContactForces.solve

    def count(self, *args):
        sample["n"] += 1
        return real(self, *args)

    monkeypatch.setattr(ContactForces, "solve", count)
    runtime.simulate(_small_scene(), duration=0.005)
    halfway = sample["n"]  # calls in 5 steps: fail in the 6th or so

    def boom(_solution):
        raise ContactSolverError("contact 0 cannot be driven to zero: infeasible (test)", [0])

    _fail_from(monkeypatch, halfway + 1, boom)
    with pytest.raises(runtime.SimulationError) as info:
        runtime.simulate(_small_scene())
    k = _check_failure(info.value, reference, ("resting/floor",))
    assert k >= 4 and "infeasible (test)" in str(info.value)
    assert isinstance(info.value.__cause__, ContactSolverError)


def test_infeasible_contact_set_names_step_time_and_both_contacts():
    """A disc at the bottom of a bowl (R = 1) pinched by a fixed disc (R = 2) from above,
    moving sideways: the passage narrows both ways (the upper curve is flatter), so no
    contact forces can keep both gaps closed -- the LCP has no solution."""
    data = {
        "body": [
            {"name": "bowl", "fixed": True, "position": [0.0, 1.0],
             "shape": {"type": "bowl", "radius": 1.0, "start_angle": -2.5, "end_angle": -0.6}},
            {"name": "lid", "fixed": True, "position": [0.0, 2.2],
             "shape": {"type": "disc", "radius": 2.0}},
            {"name": "disc", "shape": {"type": "disc", "radius": 0.1}, "density": 1000.0,
             "position": [0.0, 0.1], "velocity": [1.0, 0.0]},
        ],
        "simulation": {"duration": 0.01, "dt": 0.001},
    }  # fmt: skip
    scene = scene_from_dict(data, source="pinch")
    with pytest.raises(runtime.SimulationError) as info:
        runtime.simulate(scene)
    message = str(info.value)
    assert message.startswith("step 0 at t = 0 s failed (") and "infeasible" in message
    assert "disc/bowl" in message and "disc/lid" in message
    poses, velocities = info.value.state
    np.testing.assert_array_equal(poses, scene.poses())
    np.testing.assert_array_equal(velocities, scene.velocities())
    assert info.value.run.t.size == 0


def _nan(solution):
    return dataclasses.replace(solution, accelerations=solution.accelerations * np.nan)


def _free_flight():
    """Two discs flying apart above a floor: no contacts for the first 0.05 s."""
    scene = _small_scene()
    scene.bodies[1].position = (-0.3, 0.5)
    scene.bodies[1].velocity = (-1.0, 0.0)
    scene.bodies[2].velocity = (1.0, 0.0)
    return scene


def test_a_non_finite_state_is_never_kept(monkeypatch):
    """Accelerations that turn NaN from the 7th evaluation on (as from a kernel overflow) stop
    the run at that step with the finite state before it; nothing non-finite is recorded."""
    reference = runtime.simulate(_free_flight())
    _fail_from(monkeypatch, 7, _nan)
    with pytest.raises(runtime.SimulationError) as info:
        runtime.simulate(_free_flight())
    assert "non-finite" in str(info.value)
    assert _check_failure(info.value, reference, ()) >= 1
    for key, values in info.value.run.arrays().items():
        if key != "min_gap":  # +inf there means "no contact"
            assert np.all(np.isfinite(values)), key


def test_nan_with_contacts_is_a_simulation_error_naming_them(monkeypatch):
    _fail_from(monkeypatch, 1, _nan)
    with pytest.raises(runtime.SimulationError, match=r"^step 0 at t = 0 s.*resting/floor"):
        runtime.simulate(_small_scene())


def test_overflowing_contact_terms_are_a_simulation_error():
    from runtime.model.scene import Body, Scene

    floor = Body.from_shape("floor", shapes.wall((-1.0, 0.0), (1.0, 0.0)), fixed=True)
    disc = Body.from_shape(
        "disc", shapes.disc(0.1), density=1.0, position=(0.0, 0.1), angular_velocity=1e200
    )  # the Python API checks no magnitudes; a scene file refuses this spin
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # never a NumPy overflow warning on the way
        with pytest.raises(runtime.SimulationError) as info:
            runtime.simulate(Scene("spin", [floor, disc]), duration=0.002, dt=0.001)
    message = str(info.value)
    assert message.startswith("step 0 at t = 0 s failed (the contact terms of 1 contact(s)")
    assert "not finite" in message and "1e+200" in message and message.endswith("disc/floor")


def test_energy_blow_up_is_a_simulation_error():
    """Explicit Euler at dt = 0.05 s pumps the disc in the bowl (E(0) = -265 J) up: the energy
    guard stops it when E rises by half the energy scale, with the energies in the message."""
    scene = load_scene(SCENES / "disc_in_bowl.toml")
    off = runtime.Guards(penetration=None)  # else the penetration guard stops it first
    with pytest.raises(runtime.SimulationError) as info:
        runtime.simulate(scene, duration=20.0, dt=0.05, method="euler", guards=off)
    found = re.match(r"^step (\d+) at t = \S+ s raised the energy from (\S+) J at t = 0 to (\S+) J, "
                     r"more than 0.5 x the scene's energy scale (\S+) J", str(info.value))  # fmt: skip
    assert found, str(info.value)
    k, e0, e1, scale = int(found[1]), *map(float, found.group(2, 3, 4))
    assert e1 - e0 > 0.5 * scale
    energies = info.value.run.energy  # the recorded steps before: all within the bound
    assert len(energies) in (k, k + 1) and max(energies) - e0 <= 0.5 * scale


def test_euler_drifting_into_the_bowl_is_a_penetration_error():
    scene = load_scene(SCENES / "disc_in_bowl.toml")
    with pytest.raises(runtime.SimulationError) as info:
        runtime.simulate(scene, duration=20.0, dt=0.05, method="euler")
    assert re.match(r"^step \d+ at t = \S+ s left disc/bowl overlapping by \S+ m", str(info.value))
    poses, velocities = info.value.state
    assert np.all(np.isfinite(poses)) and np.all(np.isfinite(velocities))


@pytest.mark.parametrize("value", [0.0, -1.0, math.nan, math.inf])
def test_guard_limits_must_be_positive_numbers(value):
    with pytest.raises(ValueError, match="penetration must be a finite number > 0 or None"):
        runtime.Guards(penetration=value)


def test_a_tunnelling_time_step_is_a_simulation_error():
    data = {
        "body": [
            {"name": "floor", "fixed": True,
             "shape": {"type": "wall", "start": [-40.0, 0.0], "end": [40.0, 0.0]}},
            {"name": "half", "shape": {"type": "half_disc", "radius": 0.5}, "density": 10.0,
             "position": [0.0, 0.42073549240394825], "angle": 1.0, "restitution": 1.0},
        ],
        "scene": {"contact_tolerance": 2.5e-7, "overlap_tolerance": 2.5e-10},
        "simulation": {"duration": 1.63, "dt": 0.0815},
    }  # fmt: skip
    scene = scene_from_dict(data, source="rocking")
    try:
        run = runtime.simulate(scene)
    except runtime.SimulationError as exc:
        assert MESSAGE.match(str(exc)) and "left half/floor overlapping by" in str(exc)
        return
    lowest = min(p[1, 1] for p in run.poses)  # the centre of mass, 0.21 m above the arc
    assert lowest > 0.0, f"the half disc fell through the floor (y = {lowest:.3g} m)"


def _tilted_box(scale: float, dt: float) -> runtime.Scene:
    """A rounded box (scale x 0.3 scale) resting tilted on one rounded corner on a floor,
    restitution 1, midpoint steps: it tips over, its corner sliding on the floor."""
    import strategies

    shape = {"type": "rounded_rect", "width": scale, "height": 0.3 * scale,
             "corner_radius": 0.0269 * scale}  # fmt: skip
    centred, _ = shapes.rounded_rect(scale, 0.3 * scale, 0.0269 * scale).centred()
    y = -strategies.lowest_point(centred, 2.614)  # the corner exactly on the floor
    data = {
        "body": [
            {"name": "floor", "fixed": True,
             "shape": {"type": "wall", "start": [-100 * scale, 0], "end": [100 * scale, 0]}},
            {"name": "box", "shape": shape, "density": 10.0, "position": [0.0, y],
             "angle": 2.614, "restitution": 1.0},
        ],
        "scene": {"contact_tolerance": 1e-7 * scale, "overlap_tolerance": 1e-9 * scale},
        "simulation": {"dt": dt, "duration": 2 * dt, "method": "midpoint"},
    }  # fmt: skip
    return scene_from_dict(data, source=f"tilted box {scale:g} m")


def test_a_large_scene_does_not_chatter_where_its_small_twin_rests():
    small = runtime.simulate(_tilted_box(1.0, 0.0535 / math.sqrt(1000.0)))
    large = runtime.simulate(_tilted_box(1000.0, 0.0535))
    assert len(small.impact_times) <= 2
    assert len(large.impact_times) <= 10 + 10 * len(small.impact_times)


# -- the docs table: `python tests/runtime/test_bad_input.py` ----------------------------------

if __name__ == "__main__":
    sys.path.insert(0, str(ROOT))
    with tempfile.TemporaryDirectory() as scratch:
        print(scene_table(Path(scratch)))
