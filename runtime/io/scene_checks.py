"""Checks of a whole scene at load, after each body is valid on its own: tolerances against the
bodies' sizes, energies and momenta that float64 can hold, and overlaps at t = 0 (each names
the bodies and the field to change)."""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from decimal import ROUND_FLOOR, Decimal

import numpy as np

from runtime.collide.features import features
from runtime.io.scene_overlap import deepest_overlap
from runtime.io.scene_table import Table, body_label
from runtime.model.scene import Scene
from runtime.settings import SMALLEST, TOLERANCE_FRACTION

__all__ = ["check_finite_scales", "check_overlaps", "check_tolerances"]


def check_tolerances(scene: Scene, table: Table) -> None:
    """The contact and overlap tolerances are absolute lengths (defaults 1e-4 m and 1e-9 m):
    against a small body they stop being small.  A contact tolerance near a body's size holds
    resting bodies visibly apart (a resting contact is kept up to that gap), and an overlap
    tolerance near it lets overlapping bodies start; both are refused, naming the body, with
    a value to use that the loader accepts.  A body so small that no tolerance fits (at least
    SMALLEST, at most TOLERANCE_FRACTION of its half-width) is refused itself."""
    moving = [(k, b) for k, b in enumerate(scene.bodies) if not b.fixed]
    if not moving:
        return
    widths = [(float(features(b.shape).half_width), k) for k, b in moving]
    half, k = min(widths)
    limit = TOLERANCE_FRACTION * half
    label = body_label(k, scene.bodies[k].name)
    if limit < SMALLEST:
        Table({}, scene.source, label).fail(
            "shape",
            f"half-width {half:.6g} m is below {SMALLEST / TOLERANCE_FRACTION:g} m, the smallest "
            f"moving body: its contact and overlap tolerances (at least {SMALLEST:g} m, at most "
            f"{TOLERANCE_FRACTION:g} x its half-width) would not fit; make it larger",
        )
    suggestion = f"{_round_down(limit):g} m"
    effects = {
        "contact_tolerance": "would hold resting bodies that far apart",
        "overlap_tolerance": "would let bodies start that deep inside each other",
    }
    values = {
        "contact_tolerance": scene.contact_tolerance,
        "overlap_tolerance": scene.overlap_tolerance,
    }
    too_large = [key for key, value in values.items() if value > limit]
    for key in too_large:
        given = "" if table.has(key) else " (the default)"
        also = [f"{other} ({values[other]:g} m) too" for other in too_large if other != key]
        table.fail(
            key,
            f"{values[key]:g} m{given} is too large for {label}, half-width {half:.6g} m: it "
            f"{effects[key]}; set it to at most {suggestion} (half that half-width)"
            + "".join(f", and {text}" for text in also),
        )


def _round_down(x: float) -> float:
    """``x`` rounded down to 3 significant digits (a suggested limit that is not above it)."""
    exact = Decimal(x)
    return float(exact.quantize(Decimal(1).scaleb(exact.adjusted() - 2), rounding=ROUND_FLOOR))


def check_finite_scales(scene: Scene) -> None:
    """Every energy and momentum the engine derives from the initial state must be finite: the
    guards compare energies with the scene's energy scale (kinetic energy + m |g| (H + 2 r) per
    moving body, H the height the scene spans; runtime/step/guards.py) and the run records
    energies and momenta, so an overflow here used to be written as an `inf` energy and a run
    reported as a success.  Each moving body's terms and the running totals are checked; the
    first that overflows is named with its body and the field to change."""
    g = math.hypot(*scene.gravity)
    gx, gy = scene.gravity
    radii = [float(b.shape.bounding_radius) for b in scene.bodies]
    ys = [b.position[1] for b in scene.bodies]
    height = max(y + r for y, r in zip(ys, radii, strict=True)) - min(
        y - r for y, r in zip(ys, radii, strict=True)
    )
    totals: dict[str, float] = {}
    for k, body in enumerate(scene.bodies):
        if body.fixed:
            continue
        m, inertia, (x, y), (vx, vy), w = (body.mass, body.inertia, body.position,
                                           body.velocity, body.angular_velocity)  # fmt: skip
        mass, speed = f"mass {m:g} kg", math.hypot(vx, vy)
        terms = (  # field, what, its total's name (None: not summed), value, detail
            ("velocity", "its momentum", "momentum", m * speed, f"{mass}, speed {speed:g} m/s"),
            ("angular_velocity", "its angular momentum", None, inertia * abs(w),
             f"inertia {inertia:g} kg m^2"),
            ("velocity", "its kinetic energy", "kinetic energy",
             0.5 * m * speed * speed + 0.5 * inertia * w * w, mass),
            ("position", "its potential energy", "potential energy", -m * (gx * x + gy * y),
             f"{mass} at ({x:g}, {y:g}) m"),
            ("position", "its share of the energy scale, m |g| (H + 2 r),", "energy scale",
             m * g * (height + 2 * radii[k]), f"{mass}, H = {height:g} m the height the scene spans"),
        )  # fmt: skip
        for field, what, total, value, detail in terms:
            if not math.isfinite(value):
                _not_finite(scene, k, field, what, detail)
            if total is not None:
                totals[total] = totals.get(total, 0.0) + abs(value)
                if not math.isfinite(totals[total]):
                    _not_finite(scene, k, field, f"the scene's total {total}", "with this body")


def _not_finite(scene: Scene, k: int, field: str, what: str, detail: str) -> None:
    Table({}, scene.source, body_label(k, scene.bodies[k].name)).fail(
        field, f"{what} overflows float64 ({detail})"
    )


def check_overlaps(scene: Scene) -> None:
    """Refuse bodies that overlap at t = 0 by more than ``scene.overlap_tolerance``: first the
    contacts the engine would see, then deep overlaps that the contact finder leaves out."""
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        found = scene.contacts()
        deep = deepest_overlap(
            scene.shapes, scene.poses(), scene.fixed, scene.overlap_tolerance, scene.joined_pairs
        )
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
