"""Shapes: exact mass properties against closed forms and two independent numerical oracles
(a fine polygon through the boundary, Monte Carlo with an analytic inside test), constructor
validation, arcs' spans and orientation conventions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from runtime.model import shapes
from runtime.model.shapes import Arc, Ellipse, Segment, Shape, shape_from_edges

pytestmark = pytest.mark.filterwarnings("error")


def boundary_polygon(shape: Shape, per_radian: int = 4000) -> np.ndarray:
    """Points along the boundary in traversal order (an independent discretisation)."""
    pts = []
    for e in shape.edges:
        if isinstance(e, Segment):
            pts.append(np.array([e.start]))
        elif isinstance(e, Arc):
            n = max(16, int(per_radian * e.span))
            a = np.linspace(e.start_angle, e.end_angle, n, endpoint=False)
            if e.radius < 0:  # traversed clockwise: from end_angle back to start_angle
                a = np.linspace(e.end_angle, e.start_angle, n, endpoint=False)
            r = abs(e.radius)
            pts.append(np.c_[e.centre[0] + r * np.cos(a), e.centre[1] + r * np.sin(a)])
        else:
            t = np.linspace(0, 2 * np.pi, 20000, endpoint=False)
            c, s = math.cos(e.angle), math.sin(e.angle)
            x, y = e.a * np.cos(t), e.b * np.sin(t)
            pts.append(np.c_[e.centre[0] + c * x - s * y, e.centre[1] + s * x + c * y])
    return np.vstack(pts)


def polygon_properties(p: np.ndarray) -> tuple[float, np.ndarray, float]:
    """Area, centroid and polar second moment about the centroid of a simple polygon."""
    x, y = p[:, 0], p[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    area = cross.sum() / 2
    cx = ((x + x1) * cross).sum() / (6 * area)
    cy = ((y + y1) * cross).sum() / (6 * area)
    j0 = ((x * x + x * x1 + x1 * x1 + y * y + y * y1 + y1 * y1) * cross).sum() / 12
    return area, np.array([cx, cy]), j0 - area * (cx * cx + cy * cy)


def assert_matches_fine_polygon(shape: Shape, rel: float = 1e-6) -> None:
    area, centroid, second = polygon_properties(boundary_polygon(shape))
    size = shape.bounding_radius
    assert shape.area == pytest.approx(area, rel=rel)
    np.testing.assert_allclose(shape.centroid, centroid, rtol=0, atol=rel * size)
    assert shape.second_moment == pytest.approx(second, rel=rel)


# -- closed forms ----------------------------------------------------------------------------


def test_disc_area_centroid_and_polar_moment():
    r = 1.7
    d = shapes.disc(r)
    assert d.area == pytest.approx(math.pi * r**2, rel=1e-14)
    assert d.second_moment == pytest.approx(math.pi * r**4 / 2, rel=1e-14)
    assert d.centroid == pytest.approx((0.0, 0.0), abs=1e-15)
    assert d.vertices == () and d.bounding_radius == r and len(d.edges) == 1
    assert d.edges[0].full and d.edges[0].convex


def test_rectangle_from_points_clockwise_or_not():
    w, h, x0, y0 = 3.0, 1.2, 2.0, -5.0
    ccw = [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]
    for pts in (ccw, ccw[::-1]):
        box = shapes.polygon(pts)
        assert box.area == pytest.approx(w * h, rel=1e-14)
        assert box.centroid == pytest.approx((x0 + w / 2, y0 + h / 2), rel=1e-14)
        assert box.second_moment == pytest.approx(w * h * (w * w + h * h) / 12, rel=1e-12)
        assert len(box.vertices) == 4
        for seg in box.edges:  # outward normals: the centroid is behind every edge
            n, (ex, ey) = seg.normal, seg.start
            assert n[0] * (box.centroid[0] - ex) + n[1] * (box.centroid[1] - ey) < 0


def test_half_disc_centroid_is_4r_over_3pi():
    r = 0.8
    hd = shapes.half_disc(r)
    assert hd.area == pytest.approx(math.pi * r**2 / 2, rel=1e-14)
    assert hd.centroid == pytest.approx((0.0, 4 * r / (3 * math.pi)), rel=1e-13, abs=1e-16)
    assert hd.second_moment == pytest.approx(
        math.pi * r**4 / 4 - 8 * r**4 / (9 * math.pi), rel=1e-13
    )
    assert sorted(hd.vertices) == [(-r, 0.0), (r, 0.0)]


def test_rounded_rect_area_and_no_vertices():
    w, h, c = 2.0, 1.0, 0.3
    rr = shapes.rounded_rect(w, h, c)
    assert rr.area == pytest.approx(w * h - (4 - math.pi) * c * c, rel=1e-14)
    assert rr.vertices == () and rr.centroid == pytest.approx((0, 0), abs=1e-15)
    assert len(rr.edges) == 8
    assert shapes.rounded_rect(w, h, 0.0).vertices  # plain rectangle
    stadium = shapes.rounded_rect(2.0, 1.0, 0.5)  # the short sides vanish
    assert len(stadium.edges) == 6
    assert stadium.area == pytest.approx(1.0 + math.pi * 0.25, rel=1e-14)


def test_d_shape_and_its_half_disc_limit():
    w, h = 2.0, 1.0
    d = shapes.d_shape(w, h)
    assert d.area == pytest.approx((w - h / 2) * h + math.pi * (h / 2) ** 2 / 2, rel=1e-14)
    assert sorted(d.vertices) == [(-(w - h / 2), -h / 2), (-(w - h / 2), h / 2)]
    limit = shapes.d_shape(0.5, 1.0)
    assert limit.area == pytest.approx(shapes.half_disc(0.5).area, rel=1e-14)
    assert len(limit.vertices) == 2


def test_ellipse_area_and_moment():
    a, b = 2.0, 0.5
    e = shapes.ellipse(a, b)
    assert e.area == pytest.approx(math.pi * a * b, rel=1e-14)
    assert e.second_moment == pytest.approx(math.pi * a * b * (a * a + b * b) / 4, rel=1e-14)
    assert e.bounding_radius == a and e.vertices == ()


def test_ellipse_osculating_circle_at_the_axes():
    e = Ellipse((0.0, 0.0), 2.0, 0.5)
    (cx, cy), rho = e.osculating(math.pi / 2)  # end of the minor axis: flattest point
    assert rho == pytest.approx(4.0 / 0.5) and (cx, cy) == pytest.approx((0.0, 0.5 - 8.0))
    (cx, cy), rho = e.osculating(0.0)  # end of the major axis: sharpest point
    assert rho == pytest.approx(0.25 / 2.0) and (cx, cy) == pytest.approx((2.0 - 0.125, 0.0))


# -- numerical oracles -----------------------------------------------------------------------


def bitten_square(side: float, bite: float) -> Shape:
    """Square [0, s]^2 whose top edge has a concave circular bite of radius ``bite`` centred
    at (s/2, s): an arc with negative radius inside a closed boundary."""
    s, r = side, bite
    return shape_from_edges(
        [
            Segment((0, 0), (s, 0)),
            Segment((s, 0), (s, s)),
            Segment((s, s), (s / 2 + r, s)),
            Arc((s / 2, s), -r, math.pi, 2 * math.pi),
            Segment((s / 2 - r, s), (0, s)),
            Segment((0, s), (0, 0)),
        ]
    )


def test_concave_bite_against_fine_polygon_and_monte_carlo():
    s, r = 2.0, 0.6
    shape = bitten_square(s, r)
    assert shape.area == pytest.approx(s * s - math.pi * r * r / 2, rel=1e-14)
    assert_matches_fine_polygon(shape)
    assert len(shape.vertices) == 6  # the square's corners and the bite's two sharp rims
    rng = np.random.default_rng(7)
    n = 400_000
    pts = rng.uniform(0, s, size=(n, 2))
    inside = np.hypot(pts[:, 0] - s / 2, pts[:, 1] - s) > r
    q = pts[inside]
    area = s * s * inside.mean()
    sigma = s * s * math.sqrt(inside.mean() * (1 - inside.mean()) / n)
    assert abs(shape.area - area) < 5 * sigma
    centroid = q.mean(axis=0)
    np.testing.assert_allclose(shape.centroid, centroid, atol=5 * s / math.sqrt(len(q)))
    second = area * np.mean(((q - shape.centroid) ** 2).sum(axis=1))
    assert shape.second_moment == pytest.approx(second, rel=0.01)


def convex_points(draw_angles: list[float], radii: list[float]) -> list[tuple[float, float]]:
    angles = np.sort(np.asarray(draw_angles))
    return [(r * math.cos(a), r * math.sin(a)) for a, r in zip(angles, radii, strict=False)]


@settings(derandomize=True, max_examples=40, deadline=None)
@given(
    kind=st.sampled_from(["rounded_rect", "d_shape", "half_disc", "polygon", "bite", "ellipse"]),
    p=st.lists(st.floats(0.1, 3.0), min_size=3, max_size=3),
    shift=st.tuples(st.floats(-5, 5), st.floats(-5, 5)),
)
def test_mass_properties_match_a_fine_polygon(kind, p, shift):
    a, b, c = p
    if kind == "rounded_rect":
        shape = shapes.rounded_rect(a, b, min(a, b) / 2 * c / 3)
    elif kind == "d_shape":
        shape = shapes.d_shape(max(a, b / 2), b)
    elif kind == "half_disc":
        shape = shapes.half_disc(a)
    elif kind == "polygon":  # a regular-ish pentagon scaled by a, b
        pts = [
            (a * math.cos(t), b * math.sin(t))
            for t in np.linspace(0, 2 * np.pi, 5, endpoint=False) + c
        ]
        shape = shapes.polygon(pts)
    elif kind == "ellipse":
        shape = shapes.ellipse(a, b)
    else:
        shape = bitten_square(a + 1.0, min(0.45 * (a + 1.0), b / 3))
    shape = shape.translated(*shift)
    assert_matches_fine_polygon(shape, rel=2e-6)


def test_centred_moves_the_centroid_to_the_origin():
    for shape in (shapes.half_disc(1.3), shapes.d_shape(2, 1), bitten_square(2, 0.5),
                  shapes.polygon([(1, 1), (4, 1), (2, 3)])):  # fmt: skip
        centred, offset = shape.centred()
        assert offset == pytest.approx(shape.centroid, abs=0)
        assert centred.centroid == pytest.approx((0, 0), abs=1e-14)
        assert centred.area == pytest.approx(shape.area, rel=1e-13)
        assert centred.second_moment == pytest.approx(shape.second_moment, rel=1e-12)
        assert len(centred.vertices) == len(shape.vertices)
    floor = shapes.wall((-1, 0), (1, 0))
    assert floor.centred() == (floor, (0.0, 0.0))


@pytest.mark.parametrize(
    "shape",
    [
        shapes.half_disc(1.0).translated(0.3, -0.2),
        shapes.d_shape(2, 1),
        shapes.rounded_rect(2, 1, 0.3),
        shapes.bowl(2.0, -2.5, -0.6),
        shapes.box_walls(3, 1),
        bitten_square(2, 0.5),
        shapes.ellipse(1.5, 0.5),
    ],  # fmt: skip
)
def test_bounding_radius_is_the_farthest_boundary_point(shape):
    far = np.hypot(*boundary_polygon(shape).T).max()
    if isinstance(shape.edges[0], Ellipse):
        assert shape.bounding_radius >= far - 1e-12
    else:
        assert shape.bounding_radius == pytest.approx(far, rel=1e-6)


# -- conventions: arcs, walls, bowls ---------------------------------------------------------


def test_arc_span_runs_counter_clockwise_for_both_signs():
    convex = Arc((0, 0), 1.0, 0.0, math.pi / 2)
    concave = Arc((0, 0), -1.0, 0.0, math.pi / 2)
    for arc in (convex, concave):
        assert arc.contains_angle(math.pi / 4) and arc.contains_angle(2 * math.pi + 0.1)
        assert not arc.contains_angle(-0.01) and not arc.contains_angle(math.pi / 2 + 0.01)
        assert arc.contains_angle(-0.01, slack=0.02)
        np.testing.assert_allclose(arc.end_points, [(1, 0), (0, 1)], atol=1e-16)
    assert convex.first == pytest.approx((1, 0)) and convex.last == pytest.approx((0, 1), abs=1e-16)
    assert concave.first == pytest.approx((0, 1), abs=1e-16) and concave.last == pytest.approx(
        (1, 0)
    )
    assert concave.normal_at(0.0) == (-1.0, -0.0)  # a bowl's normal points to its centre


def test_wall_bowl_and_box_orientation():
    floor = shapes.wall((-1, 0), (1, 0))  # material on the right: below
    assert floor.edges[0].normal == pytest.approx((0, 1)) and not floor.closed
    assert floor.area == 0 and floor.vertices == ()
    assert len(shapes.wall((-1, 0), (1, 0), end_vertices=True).vertices) == 2
    b = shapes.bowl(2.0, -2.5, -0.6)
    assert b.edges[0].radius == -2.0 and b.vertices == () and not b.closed
    assert len(shapes.bowl(2.0, -2.5, -0.6, end_vertices=True).vertices) == 2
    assert shapes.bowl(1.0, 0, 2 * math.pi).edges[0].full
    box = shapes.box_walls(4.0, 2.0)
    normals = sorted(tuple(np.round(e.normal, 12) + 0.0) for e in box.edges)
    assert normals == [(-1.0, 0.0), (0.0, 1.0), (1.0, 0.0)]  # right wall, floor, left wall
    assert box.vertices == ()
    v = shapes.segment_chain([(-1, 1), (0, 0), (1, 1)])  # a valley, material below
    h = 1 / 2**0.5
    np.testing.assert_allclose([e.normal for e in v.edges], [(-h, h), (h, h)], rtol=1e-15)


def test_shape_from_edges_checks_connection_and_orientation():
    with pytest.raises(ValueError, match="edge 0 ends"):
        shape_from_edges(
            [Segment((0, 0), (1, 0)), Segment((2, 0), (2, 1)), Segment((2, 1), (0, 0))]
        )
    with pytest.raises(ValueError, match="counter-clockwise"):
        shape_from_edges(
            [Segment((0, 0), (0, 1)), Segment((0, 1), (1, 0)), Segment((1, 0), (0, 0))]
        )
    with pytest.raises(ValueError, match="only edge"):
        shape_from_edges([Ellipse((0, 0), 1, 1), Segment((0, 0), (1, 0))])


# -- validation ------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: shapes.disc(-1.0), "radius"),
        (lambda: shapes.disc(float("nan")), "radius"),
        (lambda: shapes.disc("big"), "radius"),
        (lambda: shapes.rounded_rect(1, 1, 0.6), "corner_radius"),
        (lambda: shapes.rounded_rect(0, 1, 0.1), "width"),
        (lambda: shapes.rounded_rect(1, float("inf"), 0.1), "height"),
        (lambda: shapes.half_disc(0), "radius"),
        (lambda: shapes.d_shape(0.2, 1.0), "width"),
        (lambda: shapes.ellipse(1, -2), "b"),
        (lambda: shapes.ellipse(1.0, 1e-16), "a"),  # a needle: a / b beyond MAX_AXIS_RATIO
        (lambda: shapes.ellipse(1e-7, 1.0), "b"),
        (lambda: shapes.wall((0, 0), (0, 0)), "start"),
        (lambda: shapes.wall((0, 0), (1, float("nan"))), "end"),
        (lambda: shapes.bowl(1.0, 0.0, -1.0), "end_angle"),
        (lambda: shapes.bowl(-1.0, 0.0, 1.0), "radius"),
        (lambda: shapes.box_walls(1.0, 0.0), "height"),
        (lambda: shapes.polygon([(0, 0), (1, 0)]), "points"),
        (lambda: shapes.polygon([(0, 0), (1, 0), "x"]), "points"),
        (lambda: shapes.polygon(5), "points"),
    ],
)
def test_constructors_raise_value_error_naming_the_parameter(call, name):
    with pytest.raises(ValueError, match=rf"\b{name}\b"):
        call()


@pytest.mark.parametrize(
    ("points", "words"),
    [
        ([(0, 0), (1, 0), (0.2, 0.2), (0, 1)], ["convex", "vertex 2"]),
        ([(0, 0), (1, 1), (1, 0), (0, 1)], ["points", "vertex"]),  # bow tie
        ([(0, 0), (1, 0), (2, 0), (1, 1)], ["collinear", "vertex 1"]),
        ([(0, 0), (1, 0), (1, 0), (0, 1)], ["repeat", "vertex"]),
        (
            [(math.cos(a), math.sin(a)) for a in np.arange(5) * 4 * math.pi / 5],
            ["self-intersecting", "vertex"],
        ),
    ],
)
def test_polygon_rejects_bad_outlines_naming_the_vertex(points, words):
    with pytest.raises(ValueError) as err:
        shapes.polygon(points)
    for word in words:
        assert word in str(err.value)


@pytest.mark.parametrize("offset", [1e9, 1e11, 1e12, 1e13, 1e14])
def test_far_away_unit_square_is_convex_in_both_orientations(offset):
    """Issue #13: a unit square written at 1e9..1e14 m used to be refused as non-convex in a
    quarter of the trials (its orientation came from products of coordinates near offset^2).
    Reference: its area is 1 up to the rounding of its corners (half a spacing of doubles at
    ``offset`` each, so at most 4 x 2 x that spacing over the perimeter)."""
    rng = np.random.default_rng(13)
    bound = 8 * np.spacing(offset)
    for _ in range(50):
        x0, y0 = rng.uniform(-1, 1, 2) * offset
        th = rng.uniform(0, 2 * math.pi)
        c, s = math.cos(th), math.sin(th)
        corners = [(x0 + c * u - s * v, y0 + s * u + c * v) for u, v in
                   ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))]  # fmt: skip
        for pts in (corners, corners[::-1]):
            square = shapes.polygon(pts)
            assert square.area == pytest.approx(1.0, abs=bound)
            assert len(square.vertices) == 4
    dart = [(offset + x, offset + y) for x, y in ((0, 0), (1, 0), (0.25, 0.25), (0, 1))]
    with pytest.raises(ValueError, match="vertex 2 .* is reflex"):
        shapes.polygon(dart)


def test_needle_ellipse_limit_is_the_axis_ratio():
    """Issue #13: a needle (a / b = 1e16) passed every size check. The limit is the ratio, at
    1e6 (runtime/settings.py): the message gives the curvature radius b^2 / a at the tip."""
    with pytest.raises(ValueError) as err:
        shapes.ellipse(1.0, 1e-16)
    assert str(err.value) == (
        "ellipse: a / b must be at most 1e+06, got 1e+16: the radius of curvature at the ends, "
        "b^2/a = 1e-32 m, would be lost in the rounding of positions there (~2.2e-16 m)"
    )
    assert shapes.ellipse(1.0, 1e-6).area == pytest.approx(math.pi * 1e-6, rel=1e-15)
    assert shapes.ellipse(1e-6, 1.0).area == pytest.approx(math.pi * 1e-6, rel=1e-15)
