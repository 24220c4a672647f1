"""Independent references for contact tests: the gap formulas of docs/conventions.md, dense
boundary samples of a shape, exact distances to straight and circular edges, and
:func:`check_contacts`, the contract every found contact set must meet.

Written from the definitions only; it shares no code with the contact finder or the kernels
(it reads only the Contacts contract: array layout, case ids, geometry columns), so a test
comparing against it can fail when the contact finder is wrong.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import pytest

from generated import CASE_ID, GEOMETRY_COLUMNS
from runtime.collide.contact_set import KIND_NAMES, Contacts
from runtime.model.shapes import Arc, Segment, Shape

CASE_NAME = {number: name for name, number in CASE_ID.items()}


def rot(th: float, v) -> np.ndarray:
    c, s = math.cos(th), math.sin(th)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def geometry_dict(case: str, row) -> dict[str, float]:
    """The kernel keyword arguments of one geometry row (generated.GEOMETRY_COLUMNS)."""
    return {name: float(row[column]) for name, column in GEOMETRY_COLUMNS[case].items()}


def reference_gap(case: str, g: dict, pose1, pose2) -> tuple[float, np.ndarray]:
    """Gap and unit normal (body 2 -> body 1) from the formulas of docs/conventions.md."""
    x1, y1, t1 = pose1
    x2, y2, t2 = pose2
    if case.startswith("vertex"):
        one, r1 = np.array([x1, y1]) + rot(t1, (g["px1"], g["py1"])), 0.0
    else:
        one, r1 = np.array([x1, y1]) + rot(t1, (g["cx1"], g["cy1"])), g["r1"]
    if case.endswith("edge"):
        n = rot(t2, (g["nx2"], g["ny2"]))
        e = np.array([x2, y2]) + rot(t2, (g["ex2"], g["ey2"]))
        return float(n @ (one - e) - r1), n
    v = one - (np.array([x2, y2]) + rot(t2, (g["cx2"], g["cy2"])))
    sigma = math.copysign(1.0, g["r2"])
    return float(sigma * np.hypot(*v) - g["r2"] - r1), sigma * v / np.hypot(*v)


def sample_boundary(shape: Shape, pose, per_unit: int = 3000) -> np.ndarray:
    """World points along the whole boundary, about ``per_unit`` per unit length."""
    pts = []
    for e in shape.edges:
        if isinstance(e, Segment):
            t = np.linspace(0, 1, int(per_unit * e.length) + 2)[:, None]
            pts.append(np.array(e.start) * (1 - t) + np.array(e.end) * t)
        elif isinstance(e, Arc):
            a = np.linspace(e.start_angle, e.end_angle, int(per_unit * abs(e.radius) * e.span) + 2)
            pts.append(np.c_[np.cos(a), np.sin(a)] * abs(e.radius) + e.centre)
        else:
            t = np.linspace(0, 2 * np.pi, int(per_unit * 2 * np.pi * max(e.a, e.b)))
            x, y = e.a * np.cos(t), e.b * np.sin(t)
            c, s = math.cos(e.angle), math.sin(e.angle)
            pts.append(np.c_[c * x - s * y, s * x + c * y] + e.centre)
    p = np.vstack(pts)
    c, s = math.cos(pose[2]), math.sin(pose[2])
    return np.c_[pose[0] + c * p[:, 0] - s * p[:, 1], pose[1] + s * p[:, 0] + c * p[:, 1]]


def signed_distance_to_convex_polygon(q, corners) -> float:
    """Exact: distance to the nearest edge, negative inside (corners counter-clockwise)."""
    best, inside = math.inf, True
    for a, b in zip(corners, np.roll(corners, -1, axis=0), strict=True):
        d = b - a
        t = np.clip((q - a) @ d / (d @ d), 0, 1)
        best = min(best, float(np.hypot(*(q - a - t * d))))
        inside &= bool(d[0] * (q - a)[1] - d[1] * (q - a)[0] > 0)
    return -best if inside else best


def distance_to_edges(points: np.ndarray, shape: Shape, pose) -> np.ndarray:
    """Exact distance of each point to the nearest point of the (world) edges of a shape made
    of segments and arcs."""
    best = np.full(len(points), np.inf)
    for e in shape.edges:
        if isinstance(e, Segment):
            a = np.array(pose[:2]) + rot(pose[2], e.start)
            b = np.array(pose[:2]) + rot(pose[2], e.end)
            d = b - a
            t = np.clip((points - a) @ d / (d @ d), 0, 1)
            best = np.minimum(best, np.hypot(*(points - a - t[:, None] * d).T))
        else:
            c = np.array(pose[:2]) + rot(pose[2], e.centre)
            v = points - c
            angle = np.arctan2(v[:, 1], v[:, 0]) - pose[2]
            inside = (angle - e.start_angle) % (2 * np.pi) <= e.span
            ends = [np.array(pose[:2]) + rot(pose[2], p) for p in e.end_points]
            to_ends = np.minimum(*(np.hypot(*(points - p).T) for p in ends))
            best = np.minimum(
                best, np.where(inside, np.abs(np.hypot(*v.T) - abs(e.radius)), to_ends)
            )
    return best


GEOMETRY_ARGS = {
    "vertex_edge": {"px1", "py1", "ex2", "ey2", "nx2", "ny2"},
    "vertex_circle": {"px1", "py1", "cx2", "cy2", "r2"},
    "circle_edge": {"cx1", "cy1", "r1", "ex2", "ey2", "nx2", "ny2"},
    "circle_circle": {"cx1", "cy1", "r1", "cx2", "cy2", "r2"},
}


class Row(NamedTuple):
    """One row of a Contacts, readable in assertions (built here from the arrays)."""

    case: str
    body1: int
    body2: int
    geometry: dict
    gap: float
    feature: tuple
    point: tuple
    normal: tuple


def rows(found: Contacts) -> list[Row]:
    out = []
    for k in range(len(found)):
        case = CASE_NAME[int(found.case[k])]
        kind1, index1, kind2, index2 = found.feature[k].tolist()
        out.append(Row(case, int(found.body1[k]), int(found.body2[k]),
                       geometry_dict(case, found.geometry[k]), float(found.gap[k]),
                       ((KIND_NAMES[kind1], index1), (KIND_NAMES[kind2], index2)),
                       tuple(found.point[k].tolist()), tuple(found.normal[k].tolist())))  # fmt: skip
    return out


def same(got, want, atol: float = 1e-12) -> None:
    np.testing.assert_allclose(
        np.asarray(got, dtype=float), np.asarray(want, dtype=float), rtol=0, atol=atol
    )


def check_contacts(found: Contacts, poses) -> None:
    """Every contact against the formulas of docs/conventions.md, and the array contract:
    dtypes and shapes, unused geometry columns 0, radii signs, pairs in order."""
    m = len(found)
    assert found.case.dtype == found.body1.dtype == found.feature.dtype == np.int64
    assert found.geometry.shape == (m, 7) and found.feature.shape == (m, 4)
    assert found.point.shape == found.normal.shape == (m, 2) and found.gap.shape == (m,)
    pairs = np.c_[np.minimum(found.body1, found.body2), np.maximum(found.body1, found.body2)]
    assert [tuple(p) for p in pairs.tolist()] == sorted(tuple(p) for p in pairs.tolist())
    scale = 1.0 + float(np.abs(np.asarray(poses)[:, :2]).max())
    for k, c in enumerate(rows(found)):
        gap, n = reference_gap(c.case, c.geometry, poses[c.body1], poses[c.body2])
        assert c.gap == pytest.approx(gap, rel=1e-12, abs=1e-13 * scale), c
        np.testing.assert_allclose(c.normal, n, atol=1e-12)
        assert math.isclose(math.hypot(*c.normal), 1.0, rel_tol=1e-12)
        assert set(c.geometry) == GEOMETRY_ARGS[c.case]
        used = list(GEOMETRY_COLUMNS[c.case].values())
        assert not np.any(np.delete(found.geometry[k], used)), "unused geometry columns are 0"
        if "r1" in c.geometry:
            assert c.geometry["r1"] > 0
        if c.case == "circle_circle" or (c.case == "vertex_circle" and c.feature[1][0] == "edge"):
            assert c.geometry["r2"] != 0
        if c.feature[1][0] == "vertex":  # corner on corner: a circle of radius +0
            assert c.case == "vertex_circle" and math.copysign(1, c.geometry["r2"]) == 1
        hash(c.feature)
