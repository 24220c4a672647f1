"""Checked reading of a scene's ``[[joint]]`` and ``[[spring]]`` tables (issue #16).

Why a module of its own: a link names bodies, so it can only be checked once every body is
built (a name that is no body, a body linked to itself, two fixed ends that nothing can move);
each mistake comes back as one line naming the table (``joint #2``) and the field, like the
body errors of runtime/io/scene_validation.py.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from runtime.io.scene_hints import closest
from runtime.io.scene_table import REQUIRED, Table, describe, is_sequence
from runtime.model.links import (
    JOINT_KINDS,
    WORLD,
    Joint,
    Spring,
    anchor_in_body,
    anchor_in_world,
    body_point_in_world,
)
from runtime.settings import JOINT_ASSEMBLY

__all__ = ["JOINT_KEYS", "SPRING_KEYS", "read_joints", "read_springs"]

JOINT_KEYS = ("type", "body1", "body2", "anchor1", "anchor2")
SPRING_KEYS = ("body1", "body2", "anchor1", "anchor2", "rest_length", "stiffness", "damping")
WORLD_NAME = "world"


def _tables(top: Table, key: str) -> list[Table]:
    raw = top.data.get(key, [])
    if isinstance(raw, Mapping):
        top.fail(key, f"expected an array of tables: write [[{key}]], not [{key}]")
    if not is_sequence(raw):
        top.fail(key, f"expected an array of [[{key}]] tables, got {describe(raw)}")
    return [Table(t, top.source, f"{key} #{k + 1}", field="") for k, t in enumerate(raw)]


def _ends(table: Table, bodies: list) -> tuple[int, int, tuple, tuple]:
    """(body1, body2, anchor 1 in body coordinates, anchor 2 in body or world coordinates) of
    a link table, body 1 the moving end (swapped if only body 2 moves)."""
    names = [b.name for b in bodies]
    index = []
    for key in ("body1", "body2"):
        name = table.string(key, REQUIRED)
        if name == WORLD_NAME:
            if WORLD_NAME in names:
                table.fail(key, "ambiguous: a body is named 'world'; rename that body")
            index.append(WORLD)
        elif name in names:
            index.append(names.index(name))
        else:
            table.fail(key, f"no body named {name!r}; {closest(name, names, 'bodies')}")
    anchors = [table.vector(key, (0.0, 0.0)) for key in ("anchor1", "anchor2")]
    if index[0] == index[1]:
        table.fail("body2", "a link needs two different ends; it links the body to itself")
    moving = [k >= 0 and not bodies[k].fixed for k in index]
    if not any(moving):
        table.fail("body2", "both ends are fixed (or the world): nothing can move; remove it")
    if not moving[0]:
        index.reverse()
        anchors.reverse()
    ends = []
    for k, anchor in zip(index, anchors, strict=True):
        if k == WORLD:
            ends.append((WORLD, anchor))
        elif bodies[k].fixed:
            ends.append((WORLD, anchor_in_world(bodies[k], anchor)))
        else:
            ends.append((k, anchor_in_body(bodies[k], anchor)))
    return ends[0][0], ends[1][0], ends[0][1], ends[1][1]


def _world_separation(bodies: list, body1: int, body2: int, a1, a2) -> tuple[float, float]:
    """|p1 - p2| at t = 0 and the size of the anchor positions (for a relative tolerance)."""
    p1 = body_point_in_world(bodies[body1], a1)
    p2 = a2 if body2 == WORLD else body_point_in_world(bodies[body2], a2)
    size = max(1.0, math.hypot(*p1), math.hypot(*p2))
    return math.hypot(p1[0] - p2[0], p1[1] - p2[1]), size


def read_joints(top: Table, bodies: list) -> list[Joint]:
    """The ``[[joint]]`` tables as runtime.model.links.Joint (anchors in body coordinates)."""
    joints = []
    for k, table in enumerate(_tables(top, "joint")):
        table.check_keys(JOINT_KEYS)
        kind = table.string("type", REQUIRED)
        if kind not in JOINT_KINDS:
            table.fail(
                "type", f"unknown joint type {kind!r}; {closest(kind, list(JOINT_KINDS), 'types')}"
            )
        body1, body2, a1, a2 = _ends(table, bodies)
        length, size = _world_separation(bodies, body1, body2, a1, a2)
        if kind == "pin" and length > JOINT_ASSEMBLY * size:
            table.fail(
                "anchor2",
                f"the anchors are {length:.6g} m apart at t = 0; a pin holds them together: "
                'give anchor2 at anchor1\'s place (or use type = "distance")',
            )
        if kind == "distance" and length <= JOINT_ASSEMBLY * size:
            table.fail(
                "anchor2",
                "the anchors coincide at t = 0, so a distance joint has no direction; "
                'use type = "pin"',
            )
        name = f"joint #{k + 1}"
        joints.append(
            Joint(name, kind, body1, body2, a1, a2, length if kind == "distance" else 0.0)
        )
    return joints


def read_springs(top: Table, bodies: list) -> list[Spring]:
    """The ``[[spring]]`` tables as runtime.model.links.Spring (anchors in body coordinates)."""
    springs = []
    for k, table in enumerate(_tables(top, "spring")):
        table.check_keys(SPRING_KEYS)
        body1, body2, a1, a2 = _ends(table, bodies)
        springs.append(
            Spring(
                f"spring #{k + 1}",
                body1,
                body2,
                a1,
                a2,
                rest_length=table.number("rest_length", REQUIRED, check="nonnegative"),
                stiffness=table.number("stiffness", REQUIRED, check="nonnegative"),
                damping=table.number("damping", 0.0, check="nonnegative"),
            )
        )
    return springs


def read_body_damping(table: Table, fixed: bool) -> dict[str, Any]:
    """A body's ``linear_damping`` and ``angular_damping`` (1/s, >= 0), for Body.from_shape."""
    values = {}
    for key in ("linear_damping", "angular_damping"):
        if table.has(key):
            if fixed:
                table.fail(key, "a fixed body cannot move; remove this field")
            values[key] = table.number(key, check="nonnegative")
    return values
