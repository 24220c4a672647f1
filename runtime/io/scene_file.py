"""Scene files: a scene read from TOML or a dict, checked, with messages that name the cause.

It refuses bad input with a message naming the file, the body and the field (see
docs/scene-format.md), so that a typo never surfaces later as a NaN or a NumPy warning.
"""

from __future__ import annotations

import codecs
import errno
import os
import re
import stat
import tomllib
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from runtime.io.scene_checks import check_finite_scales, check_overlaps, check_tolerances
from runtime.io.scene_facing import check_facing
from runtime.io.scene_links import read_joints, read_springs
from runtime.io.scene_table import SceneError, SceneWarning, Table, body_label
from runtime.io.scene_validation import (
    SCENE_KEYS,
    SIMULATION_KEYS,
    TOP_LEVEL_KEYS,
    read_bodies,
    read_simulation,
)
from runtime.model.scene import Body, Scene, SimulationDefaults
from runtime.settings import SCENE_FILE_MAX_BYTES

__all__ = ["SceneError", "SceneWarning", "load_scene", "scene_from_dict"]


# -- reading ---------------------------------------------------------------------------------


def load_scene(path: str | Path) -> Scene:
    """Read a scene file (TOML, format in docs/scene-format.md); raise SceneError if invalid."""
    source = str(path)
    data = _parse_toml(_read_text(path, source), source)
    return scene_from_dict(data, source=source, default_name=Path(path).stem)


def _read_text(path: str | Path, source: str) -> str:
    """The file's text: a regular file of at most SCENE_FILE_MAX_BYTES, UTF-8 with or without a
    byte-order mark.  It is opened without blocking and checked before reading, so a FIFO, a
    device such as /dev/zero or a directory is refused instead of hanging or filling memory."""
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except FileNotFoundError:
        dangling = " (a symbolic link to a missing file)" if os.path.islink(path) else ""
        raise SceneError(f"{source}: file not found{dangling}") from None
    except OSError as exc:
        reason = "a loop of symbolic links" if exc.errno == errno.ELOOP else exc.strerror or exc
        raise SceneError(f"{source}: cannot read the file: {reason}") from None
    try:
        mode = os.fstat(fd).st_mode
        chunks, size = [], 0
        while (
            stat.S_ISREG(mode) and size <= SCENE_FILE_MAX_BYTES and (chunk := os.read(fd, 1 << 20))
        ):
            chunks.append(chunk)
            size += len(chunk)
    except OSError as exc:
        raise SceneError(f"{source}: cannot read the file: {exc.strerror or exc}") from None
    finally:
        os.close(fd)
    if not stat.S_ISREG(mode):
        raise SceneError(
            f"{source}: cannot read the file: {_file_kind(mode)}, not a regular file"
        ) from None
    if size > SCENE_FILE_MAX_BYTES:
        limit = SCENE_FILE_MAX_BYTES / 2**20
        raise SceneError(
            f"{source}: cannot read the file: larger than {limit:g} MiB, the limit of a scene file"
        ) from None
    data = b"".join(chunks)
    bom = len(codecs.BOM_UTF8) if data.startswith(codecs.BOM_UTF8) else 0
    try:
        return data[bom:].decode("utf-8")
    except UnicodeDecodeError as exc:
        raise SceneError(f"{source}: not UTF-8 text (byte {exc.start + bom})") from None


def _file_kind(mode: int) -> str:
    kinds = ((stat.S_ISDIR, "a directory"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
             (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
             (stat.S_ISSOCK, "a socket"))  # fmt: skip
    return next((name for test, name in kinds if test(mode)), "not a file")


def _parse_toml(text: str, source: str) -> dict[str, Any]:
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        message = str(exc)
        match = re.fullmatch(r"(.*) \(at line (\d+), column (\d+)\)", message, re.S)
        if match:
            message = f"line {match[2]}, column {match[3]}: TOML syntax error: {match[1]}"
        else:
            message = f"TOML syntax error: {message}"
        raise SceneError(f"{source}: {message}") from None
    except RecursionError:  # tomllib recurses once per level of arrays or inline tables
        raise SceneError(
            f"{source}: TOML nested too deeply: arrays or inline tables hundreds of levels deep"
        ) from None


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
        name=scene_table.name("name", default_name),
        description=scene_table.string("description", ""),
        bodies=bodies,
        gravity=scene_table.vector("gravity", (0.0, -9.81)),
        contact_tolerance=scene_table.number("contact_tolerance", 1e-4, check="positive"),
        overlap_tolerance=scene_table.number("overlap_tolerance", 1e-9, check="positive"),
        simulation=simulation,
        source=source,
        mutual_gravity=scene_table.number("mutual_gravity", 0.0, check="nonnegative"),
    )
    scene.joints = read_joints(top, bodies)
    scene.springs = read_springs(top, bodies)
    check_tolerances(scene, scene_table)
    check_finite_scales(scene)
    check_facing(scene)
    check_overlaps(scene)
    return scene
