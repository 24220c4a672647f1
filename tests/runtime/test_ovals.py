"""Ovals: a contact on an ellipse stands for its osculating circle at the contact point, and
ContactFinder.refresh_ovals finds that point again when the bodies move.  References: the
ellipse's exact support function (distance from a line), and distances between curves by
dense sampling refined with scipy's minimiser (independent of runtime/collide/ovals.py)."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
from contact_reference import rows
from scipy.optimize import minimize
from scipy.spatial import cKDTree

from runtime.collide.finder import ContactFinder
from runtime.model import shapes

pytestmark = pytest.mark.filterwarnings("error")
FLOOR = shapes.wall((-5.0, 0.0), (5.0, 0.0))
OVAL = shapes.ellipse(0.4, 0.15)


def kernel_gap(found, k: int, poses) -> float:
    """The generated NumPy kernel's gap of contact k of ``found`` at ``poses``."""
    c = rows(found)[k]
    x1, y1, th1 = poses[c.body1]
    x2, y2, th2 = poses[c.body2]
    kernel = importlib.import_module(f"generated.{c.case}")
    return float(kernel.gap(x1=x1, y1=y1, th1=th1, x2=x2, y2=y2, th2=th2, **c.geometry))


def curve(shape, pose):
    """t -> world point of the single edge of a disc or an ellipse shape (vectorised)."""
    e = shape.edges[0]
    a, b = (e.a, e.b) if hasattr(e, "a") else (abs(e.radius), abs(e.radius))
    angle = getattr(e, "angle", 0.0) + pose[2]
    c, s = math.cos(angle), math.sin(angle)
    cx, cy = np.array(pose[:2]) + [
        math.cos(pose[2]) * e.centre[0] - math.sin(pose[2]) * e.centre[1],
        math.sin(pose[2]) * e.centre[0] + math.cos(pose[2]) * e.centre[1],
    ]

    def point(t):
        x, y = a * np.cos(t), b * np.sin(t)
        return np.stack([cx + c * x - s * y, cy + s * x + c * y], axis=-1)

    return point


def curve_distance(p1, p2) -> float:
    """Smallest distance between two closed curves t -> point: dense samples, then refined."""
    t = np.linspace(0, 2 * np.pi, 4000, endpoint=False)
    d, k = cKDTree(p2(t)).query(p1(t))
    i = int(np.argmin(d))
    res = minimize(lambda v: np.hypot(*(p1(v[0]) - p2(v[1]))), [t[i], t[k[i]]],
                   method="Nelder-Mead", options={"xatol": 1e-13, "fatol": 1e-15})  # fmt: skip
    return float(res.fun)


def test_refresh_at_the_same_poses_changes_nothing():
    poses = np.array([[0, 0, 0], [0.3, 0.15 + 1e-3, 0.2]])
    finder = ContactFinder([FLOOR, OVAL], [True, False])
    found = finder.find(poses, 0.05)
    again = finder.refresh_ovals(poses, found)
    np.testing.assert_allclose(again.geometry, found.geometry, rtol=0, atol=1e-14)
    plain = ContactFinder([FLOOR, shapes.disc(0.1)], [True, False])
    disc = plain.find(np.array([[0, 0, 0], [0, 0.1, 0]]), 1e-3)
    assert plain.refresh_ovals(np.zeros((2, 3)), disc) is disc  # no ovals: nothing to do


@pytest.mark.parametrize("turn", [0.05, 0.3, 1.0, -2.0])
def test_ellipse_on_a_floor_refreshed_gap_is_its_exact_height(turn):
    """After the oval turns (and moves), the kernel's gap with the refreshed osculating circle
    is the exact distance of the ellipse from the floor, y - sqrt(a^2 sin^2 th + b^2 cos^2 th)
    (its support function); with the stale circle it is not."""
    a, b = 0.4, 0.15
    start = np.array([[0, 0, 0], [0.3, b + 1e-4, 0.2]])
    finder = ContactFinder([FLOOR, OVAL], [True, False])
    found = finder.find(start, 0.05)
    assert len(found) == 1
    th = 0.2 + turn
    height = math.sqrt(a * a * math.sin(th) ** 2 + b * b * math.cos(th) ** 2)
    moved = np.array([[0, 0, 0], [0.31, height + 2e-3, th]])  # turned, lowered or lifted
    exact = moved[1, 1] - height
    refreshed = finder.refresh_ovals(moved, found)
    assert kernel_gap(refreshed, 0, moved) == pytest.approx(exact, abs=1e-14)
    assert abs(kernel_gap(found, 0, moved) - exact) > 1e-6  # the stale circle is wrong
    fresh = finder.find(moved, 1.0)  # and the narrow phase agrees
    np.testing.assert_allclose(refreshed.geometry, fresh.geometry, atol=1e-12)


@pytest.mark.parametrize(
    ("other", "pose", "move"),
    [
        (shapes.ellipse(0.3, 0.2), [0.75, 0.1, 0.4], [0.02, -0.03, 0.5]),  # two ovals
        (shapes.disc(0.25), [0.0, 0.42, 0.0], [0.03, 0.01, 0.3]),  # a disc on an oval
    ],
)
def test_convex_curve_on_an_ellipse_refreshed_gap_is_the_curve_distance(other, pose, move):
    poses = np.array([[0.0, 0.0, 0.3], pose])
    finder = ContactFinder([OVAL, other], [False, False])
    found = finder.find(poses, 0.2)
    assert len(found) == 1 and found.case[0] == 3  # circle_circle
    moved = poses + [[0.0, 0.0, -0.2], move]
    refreshed = finder.refresh_ovals(moved, found)
    exact = curve_distance(curve(OVAL, moved[0]), curve(other, moved[1]))
    assert kernel_gap(refreshed, 0, moved) == pytest.approx(exact, abs=1e-9)
    assert abs(kernel_gap(found, 0, moved) - exact) > 1e-5


def test_ellipse_in_a_bowl_refreshed_gap_is_the_distance_to_the_bowl():
    """Inside a concave arc (radius R about the origin) the gap is R minus the ellipse's
    farthest distance from the centre."""
    bowl = shapes.bowl(1.0, -2.8, -0.3)
    poses = np.array([[0, 0, 0], [0.05, -0.84, 0.1]])
    finder = ContactFinder([bowl, OVAL], [True, False])
    found = finder.find(poses, 0.05)
    assert len(found) == 1 and found.geometry[0, 5] == -1.0
    moved = poses + [[0, 0, 0], [0.1, -0.05, 0.4]]
    refreshed = finder.refresh_ovals(moved, found)
    point = curve(OVAL, moved[1])
    t = np.linspace(0, 2 * np.pi, 20000, endpoint=False)
    k = int(np.argmax(np.hypot(*point(t).T)))
    far = -minimize(lambda v: -np.hypot(*point(v[0])), [t[k]], method="Nelder-Mead",
                    options={"xatol": 1e-13, "fatol": 1e-16}).fun  # fmt: skip
    assert kernel_gap(refreshed, 0, moved) == pytest.approx(1.0 - far, abs=1e-9)
    assert abs(kernel_gap(found, 0, moved) - (1.0 - far)) > 1e-5


def test_corner_on_an_ellipse_refreshed_gap_is_the_point_distance():
    square = shapes.polygon([(-0.2, -0.2), (0.2, -0.2), (0.2, 0.2), (-0.2, 0.2)])
    poses = np.array([[0, 0, 0.0], [0.0, 0.15 + 0.01 + 0.2 * math.sqrt(2), math.pi / 4]])
    finder = ContactFinder([OVAL, square], [False, False])
    found = finder.find(poses, 0.05)
    (k,) = np.flatnonzero(found.case == 1)  # vertex_circle: the lowest corner on the oval
    moved = poses + [[0.0, 0.0, 0.3], [0.05, 0.0, 0.02]]
    refreshed = finder.refresh_ovals(moved, found)
    corner = rows(found)[k].feature[0][1]
    p = moved[1, :2] + np.array(
        [
            [math.cos(moved[1, 2]), -math.sin(moved[1, 2])],
            [math.sin(moved[1, 2]), math.cos(moved[1, 2])],
        ]
    ) @ np.array(square.vertices[corner])
    exact = curve_distance(lambda t: np.broadcast_to(p, np.shape(t) + (2,)), curve(OVAL, moved[0]))
    c, s = math.cos(moved[0, 2]), math.sin(moved[0, 2])
    inside = ((c * p[0] + s * p[1]) / 0.4) ** 2 + ((c * p[1] - s * p[0]) / 0.15) ** 2 < 1
    exact *= -1 if inside else 1  # the corner sinks into the turned oval: a penetration
    assert kernel_gap(refreshed, k, moved) == pytest.approx(exact, abs=1e-9)
