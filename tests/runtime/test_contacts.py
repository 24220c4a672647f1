"""Contacts: hand-computed configurations, the kernels' gap formulas (an independent
re-implementation of docs/conventions.md, tests/contact_reference.py, and the generated NumPy
kernels), brute-force distances by dense boundary sampling, invariance under rigid motions of
the whole scene, the broad phase against all pairs, possible_cases, argument checks."""

from __future__ import annotations

import dataclasses
import importlib
import math
import re

import numpy as np
import pytest
from contact_reference import (
    Row,
    check_contacts,
    rot,
    rows,
    same,
    sample_boundary,
    signed_distance_to_convex_polygon,
)
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.spatial import cKDTree

from runtime.collide import contacts
from runtime.collide.broadphase import sweep
from runtime.collide.candidates import BODY1, BODY2
from runtime.collide.contacts import candidate_pairs, find_contacts, possible_cases
from runtime.collide.finder import ContactFinder
from runtime.collide.narrowphase import find_candidates
from runtime.model import shapes

pytestmark = pytest.mark.filterwarnings("error")
FLOOR = shapes.wall((-5.0, 0.0), (5.0, 0.0))
SQUARE = shapes.polygon([(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])
PENTAGON = shapes.polygon(
    [(math.cos(a), 0.7 * math.sin(a)) for a in np.arange(5) * 2 * math.pi / 5 + 0.3]
).centred()[0]


def find(shapes_, poses, fixed, tol=1e-6) -> list[Row]:
    poses = np.asarray(poses, dtype=float)
    found = find_contacts(shapes_, poses, fixed, tol)
    check_contacts(found, poses)
    return rows(found)


# -- hand-computed configurations -------------------------------------------------------------


def test_unit_square_resting_on_a_wall_has_two_vertex_contacts():
    found = find([FLOOR, SQUARE], [[0, 0, 0], [0.2, 0.5, 0]], [True, False])
    assert len(found) == 2
    assert {c.case for c in found} == {"vertex_edge"}
    assert all(
        c.body1 == 1 and c.body2 == 0 and c.gap == pytest.approx(0, abs=1e-15) for c in found
    )
    same(sorted(c.point for c in found), [(-0.3, 0.0), (0.7, 0.0)])
    assert all(c.normal == pytest.approx((0, 1)) for c in found)
    assert {(c.geometry["px1"], c.geometry["py1"]) for c in found} == {(-0.5, -0.5), (0.5, -0.5)}


def test_disc_on_a_wall_at_gap_0_01():
    disc = shapes.disc(0.5)
    (c,) = find([FLOOR, disc], [[0, 0, 0], [1.0, 0.51, 2.0]], [True, False], tol=0.02)
    assert c.case == "circle_edge" and (c.body1, c.body2) == (1, 0)
    assert c.gap == pytest.approx(0.01, rel=1e-12)
    assert c.point == pytest.approx((1.0, 0.01)) and c.normal == pytest.approx((0, 1))
    assert find([FLOOR, disc], [[0, 0, 0], [1.0, 0.51, 2.0]], [True, False], tol=0.005) == []


def test_disc_resting_in_a_bowl_0_3_rad_off_the_bottom():
    bowl = shapes.bowl(1.0, -2.5, -0.6)
    r, a = 0.1, -math.pi / 2 + 0.3
    pos = [(1.0 - r) * math.cos(a), (1.0 - r) * math.sin(a), 0.7]
    (c,) = find([bowl, shapes.disc(r)], [[0, 0, 0], pos], [True, False])
    assert c.case == "circle_circle" and (c.body1, c.body2) == (1, 0)
    assert c.geometry["r2"] == -1.0 and c.geometry["r1"] == r
    assert c.gap == pytest.approx(0.0, abs=1e-15)
    assert c.normal == pytest.approx((-math.cos(a), -math.sin(a)))  # toward the bowl's centre
    assert c.point == pytest.approx((math.cos(a), math.sin(a)))


def test_vertex_against_an_arc_just_inside_and_just_outside_its_span():
    hd = shapes.half_disc(1.0)  # arc over [0, pi], corners at (+-1, 0)
    tip = SQUARE.translated(0.5, 0.5)  # vertex 0 at its origin; its edges leave along +x, +y
    d = 0.01
    for angle, inside in ((0.02, True), (-0.02, False)):
        p = (1 + d) * np.array([math.cos(angle), math.sin(angle)])
        pose = [p[0], p[1], angle - math.pi / 4]  # the corner points at the arc's centre
        found = find([hd, tip], [[0, 0, 0], pose], [True, False], tol=0.05)
        arc = [c for c in found if c.case == "vertex_circle"]
        if inside:
            (c,) = found
            assert arc == [c] and c.feature == (("vertex", 0), ("edge", 1))
            assert c.gap == pytest.approx(d, rel=1e-12) and c.body1 == 1
        else:  # beyond the arc's end the half disc's corner (1, 0) touches the square's edge
            assert arc == [] and found
            for c in found:
                assert c.case == "vertex_edge" and c.body1 == 0
                assert (c.geometry["px1"], c.geometry["py1"]) == (1.0, 0.0)


def test_vertex_beyond_a_bowl_rim_is_not_an_arc_contact():
    bowl = shapes.bowl(2.0, -2.5, -0.6)
    tip = shapes.polygon([(0, 0), (0.3, 0.1), (0.3, -0.1)])  # vertex 0 points along -x
    for angle, n in ((-0.62, 1), (-0.58, 0)):
        u = np.array([math.cos(angle), math.sin(angle)])
        p = 1.99 * u  # the tip points outward at the bowl's wall, 0.01 short of it
        pose = [p[0], p[1], angle + math.pi]
        found = find([bowl, tip], [[0, 0, 0], pose], [True, False], tol=0.05)
        assert len(found) == n
        if n:
            assert found[0].case == "vertex_circle" and found[0].gap == pytest.approx(0.01)
            assert found[0].normal == pytest.approx(-u)


def test_box_flat_on_a_floor_and_on_a_box_gives_two_contacts_each():
    found = find(
        [FLOOR, SQUARE, SQUARE], [[0, 0, 0], [0, 0.5, 0], [0, 1.5, 0]], [True, False, False]
    )
    pairs = [(min(c.body1, c.body2), max(c.body1, c.body2)) for c in found]
    assert pairs == [(0, 1), (0, 1), (1, 2), (1, 2)]
    top = [c for c in found if {c.body1, c.body2} == {1, 2}]
    same(sorted(c.point for c in top), [(-0.5, 1.0), (0.5, 1.0)])
    shifted = find([SQUARE, SQUARE], [[0, 0, 0], [0.3, 1.0, 0]], [False, False])
    same(sorted(c.point for c in shifted), [(-0.2, 0.5), (0.5, 0.5)])


def test_rounded_box_flat_and_tilted_on_a_floor_and_stacked():
    box = shapes.rounded_rect(2.0, 1.0, 0.2)
    flat = find([FLOOR, box], [[0, 0, 0], [0, 0.5, 0]], [True, False], tol=0.01)
    assert [c.case for c in flat] == ["circle_edge", "circle_edge"]
    same(sorted(c.point for c in flat), [(-0.8, 0), (0.8, 0)])
    th = 0.001  # tilted: the low end is an arc contact, the lifted end the arc's end point
    y = 0.3 * math.cos(th) + 0.8 * math.sin(th) + 0.2  # the left arc just touches
    tilted = find([FLOOR, box], [[0, 0, 0], [0, y, th]], [True, False], tol=0.01)
    cases = sorted(c.case for c in tilted)
    assert cases == ["circle_edge", "vertex_edge"]
    lifted = next(c for c in tilted if c.case == "vertex_edge")
    assert lifted.feature[0][0] == "end" and lifted.gap == pytest.approx(
        1.6 * math.sin(th), rel=1e-3
    )
    stack = find([box, box], [[0, 0, 0], [0.0, 1.0, 0]], [False, False])
    assert len(stack) == 2 and all(c.gap == pytest.approx(0, abs=1e-15) for c in stack)


def test_sunk_smooth_end_is_a_contact_only_within_cone_slack_beyond_its_arc():
    """A rounded box tilted right side down and sunk into a floor: the left end of its flat
    bottom (where it runs into the arc) penetrates too; it is a contact while the floor's
    normal lies at most CONE_SLACK (0.1 rad) beyond its arc, not at 0.15 rad."""
    box = shapes.rounded_rect(2.0, 1.0, 0.2)
    for th, sink, end in ((-0.05, 0.1, True), (-0.15, 0.3, False)):
        lowest = math.sin(th) * 0.8 - math.cos(th) * 0.3 - 0.2  # the right arc's, body at 0
        found = find([FLOOR, box], [[0, 0, 0], [0, -lowest - sink, th]], [True, False], tol=0.0)
        ends = [c for c in found if c.feature[0][0] == "end"]
        corner = np.array([0, -lowest - sink]) + rot(th, (-0.8, -0.5))
        assert [c.gap for c in ends] == ([pytest.approx(corner[1], abs=1e-12)] if end else [])
        assert corner[1] < -0.01  # it does penetrate in both
        (arc,) = [c for c in found if c.case == "circle_edge"]
        assert arc.gap == pytest.approx(-sink, abs=1e-12)


def test_disc_wedged_in_a_v_touches_both_sides():
    v = shapes.segment_chain([(-1, 1), (0, 0), (1, 1)])
    r = 0.3
    found = find([v, shapes.disc(r)], [[0, 0, 0], [0, r * math.sqrt(2), 0]], [True, False])
    assert len(found) == 2 and {c.case for c in found} == {"circle_edge"}
    h = 1 / math.sqrt(2)
    same(sorted(c.normal for c in found), [(-h, h), (h, h)])
    assert all(c.gap == pytest.approx(0, abs=1e-15) for c in found)


def test_corner_facing_a_corner_is_a_vertex_circle_of_radius_zero():
    # two half discs whose nearest points are two corners (each beyond the other's edges)
    hd = shapes.half_disc(0.5).centred()[0]
    poses = [[0.0, 0.0, 2.0], [1.35, 0.0, 0.0]]
    (c,) = find([hd, hd], poses, [False, False], tol=1.0)
    assert c.case == "vertex_circle" and c.geometry["r2"] == 0.0
    assert c.feature[0][0] == c.feature[1][0] == "vertex"
    p = [np.array(poses[k][:2]) + rot(poses[k][2], hd.vertices[c.feature[k][1]]) for k in (0, 1)]
    assert c.gap == pytest.approx(np.hypot(*(p[0] - p[1])), rel=1e-12)
    # corners meeting along an edge are edge contacts, not corner-corner
    assert all(
        c.feature[1][0] == "edge"
        for c in find([SQUARE, SQUARE], [[0, 0, 0], [1.0, 0.5, 0]], [False, False])
    )


def test_convex_circles_fixed_body_is_body_two_else_lower_index_first():
    a, b = shapes.disc(1.0), shapes.disc(0.5)
    (c,) = find([a, b], [[0, 0, 0], [1.5, 0, 0]], [True, False])
    assert (c.body1, c.body2) == (1, 0)
    (c,) = find([a, b], [[0, 0, 0], [1.5, 0, 0]], [False, False])
    assert (c.body1, c.body2) == (0, 1)
    (c,) = find([a, b], [[0, 0, 0], [1.5, 0, 0]], [False, True])
    assert (c.body1, c.body2) == (0, 1)
    assert find([a, b], [[0, 0, 0], [1.5, 0, 0]], [True, True]) == []


def test_ellipse_resting_on_a_floor_uses_its_osculating_circle():
    a, b = 1.0, 0.4
    (c,) = find([FLOOR, shapes.ellipse(a, b)], [[0, 0, 0], [0.3, b, 0]], [True, False])
    assert c.case == "circle_edge" and c.gap == pytest.approx(0, abs=1e-15)
    assert c.geometry["r1"] == pytest.approx(a * a / b)
    assert (c.geometry["cx1"], c.geometry["cy1"]) == pytest.approx((0.0, a * a / b - b), abs=1e-12)
    (c,) = find(
        [FLOOR, shapes.ellipse(a, b)],
        [[0, 0, 0], [0.3, a + 0.01, math.pi / 2]],
        [True, False],
        tol=0.1,
    )
    assert c.gap == pytest.approx(0.01) and c.geometry["r1"] == pytest.approx(b * b / a)


def test_ellipse_in_a_bowl_corner_on_an_ellipse_and_two_ellipses():
    e = shapes.ellipse(0.3, 0.15)
    bowl = shapes.bowl(1.0, -2.8, -0.3)
    (c,) = find([bowl, e], [[0, 0, 0], [0, -0.85 + 0.001, 0]], [True, False], tol=0.01)
    assert c.case == "circle_circle" and c.gap == pytest.approx(0.001, rel=1e-9)
    assert c.geometry["r2"] == -1.0
    (c,) = find(
        [e, SQUARE],
        [[0, 0, 0], [0, 0.15 + 0.02 + 0.5 * math.sqrt(2), math.pi / 4]],
        [False, False],
        tol=0.05,
    )
    assert c.case == "vertex_circle" and c.gap == pytest.approx(0.02, rel=1e-9)
    (c,) = find([e, e], [[0, 0, 0], [0.62, 0, 0]], [False, False], tol=0.05)
    assert c.case == "circle_circle" and c.gap == pytest.approx(0.02, rel=1e-9)


def test_penetration_keeps_only_plausible_contacts():
    sunk = find([FLOOR, SQUARE], [[0, 0, 0], [0, 0.49, 0]], [True, False])
    assert len(sunk) == 2 and all(c.gap == pytest.approx(-0.01) for c in sunk)
    # a corner poking 0.01 into the top of a box near its right side, 0.03 from that side
    poke = find(
        [SQUARE, SQUARE],
        [[0, 0, 0], [0.47, 0.49 + 0.5 * math.sqrt(2), math.pi / 4]],
        [False, False],
    )
    assert (
        len(poke) == 1
        and poke[0].gap == pytest.approx(-0.01)
        and poke[0].normal == pytest.approx((0, 1))
    )
    # two half discs overlapping by about 0.05 on their arcs; a corner of one lies 0.2 behind
    # the other's flat side but much nearer its arc: that is no contact
    hd = shapes.half_disc(0.6).centred()[0]
    poses = [
        [0, 0, 1.0466657252596683],
        [0.7712241681210872, 0.8934486617963334, -1.9316406270348754],
    ]
    (c,) = find([hd, hd], poses, [False, False], tol=0.0)
    assert c.case == "circle_circle" and c.gap == pytest.approx(-0.046079, abs=1e-6)
    # stacked boxes sunk 1e-4 into each other and 1e-7 out of line: still both ends
    ends = find([SQUARE, SQUARE], [[0, 0, 0], [1e-7, 1 - 1e-4, 0]], [False, False])
    assert len(ends) == 2 and all(c.gap == pytest.approx(-1e-4) for c in ends)
    same(sorted(c.normal[1] * (1 if c.body2 == 0 else -1) for c in ends), [1, 1])
    deep = find([FLOOR, shapes.disc(0.1)], [[0, 0, 0], [0, 0.05, 0]], [True, False])
    assert [c.gap for c in deep] == pytest.approx([-0.05])  # reported for the overlap check
    assert find([FLOOR, shapes.disc(0.1)], [[0, 0, 0], [0, -0.05, 0]], [True, False]) == []


def test_penetrating_corner_keeps_only_its_shallowest_way_out_of_a_closed_body():
    """A wide tip poking into a box's corner, 0.01 below its top and 0.02 inside its side: both
    edges are in the tip's normal cone and both depths plausible, but one corner in a closed
    body is one constraint, the shallowest: the top edge."""
    tip = shapes.polygon([(0, 0), (1.0, 0.3), (0.3, 1.0)])  # vertex 0 points down-left
    (c,) = find([SQUARE, tip], [[0, 0, 0], [0.48, 0.49, 0]], [False, False], tol=0.0)
    assert c.feature == (("vertex", 0), ("edge", 2)) and c.gap == pytest.approx(-0.01)
    (c,) = find([SQUARE, tip], [[0, 0, 0], [0.49, 0.48, 0]], [False, False], tol=0.0)
    assert c.feature == (("vertex", 0), ("edge", 1)) and c.gap == pytest.approx(-0.01)


def test_corner_on_a_box_side_is_not_deep_under_its_top():
    """A half disc's corner on a box's side, 0.01 below its top: 1e-13 outside, no contact at
    tolerance 0 (it was one 0.01 deep against the top, which locked the bodies together in a
    pile); 1e-13 inside, the side's contact at -1e-13. At either angle of the pair."""
    box = shapes.polygon([(-0.05, -0.04), (0.05, -0.04), (0.05, 0.04), (-0.05, 0.04)])
    hd = shapes.half_disc(0.06).centred()[0]
    corner = np.asarray(hd.edges[0].start)  # the flat side's left end
    for th in (0.0, -0.5233):
        for out, expected in ((1e-13, []), (-1e-13, [(("vertex", 0), ("edge", 1), -1e-13)])):
            centre = rot(th, np.array([0.05 + out, 0.03]) - corner)
            found = find([box, hd], [[0, 0, th], [*centre, th]], [False, False], tol=0.0)
            assert [(*c.feature, c.gap) for c in found] == [
                (a, b, pytest.approx(g, abs=1e-16)) for a, b, g in expected
            ]


# -- kernels ---------------------------------------------------------------------------------


def mixed_scene(seed: int):
    rng = np.random.default_rng(seed)
    bodies = [
        shapes.box_walls(6.0, 3.0),
        shapes.bowl(1.2, -2.8, -0.3),
        shapes.disc(0.3),
        SQUARE,
        shapes.rounded_rect(0.8, 0.4, 0.1),
        shapes.half_disc(0.4).centred()[0],
        shapes.d_shape(0.8, 0.5).centred()[0],
        shapes.ellipse(0.4, 0.2),
        PENTAGON,
    ]
    fixed = [True, True] + [False] * (len(bodies) - 2)
    poses = np.zeros((len(bodies), 3))
    poses[2:, 0] = rng.uniform(-1.0, 1.0, len(bodies) - 2)
    poses[2:, 1] = rng.uniform(-1.2, 1.0, len(bodies) - 2)
    poses[2:, 2] = rng.uniform(-3, 3, len(bodies) - 2)
    return bodies, poses, fixed


def test_every_case_occurs_and_matches_the_generated_kernels():
    seen = {}
    for seed in range(60):
        bodies, poses, fixed = mixed_scene(seed)
        for c in find(bodies, poses, fixed, tol=0.3):
            seen.setdefault(c.case, []).append((c, poses))
    assert set(seen) == set(contacts.CASES)
    for case, items in seen.items():  # the generated NumPy kernels (the public API)
        kernel = importlib.import_module(f"generated.{case}")
        for c, poses in items:
            x1, y1, th1 = poses[c.body1]
            x2, y2, th2 = poses[c.body2]
            d = kernel.gap(x1=x1, y1=y1, th1=th1, x2=x2, y2=y2, th2=th2, **c.geometry)
            assert c.gap == pytest.approx(float(d), rel=1e-12, abs=1e-14), (case, c)


# -- brute force and invariance --------------------------------------------------------------


@settings(derandomize=True, max_examples=60, deadline=None)
@given(
    st.floats(-2.0, 2.0),
    st.floats(-2.0, 2.0),
    st.floats(-math.pi, math.pi),
    st.floats(0.1, 0.6),
    st.floats(-4, 4),
)
def test_disc_and_polygon_min_gap_is_the_brute_force_distance(x, y, th, r, th_disc):
    poses = np.array([[0.2, -0.1, th], [x, y, th_disc]])
    corners = np.array([np.array(poses[0, :2]) + rot(th, v) for v in PENTAGON.vertices])
    exact = signed_distance_to_convex_polygon(np.array([x, y]), corners) - r
    assume(exact > -0.5 * r)  # deeper than half the disc is not a plausible contact
    found = find([PENTAGON, shapes.disc(r)], poses, [False, False], tol=10.0)
    assert min(c.gap for c in found) == pytest.approx(exact, abs=1e-12)
    if exact > 0:
        sampled = cKDTree(sample_boundary(PENTAGON, poses[0])).query(
            sample_boundary(shapes.disc(r), poses[1])
        )[0]
        assert min(c.gap for c in found) == pytest.approx(sampled.min(), abs=2e-3)


OTHERS = [shapes.rounded_rect(1.0, 0.5, 0.15), shapes.half_disc(0.5).centred()[0], shapes.d_shape(1.0, 0.6).centred()[0],
          shapes.ellipse(0.6, 0.3), SQUARE, shapes.disc(0.35)]  # fmt: skip


@settings(derandomize=True, max_examples=40, deadline=None)
@given(st.integers(0, len(OTHERS) - 1), st.integers(0, len(OTHERS) - 1), st.floats(0, 2 * math.pi),
       st.floats(-math.pi, math.pi), st.floats(-math.pi, math.pi), st.floats(0.01, 0.5))  # fmt: skip
def test_separated_pairs_min_gap_is_the_sampled_distance(i, j, direction, th1, th2, clearance):
    a, b = OTHERS[i], OTHERS[j]
    u = np.array([math.cos(direction), math.sin(direction)])
    lo, hi = 0.0, a.bounding_radius + b.bounding_radius + 1.0  # slide b out along u until apart
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        pa, pb = sample_boundary(a, (0, 0, th1), 300), sample_boundary(b, (*(mid * u), th2), 300)
        lo, hi = (mid, hi) if cKDTree(pa).query(pb)[0].min() < 0.02 else (lo, mid)
    poses = np.array([[0, 0, th1], [*((hi + clearance) * u), th2]])
    found = find([a, b], poses, [False, False], tol=10.0)
    sampled = cKDTree(sample_boundary(a, poses[0])).query(sample_boundary(b, poses[1]))[0].min()
    assert min(c.gap for c in found) == pytest.approx(sampled, abs=2e-3)


@settings(derandomize=True, max_examples=25, deadline=None)
@given(st.integers(0, 10_000), st.floats(-math.pi, math.pi), st.floats(-50, 50), st.floats(-50, 50))
def test_rigid_motion_of_the_scene_keeps_contacts_and_gaps(seed, phi, tx, ty):
    bodies, poses, fixed = mixed_scene(seed)
    tol = 0.3
    before = find(bodies, poses, fixed, tol)
    moved = poses.copy()
    moved[:, :2] = np.array([rot(phi, p) for p in poses[:, :2]]) + (tx, ty)
    moved[:, 2] += phi
    after = {(c.case, c.body1, c.body2, c.feature): c for c in find(bodies, moved, fixed, tol)}
    for c in before:
        if c.gap < tol - 1e-6:
            twin = after[(c.case, c.body1, c.body2, c.feature)]
            assert twin.gap == pytest.approx(c.gap, abs=1e-9)
            np.testing.assert_allclose(twin.normal, rot(phi, c.normal), atol=1e-8)
    assert len(after) >= sum(c.gap < tol - 1e-6 for c in before)


def test_features_are_stable_under_small_motion():
    bodies, poses, fixed = mixed_scene(3)
    a = find(bodies, poses, fixed, 0.3)
    nudged = poses + 1e-9
    b = find(bodies, nudged, fixed, 0.3)
    key = [(c.case, c.body1, c.body2, c.feature) for c in a if c.gap < 0.29]
    assert set(key) <= {(c.case, c.body1, c.body2, c.feature) for c in b}


# -- broad phase, cases, validation, speed ---------------------------------------------------


@settings(derandomize=True, max_examples=30, deadline=None)
@given(st.integers(0, 60), st.integers(0, 10_000), st.floats(0, 0.5))
def test_broad_phase_finds_exactly_the_overlapping_circles(n, seed, margin):
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-5, 5, (n, 2))
    radii = rng.uniform(0.05, 1.5, n) ** 2
    fixed = rng.random(n) < 0.2
    i, j = candidate_pairs(centres, radii, fixed, margin)
    want = [(a, b) for a in range(n) for b in range(a + 1, n)
            if not (fixed[a] and fixed[b]) and np.hypot(*(centres[a] - centres[b])) <= radii[a] + radii[b] + margin]  # fmt: skip
    assert list(zip(i.tolist(), j.tolist(), strict=True)) == want


@settings(derandomize=True, max_examples=30, deadline=None)
@given(st.integers(0, 60), st.integers(0, 10_000), st.floats(0, 0.5))
def test_broad_phase_with_groups_pairs_only_one_group_or_group_minus_one(n, seed, margin):
    rng = np.random.default_rng(seed)
    centres = rng.uniform(-2, 2, (n, 2))  # crowded: most circles of different groups overlap
    radii = rng.uniform(0.05, 1.0, n) ** 2
    fixed = rng.random(n) < 0.2
    groups = rng.integers(-1, 4, n)
    i, j = candidate_pairs(centres, radii, fixed, margin, groups)
    want = [(a, b) for a in range(n) for b in range(a + 1, n)
            if not (fixed[a] and fixed[b]) and (groups[a] == groups[b] or -1 in (groups[a], groups[b]))
            and np.hypot(*(centres[a] - centres[b])) <= radii[a] + radii[b] + margin]  # fmt: skip
    assert list(zip(i.tolist(), j.tolist(), strict=True)) == want


def test_copies_in_collision_groups_find_each_copy_s_own_contacts():
    """Copies of a scene laid over each other, one collision group each, sharing the walls
    (group -1) and each with its own bowl: the contacts found together are those of each copy
    found alone (same rows, bit for bit, indices moved), and no pair joins two copies."""
    walls, bowl, *moving = mixed_scene(0)[0]
    copies = [mixed_scene(seed)[1] for seed in range(6)]  # same bodies, other poses
    bodies, poses, groups = [walls], [copies[0][0]], [-1]
    for c, q in enumerate(copies):
        bodies += [bowl, *moving]
        poses += list(q[1:])
        groups += [c] * (1 + len(moving))
    fixed = [True] + [True, *[False] * len(moving)] * len(copies)
    together = ContactFinder(bodies, fixed, groups).find(np.array(poses), 0.3)
    check_contacts(together, np.array(poses))
    want = []
    for c, q in enumerate(copies):
        alone = find_contacts([walls, bowl, *moving], q, [True, True, *[False] * len(moving)], 0.3)
        index = np.r_[0, 1 + c * (1 + len(moving)) + np.arange(1 + len(moving))]
        moved = dataclasses.replace(alone, body1=index[alone.body1], body2=index[alone.body2])
        want += rows(moved)
    assert len(want) > 30
    key = lambda r: (min(r.body1, r.body2), max(r.body1, r.body2), r.feature)  # noqa: E731
    assert sorted(rows(together), key=key) == sorted(want, key=key)
    group = np.array(groups)
    one, two = group[together.body1], group[together.body2]
    assert np.all((one == two) | (one == -1) | (two == -1))


@pytest.mark.parametrize(
    ("groups", "words"),
    [
        ([0], "one group per shape (2), got 1"),
        ([0, -2], "groups[1] = -2.0"),
        ([0, 0.5], "groups[1] = 0.5"),
        ([0, float("nan")], "groups[1] = nan"),
        (["a", 0], "groups must be integers"),
    ],
)
def test_groups_are_checked(groups, words):
    with pytest.raises(ValueError, match=re.escape(words)):
        ContactFinder([FLOOR, SQUARE], [True, False], groups)


def test_narrow_phase_only_sees_broad_phase_pairs():
    bodies = [FLOOR, SQUARE, SQUARE, PENTAGON, FLOOR]
    poses = np.array([[0, 0, 0], [0, 0.5, 0], [3.0, 0.5, 0.3], [0, 7.0, 0], [0, 20.0, 0]])
    fixed = np.array([True, False, False, False, True])
    finder = ContactFinder(bodies, fixed)
    rows_, start, body, owner = finder.tables[:4]
    cand, inputs = np.zeros((1000, finder._candidates.shape[1])), finder._kernel_inputs
    everyone, no_groups = np.ones(5, dtype=bool), np.zeros(0, dtype=np.int64)
    count = find_candidates(
        poses,
        1e-6,
        np.zeros(5),
        everyone,
        no_groups,
        no_groups,  # no pairs kept apart
        rows_,
        start,
        body,
        owner,
        False,
        cand,
        inputs,
    )
    seen = {tuple(sorted(p)) for p in cand[:count, [BODY1, BODY2]].astype(int).tolist()}
    reach = body[:, 2] + 0.5e-6
    broad = {tuple(p) for p in sweep(poses[:, 0].copy(), poses[:, 1].copy(), reach, fixed).tolist()}
    assert seen == broad == {(0, 1), (0, 2)}


def test_possible_cases():
    disc, fixed2 = shapes.disc(0.1), [True, False, False]
    assert possible_cases([FLOOR, disc, disc], fixed2) == {"circle_edge", "circle_circle"}
    assert possible_cases([FLOOR, disc], [True, False]) == {"circle_edge"}
    assert possible_cases([FLOOR, FLOOR, disc], [True, True, False]) == {"circle_edge"}
    assert possible_cases([FLOOR, shapes.bowl(1, -3, 0)], [True, True]) == set()
    assert possible_cases([FLOOR, SQUARE], [True, False]) == {"vertex_edge"}
    assert possible_cases([SQUARE, SQUARE], [False, False]) == {"vertex_edge", "vertex_circle"}
    assert possible_cases([shapes.bowl(1, -3, 0), SQUARE], [True, False]) == {"vertex_circle"}
    rr = shapes.rounded_rect(1, 0.5, 0.1)
    assert possible_cases([FLOOR, rr], [True, False]) == {"circle_edge", "vertex_edge"}
    assert possible_cases([shapes.box_walls(2, 1), disc, disc], fixed2) == {
        "circle_edge",
        "circle_circle",
    }
    for seed in range(10):
        bodies, poses, fixed = mixed_scene(seed)
        used = {c.case for c in find(bodies, poses, fixed, 0.5)}
        assert used <= possible_cases(bodies, fixed)


@pytest.mark.parametrize(
    ("args", "word"),
    [
        (([SQUARE], [[0, 0]], [False], 0.1), "poses"),
        (([SQUARE], [[0, 0, float("nan")]], [False], 0.1), "poses"),
        (([SQUARE, SQUARE], [[0, 0, 0], [0, float("inf"), 0]], [False, False], 0.1), "poses"),
        (([SQUARE], [[0, 0, 0]], [False, True], 0.1), "fixed"),
        (([SQUARE], [[0, 0, 0]], [False], float("inf")), "tolerance"),
        (([SQUARE], [[0, 0, 0]], [False], "wide"), "tolerance"),
        ((["disc"], [[0, 0, 0]], [False], 0.1), "shapes"),
    ],
)
def test_find_contacts_validates_its_arguments(args, word):
    with pytest.raises(ValueError, match=word):
        find_contacts(*args)


@pytest.mark.parametrize(
    ("margins", "words"),
    [
        ([0.1], "shape (2,)"),
        ([0.1, -0.1], "margins[1] = -0.1"),
        ([0.1, float("nan")], "margins[1] = nan"),
        (["a", 0.1], "margins must be"),
    ],
)
def test_margins_are_checked(margins, words):
    finder = ContactFinder([FLOOR, SQUARE], [True, False])
    with pytest.raises(ValueError, match=re.escape(words)):
        finder.find(np.array([[0, 0, 0], [0, 0.5, 0.0]]), 0.0, margins)
