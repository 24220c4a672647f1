"""Scene files: a scene read from TOML or a dict, checked, with messages that name the cause.

It refuses bad input with a message naming the file, the body and the field (see
docs/scene-format.md), so that a typo never surfaces later as a NaN or a NumPy warning.
"""

from __future__ import annotations

import math
import re
import tomllib
import warnings
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from runtime.collide.features import features as _features
from runtime.io.scene_overlap import deepest_overlap
from runtime.io.scene_validation import (
    SCENE_KEYS,
    SIMULATION_KEYS,
    TOP_LEVEL_KEYS,
    SceneError,
    Table,
    body_label,
    read_bodies,
    read_simulation,
)
from runtime.model.scene import Body, Scene, SimulationDefaults

__all__ = ["SceneError", "load_scene", "scene_from_dict"]


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
    widths = [(float(_features(b.shape).half_width), k) for k, b in moving]
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
        found = scene.contacts()
        deep = deepest_overlap(scene.shapes, scene.poses(), scene.fixed, scene.overlap_tolerance)
    for k, gap in enumerate(found.gap.tolist()):
        if gap < -scene.overlap_tolerance or not math.isfinite(gap):
            amount = f"by {-gap:.6g} m" if math.isfinite(gap) else "(coincident features)"
            detail = f"{found.case_name(k)} contact at {_point(found.point[k])}"
            _overlap_error(scene, int(found.body1[k]), int(found.body2[k]), amount, detail)
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
