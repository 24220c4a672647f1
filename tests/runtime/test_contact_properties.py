"""Contact finding over random shapes from every constructor of runtime.model.shapes and random
poses (hypothesis): the contract of every contact set (tests/contact_reference.py), the
generated NumPy kernels' gap, which body is body 2, valid feature indices, per-pair tolerances
with margins, and the smallest gap against brute-force distances by dense boundary sampling."""

from __future__ import annotations

import importlib
import math

import numpy as np
import pytest
from contact_reference import (
    check_contacts,
    distance_to_edges,
    rot,
    rows,
    sample_boundary,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

from runtime.collide.finder import ContactFinder
from runtime.model import shapes
from runtime.model.shapes import Arc, Ellipse, Segment

pytestmark = pytest.mark.filterwarnings("error")
SETTINGS = settings(derandomize=True, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@st.composite
def moving_shapes(draw):
    """A closed shape from one of the constructors, centred, of size ~0.2-0.6."""
    kind = draw(st.sampled_from(["polygon", "disc", "rounded_rect", "half_disc", "d_shape",
                                 "ellipse"]))  # fmt: skip
    size = draw(st.floats(0.2, 0.6))
    if kind == "polygon":
        m = draw(st.integers(3, 8))
        gaps = draw(st.lists(st.floats(0.3, 1.0), min_size=m, max_size=m))
        angles = np.cumsum(gaps) / sum(gaps) * 2 * math.pi
        return shapes.polygon([(size * math.cos(a), size * math.sin(a)) for a in angles]).centred()[
            0
        ]
    if kind == "disc":
        return shapes.disc(size)
    if kind == "rounded_rect":
        h = size * draw(st.floats(0.3, 1.0))
        return shapes.rounded_rect(2 * size, h, draw(st.sampled_from([0.0, 0.25, 0.5])) * h)
    if kind == "half_disc":
        return shapes.half_disc(size).centred()[0]
    if kind == "d_shape":
        h = size * draw(st.floats(0.4, 1.0))
        return shapes.d_shape(h / 2 + size * draw(st.floats(0.0, 1.0)), h).centred()[0]
    return shapes.ellipse(size, size * draw(st.floats(0.3, 1.0)))


@st.composite
def environments(draw):
    """A fixed shape from the constructors of walls and containers, around the origin."""
    kind = draw(st.sampled_from(["wall", "bowl", "full bowl", "box_walls", "segment_chain"]))
    ends = draw(st.booleans())
    if kind == "wall":
        return shapes.wall((-3.0, -1.0), (3.0, -1.2), end_vertices=ends)
    if kind == "bowl":
        return shapes.bowl(1.5, -2.8, -0.3, end_vertices=ends)
    if kind == "full bowl":
        return shapes.bowl(1.6, 0.0, 2 * math.pi)
    if kind == "box_walls":
        return shapes.box_walls(2.5, 1.5, end_vertices=ends).translated(0.0, -1.2)
    return shapes.segment_chain([(-2.0, 0.8), (-0.5, -1.2), (0.4, -0.9), (2.0, 0.9)],
                                end_vertices=ends)  # fmt: skip


@st.composite
def scenes(draw):
    """An environment and 2-4 moving bodies (one of them fixed at times) close together."""
    bodies = [draw(environments())] + draw(st.lists(moving_shapes(), min_size=2, max_size=4))
    n = len(bodies)
    fixed = [True] + [False] * (n - 1)
    if draw(st.booleans()):
        fixed[draw(st.integers(1, n - 1))] = True
    xy = draw(st.lists(st.tuples(st.floats(-1.0, 1.0), st.floats(-1.2, 0.6)),
                       min_size=n - 1, max_size=n - 1))  # fmt: skip
    th = draw(st.lists(st.floats(-math.pi, math.pi), min_size=n - 1, max_size=n - 1))
    poses = np.zeros((n, 3))
    poses[1:, :2], poses[1:, 2] = xy, th
    shift = draw(st.sampled_from([(0.0, 0.0), (1e3, -2e3)]))  # precision far from the origin
    poses[:, :2] += shift
    tolerance = draw(st.sampled_from([0.0, 1e-3, 0.05, 0.2]))
    return bodies, poses, fixed, tolerance


def arc_radius(shape, kind: str, index: int) -> float:
    edge = shape.edges[index] if kind == "edge" else None
    return edge.radius if isinstance(edge, Arc) else math.nan


@SETTINGS
@given(scenes())
def test_every_contact_meets_the_contract_and_the_numpy_kernels(scene):
    bodies, poses, fixed, tolerance = scene
    found = ContactFinder(bodies, fixed).find(poses, tolerance)
    check_contacts(found, poses)
    assert np.all(found.gap <= tolerance)
    for c in rows(found):
        kernel = importlib.import_module(f"generated.{c.case}")
        x1, y1, th1 = poses[c.body1]
        x2, y2, th2 = poses[c.body2]
        d = kernel.gap(x1=x1, y1=y1, th1=th1, x2=x2, y2=y2, th2=th2, **c.geometry)
        assert c.gap == pytest.approx(float(d), rel=1e-12, abs=1e-13 * 2e3)
        one, two = bodies[c.body1], bodies[c.body2]
        (kind1, index1), (kind2, index2) = c.feature
        # the features exist and carry the geometry reported
        if kind1 == "vertex":
            assert (c.geometry["px1"], c.geometry["py1"]) == one.vertices[index1]
            np.testing.assert_allclose(c.point, poses[c.body1, :2] + rot(th1, one.vertices[index1]),
                                       atol=1e-9)  # fmt: skip
        elif kind1 == "end":  # a convex arc running smoothly into a straight side
            joined = one.edges[index1], one.edges[(index1 + 1) % len(one.edges)]
            assert {type(e) for e in joined} == {Arc, Segment}
            assert (c.geometry["px1"], c.geometry["py1"]) == pytest.approx(joined[1].first)
        else:
            edge = one.edges[index1]
            assert isinstance(edge, Arc | Ellipse) and c.geometry["r1"] > 0
            if isinstance(edge, Arc):
                assert (c.geometry["cx1"], c.geometry["cy1"], c.geometry["r1"]) == (
                    *edge.centre,
                    edge.radius,
                )
        if kind2 == "vertex":
            assert (
                c.case == "vertex_circle"
                and (c.geometry["cx2"], c.geometry["cy2"]) == two.vertices[index2]
            )
        else:
            edge = two.edges[index2]
            if isinstance(edge, Segment):
                assert c.case.endswith("edge")
                assert (c.geometry["ex2"], c.geometry["ey2"]) == edge.start
                assert (c.geometry["nx2"], c.geometry["ny2"]) == pytest.approx(
                    edge.normal, abs=1e-15
                )
            elif isinstance(edge, Arc):
                assert (c.geometry["cx2"], c.geometry["cy2"], c.geometry["r2"]) == (
                    *edge.centre,
                    edge.radius,
                )
            else:
                assert c.geometry["r2"] > 0
        # which body is body 2: a vertex is body 1, a concave arc body 2; between two convex
        # features (or two corners) a fixed body is body 2, otherwise the lower index
        assert arc_radius(one, kind1, index1) > 0 or math.isnan(arc_radius(one, kind1, index1))
        symmetric = c.case == "circle_circle" and c.geometry["r2"] > 0 or kind2 == "vertex"
        if symmetric:
            if fixed[c.body1] != fixed[c.body2]:
                assert fixed[c.body2]
            else:
                assert c.body1 < c.body2


@SETTINGS
@given(scenes(), st.lists(st.floats(0.0, 0.3), min_size=5, max_size=5))
def test_margins_widen_each_pair_by_its_two_bodies(scene, widths):
    """With per-body margins, the contacts of a pair are those found with the pair's own
    tolerance, base + margin_i + margin_j."""
    bodies, poses, fixed, tolerance = scene
    margins = np.array(widths[: len(bodies)])
    finder = ContactFinder(bodies, fixed)
    found = rows(finder.find(poses, tolerance, margins))
    pairs = {(min(c.body1, c.body2), max(c.body1, c.body2)) for c in found}
    for i in range(len(bodies)):
        for j in range(i + 1, len(bodies)):
            alone = rows(finder.find(poses, tolerance + margins[i] + margins[j]))
            mine = [c for c in alone if {c.body1, c.body2} == {i, j}]
            assert [c for c in found if {c.body1, c.body2} == {i, j}] == mine
            assert bool(mine) == ((i, j) in pairs)


@SETTINGS
@given(moving_shapes(), moving_shapes(), st.floats(0, 2 * math.pi), st.floats(-math.pi, math.pi),
       st.floats(-math.pi, math.pi), st.floats(0.005, 0.2))  # fmt: skip
def test_separated_closed_pairs_min_gap_is_the_sampled_distance(
    a, b, direction, th1, th2, clearance
):
    u = np.array([math.cos(direction), math.sin(direction)])
    tree = cKDTree(sample_boundary(a, (0, 0, th1), 600))
    hi = a.bounding_radius + b.bounding_radius + 0.5  # apart; move b in along -u until it
    while (d := tree.query(sample_boundary(b, (*(hi * u), th2), 600))[0].min()) > 0.01:
        hi -= 0.9 * d  # no point moves farther than the distance: never jumps through
    poses = np.array([[0, 0, th1], [*((hi + clearance) * u), th2]])
    found = ContactFinder([a, b], [False, False]).find(poses, 1.0)
    check_contacts(found, poses)
    sampled = cKDTree(sample_boundary(a, poses[0])).query(sample_boundary(b, poses[1]))[0].min()
    assert found.gap.min() == pytest.approx(sampled, abs=1e-3)


def lowered(environment, body, th: float, clearance: float) -> np.ndarray:
    """A pose of ``body`` at angle th lowered from a free start above the bottom of
    ``environment`` until its sampled boundary is ``clearance`` from the exact edges (each move
    no longer than the distance left: it never jumps through an edge)."""
    x, y = 0.1, (0.8 if environment.edges[0].__class__ is Segment else 0.0)

    def distance(y: float) -> float:
        pts = sample_boundary(body, (x, y, th), 400)
        return float(distance_to_edges(pts, environment, (0, 0, 0)).min())

    while (d := distance(y)) - clearance > 1e-9:
        y -= d - clearance
    return np.array([x, y, th])


@SETTINGS
@given(environments(), moving_shapes(), st.floats(-math.pi, math.pi), st.floats(0.002, 0.1))
def test_body_above_an_environment_min_gap_is_the_exact_edge_distance(env, body, th, clearance):
    """A body lowered onto a wall, bowl, box or chain from above: its smallest gap is the
    distance of its (densely sampled) boundary from the exact edges of the environment."""
    pose = lowered(env, body, th, clearance)
    poses = np.array([[0, 0, 0], pose])
    found = ContactFinder([env, body], [True, False]).find(poses, 0.2)
    check_contacts(found, poses)
    exact = distance_to_edges(sample_boundary(body, pose, 20000), env, (0, 0, 0)).min()
    assert found.gap.min() == pytest.approx(exact, abs=1e-6)
