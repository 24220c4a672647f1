"""The exact distance to an ellipse (runtime/model/ellipse_distance.py) against references that
do not use it: points placed along a normal at a known distance (exact by construction), the
closed forms on the axes, and a dense-sampling-plus-local-minimisation oracle."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from runtime.model.ellipse_distance import ellipse_distance, nearest_on_ellipse

pytestmark = pytest.mark.filterwarnings("error")


def on_ellipse(a: float, b: float, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Points at parameters ``t`` and their outward unit normals."""
    p = np.c_[a * np.cos(t), b * np.sin(t)]
    n = np.c_[b * np.cos(t), a * np.sin(t)]
    return p, n / np.hypot(*n.T)[:, None]


@pytest.mark.parametrize(
    ("a", "b"), [(2.0, 0.5), (0.5, 2.0), (1.0, 1.0), (1.0, 1e-6), (3e-9, 1e-9)]
)
def test_points_along_the_outward_normal_are_at_their_offset(a, b):
    t = np.random.default_rng(1).uniform(0, 2 * math.pi, 400)
    p, n = on_ellipse(a, b, t)
    size = max(a, b)
    for h in (0.0, 1e-9 * size, 1e-3 * size, 0.3 * size, 10 * size):
        np.testing.assert_allclose(
            ellipse_distance(a, b, p + h * n), h, rtol=0, atol=4e-16 * (size + h)
        )
    np.testing.assert_allclose(nearest_on_ellipse(a, b, p + 0.3 * size * n), p, atol=4e-16 * size)


def test_points_along_the_inward_normal_before_the_axis():
    """Inside, p - h n still has p as its nearest point while h is below the distance from p
    to the long axis along the normal, b N / a (a >= b, N the normal's length)."""
    a, b = 1.7, 0.6
    t = np.random.default_rng(2).uniform(0, 2 * math.pi, 400)
    p, n = on_ellipse(a, b, t)
    reach = b * np.hypot(b * np.cos(t), a * np.sin(t)) / a
    for fraction in (1e-9, 0.1, 0.9):
        np.testing.assert_allclose(ellipse_distance(a, b, p - fraction * reach[:, None] * n),
                                   fraction * reach, rtol=0, atol=1e-15)  # fmt: skip


def test_points_on_the_axes_match_the_closed_forms():
    a, b = 2.0, 1.0
    pts = np.array([[0.0, 0.0], [0.5, 0.0], [-0.5, 0.0], [1.6, 0.0], [3.0, 0.0], [0.0, 0.3],
                    [0.0, -4.0]])  # fmt: skip
    # on the long axis inside |x| < (a^2 - b^2)/a the nearest points are off the axis, at
    # x = a^2 x0 / (a^2 - b^2); beyond it, the vertex (a, 0); on the short axis, (0, +-b)
    x = a * a * 0.5 / (a * a - b * b)
    near = np.array([[0.0, b], [x, b * math.sqrt(1 - (x / a) ** 2)], [-x, b * math.sqrt(1 - (x / a) ** 2)],
                     [a, 0.0], [a, 0.0], [0.0, b], [0.0, -b]])  # fmt: skip
    np.testing.assert_allclose(nearest_on_ellipse(a, b, pts), near, atol=1e-15)
    np.testing.assert_allclose(nearest_on_ellipse(b, a, pts[:, ::-1]), near[:, ::-1], atol=1e-15)


def test_random_points_against_a_sampling_oracle():
    rng = np.random.default_rng(3)
    for _ in range(60):
        a, b = rng.uniform(0.01, 3.0, 2)
        p = rng.normal(size=2) * rng.choice([0.01, 0.3, 1.0, 5.0])
        t = np.linspace(0, 2 * math.pi, 4001)
        k = int(np.argmin(np.hypot(a * np.cos(t) - p[0], b * np.sin(t) - p[1])))

        def dist(s, a=a, b=b, p=p):
            return math.hypot(a * math.cos(s) - p[0], b * math.sin(s) - p[1])

        best = minimize_scalar(dist, bounds=(t[k] - 2e-3, t[k] + 2e-3), method="bounded",
                               options={"xatol": 1e-14}).fun  # fmt: skip
        assert ellipse_distance(a, b, p[None])[0] == pytest.approx(best, abs=1e-12 * max(a, b))
