"""Checks of a whole scene at load, after each body is valid on its own: tolerances against the
bodies' sizes and overlaps at t = 0 (each names the bodies and the field to change)."""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence

import numpy as np

from runtime.collide import narrowphase as _narrowphase
from runtime.io.scene_overlap import deepest_overlap
from runtime.io.scene_validation import Table, body_label
from runtime.model.scene import Scene
from runtime.settings import TOLERANCE_FRACTION

__all__ = ["check_overlaps", "check_tolerances"]


def check_tolerances(scene: Scene, table: Table) -> None:
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


def check_overlaps(scene: Scene) -> None:
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
