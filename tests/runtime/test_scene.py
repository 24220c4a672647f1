"""Tests of runtime/scene.py: mass properties, the shipped scenes, and the error messages."""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

from runtime.io.scene_file import SceneError, load_scene, scene_from_dict
from runtime.model.scene import Body, Scene

SCENES = Path(__file__).resolve().parents[2] / "scenes"
SCENE_FILES = sorted(SCENES.glob("*.toml"))
TOUCH = 1e-12  # "touching" means |gap| below this

# Pairs of bodies that each shipped scene starts in contact (|gap| <= TOUCH).
TOUCHING = {
    "disc_in_bowl": [("disc", "bowl")],
    "disc_on_incline": [("disc", "incline")],
    "block_on_incline": [("block", "incline")],
    "disc_rolling_in_bowl": [("disc", "bowl")],
    "disc_over_cylinder": [("disc", "cylinder")],
    "plank_on_cylinder": [("plank", "cylinder")],
    "rounded_box_into_bowl": [],
    "disc_pile": [],
    "rounded_stack": [
        ("block1", "floor"),
        ("block2", "block1"),
        ("block3", "block2"),
        ("block4", "block3"),
        ("block5", "block4"),
    ],
    "d_shape_rolling": [("d", "floor")],
    "disc_in_v": [("disc", "left"), ("disc", "right")],
    "box_on_floor": [("box", "floor")],
    "ball_drop": [],
    "wall_shot": [],
    "newtons_cradle": [("disc2", "disc3"), ("disc3", "disc4"), ("disc4", "disc5")],
}


def disc_body(name: str = "disc", radius: float = 0.1, position=(0.0, 0.0), **extra) -> dict:
    return {
        "name": name,
        "shape": {"type": "disc", "radius": radius},
        "density": 1000.0,
        "position": list(position),
        **extra,
    }


# -- mass properties and state conversion ------------------------------------------------


def test_disc_mass_and_inertia_from_density():
    scene = scene_from_dict({"body": [disc_body(radius=0.1)]})
    body = scene.bodies[0]
    mass = 1000.0 * math.pi * 0.1**2
    assert body.mass == pytest.approx(mass, rel=1e-12)
    assert body.inertia == pytest.approx(mass * 0.1**2 / 2, rel=1e-12)
    np.testing.assert_allclose(scene.inverse_masses, [[1 / mass, 1 / mass, 2 / (mass * 0.01)]])


def test_rectangle_polygon_mass_inertia_and_centre_of_mass():
    w, h, m = 0.4, 0.2, 2.0
    angle, omega, v = 0.3, 1.5, (0.5, -0.25)
    body_dict = {
        "name": "box",
        "shape": {"type": "polygon", "points": [[0, 0], [w, 0], [w, h], [0, h]]},
        "mass": m,
        "position": [1.0, 2.0],  # the polygon's own origin: its lower-left corner
        "angle": angle,
        "velocity": list(v),
        "angular_velocity": omega,
    }
    body = scene_from_dict({"body": [body_dict]}).bodies[0]
    assert body.mass == m
    assert body.inertia == pytest.approx(m * (w**2 + h**2) / 12, rel=1e-12)
    c, s = math.cos(angle), math.sin(angle)
    lever = np.array([c * w / 2 - s * h / 2, s * w / 2 + c * h / 2])
    np.testing.assert_allclose(body.position, np.array([1.0, 2.0]) + lever, rtol=0, atol=1e-15)
    np.testing.assert_allclose(
        body.velocity, np.array(v) + omega * np.array([-lever[1], lever[0]]), rtol=0, atol=1e-15
    )
    np.testing.assert_allclose(body.origin, [-w / 2, -h / 2], atol=1e-15)
    np.testing.assert_allclose(body.origin_position(), [1.0, 2.0], atol=1e-15)
    np.testing.assert_allclose(body.shape.centroid, [0.0, 0.0], atol=1e-15)
    assert body.angle == angle and body.angular_velocity == omega


def test_explicit_inertia_and_fixed_body_arrays():
    data = {
        "scene": {"gravity": [0.0, -1.0]},
        "body": [
            {
                "name": "floor",
                "fixed": True,
                "shape": {"type": "wall", "start": [-1, 0], "end": [1, 0]},
            },
            {
                "name": "disc",
                "shape": {"type": "disc", "radius": 0.1},
                "mass": 2.0,
                "inertia": 0.125,
                "position": np.array([0.0, 0.5]),  # the dict API takes arrays too
                "velocity": (1, 2),
            },
        ],
    }
    scene = scene_from_dict(data)
    assert scene.gravity == (0.0, -1.0)
    np.testing.assert_array_equal(scene.inverse_masses, [[0, 0, 0], [0.5, 0.5, 8.0]])
    np.testing.assert_array_equal(scene.poses(), [[0, 0, 0], [0, 0.5, 0]])
    np.testing.assert_array_equal(scene.velocities(), [[0, 0, 0], [1, 2, 0]])
    assert scene.bodies[0].mass == math.inf


def test_body_dataclass_computes_inertia():
    from runtime.model import shapes

    body = Body("d", shapes.disc(0.2), mass=3.0)
    assert body.inertia == pytest.approx(3.0 * 0.2**2 / 2, rel=1e-12)
    assert Body("w", shapes.wall((0, 0), (1, 0)), fixed=True).inverse_mass == 0.0


# -- shipped scenes ----------------------------------------------------------------------


def test_all_scenes_are_covered():
    assert {p.stem for p in SCENE_FILES} == set(TOUCHING)


@pytest.mark.parametrize("path", SCENE_FILES, ids=lambda p: p.stem)
def test_shipped_scene_loads_without_overlap_and_touches(path):
    scene = load_scene(path)
    assert scene.name and scene.source == str(path)
    assert scene.simulation.dt > 0 and scene.simulation.duration > 0
    assert np.all(np.isfinite(scene.poses())) and np.all(np.isfinite(scene.inverse_masses))
    contacts = scene.contacts()
    for k, gap in enumerate(contacts.gap):
        assert gap >= -TOUCH, (contacts.describe(k), scene.bodies[contacts.body1[k]].name)
    for a, b in TOUCHING[path.stem]:
        pair = {scene.index(a), scene.index(b)}
        gaps = [
            g
            for g, i, j in zip(contacts.gap, contacts.body1, contacts.body2, strict=True)
            if {int(i), int(j)} == pair
        ]
        assert gaps and min(abs(g) for g in gaps) <= TOUCH, (a, b, gaps)
    for body in scene.bodies:
        if not body.fixed:
            assert body.mass > 0 and body.inertia > 0
            np.testing.assert_allclose(body.shape.centroid, [0.0, 0.0], atol=1e-12)


def test_disc_pile_has_twenty_discs_and_no_vertex_case():
    scene = load_scene(SCENES / "disc_pile.toml")
    assert sum(not b.fixed for b in scene.bodies) == 20
    cases = scene.contact_cases()
    assert cases and not any(case.startswith("vertex") for case in cases)
    assert "circle_circle" in cases and "circle_edge" in cases


@pytest.mark.parametrize(
    "name", ["disc_in_bowl", "disc_on_incline", "disc_over_cylinder", "disc_in_v", "disc_pile"]
)
def test_scenes_of_discs_and_walls_need_no_vertex_case(name):
    cases = load_scene(SCENES / f"{name}.toml").contact_cases()
    assert cases and cases <= {"circle_edge", "circle_circle"}, cases


def test_disc_in_bowl_starts_at_rest_0_3_rad_off_the_bottom():
    scene = load_scene(SCENES / "disc_in_bowl.toml")
    disc = scene.body("disc")
    x, y = np.array(disc.position) - scene.body("bowl").position
    assert math.atan2(x, -y) == pytest.approx(0.3, abs=1e-12)
    assert math.hypot(x, y) == pytest.approx(0.9, abs=1e-12)
    assert disc.twist.tolist() == [0.0, 0.0, 0.0]


def test_shifted_and_copy():
    scene = load_scene(SCENES / "disc_in_bowl.toml")
    far = scene.shifted(1e6, -2e6)
    np.testing.assert_array_equal(
        far.poses()[:, :2] - scene.poses()[:, :2], np.tile([1e6, -2e6], (len(scene.bodies), 1))
    )
    np.testing.assert_array_equal(scene.poses()[:, 2], far.poses()[:, 2])
    gaps = sorted(far.contacts().gap.tolist())
    assert gaps and abs(gaps[0]) < 1e-9
    twin = scene.copy()
    twin.bodies[1].position = (5.0, 5.0)
    assert scene.bodies[1].position != (5.0, 5.0)
    assert scene.with_simulation(dt=1e-4).simulation.dt == 1e-4 and scene.simulation.dt != 1e-4


# -- bad input ---------------------------------------------------------------------------

GOOD_HEADER = """
[scene]
name = "test"

[simulation]
duration = 1.0
dt = 0.001
"""

FLOOR = """
[[body]]
name = "floor"
fixed = true
shape = { type = "wall", start = [-2.0, 0.0], end = [2.0, 0.0] }
"""


def write(tmp_path: Path, body: str, header: str = GOOD_HEADER) -> Path:
    path = tmp_path / "bad.toml"
    path.write_text(textwrap.dedent(header) + FLOOR + textwrap.dedent(body))
    return path


def expect_error(path: Path, *parts: str) -> str:
    with pytest.raises(SceneError) as info:
        load_scene(path)
    message = str(info.value)
    assert message.startswith(f"{path}: "), message
    for part in parts:
        assert part in message, (part, message)
    assert info.value.__cause__ is None and info.value.__suppress_context__  # no chained trace
    return message


def disc_toml(shape: str = 'type = "disc", radius = 0.1', extra: str = "") -> str:
    return f"""
    [[body]]
    name = "disc"
    shape = {{ {shape} }}
    density = 1000.0
    position = [0.0, 0.5]
    {extra}
    """


BAD_BODIES = {
    "negative radius": (
        disc_toml('type = "disc", radius = -1.0'),
        ["body 'disc' (#2)", "field 'shape.radius'", "must be > 0, got -1.0"],
    ),
    "zero radius": (disc_toml('type = "disc", radius = 0'), ["field 'shape.radius'", "> 0"]),
    "nan radius": (disc_toml('type = "disc", radius = nan'), ["field 'shape.radius'", "finite"]),
    "string radius": (
        disc_toml('type = "disc", radius = "0.1"'),
        ["field 'shape.radius'", "expected a number", "'0.1'"],
    ),
    "misspelt shape key": (
        disc_toml('type = "disc", radus = 0.1'),
        ["field 'shape.radus'", "unknown key", "did you mean 'radius'"],
    ),
    "corner radius too large": (
        disc_toml('type = "rounded_rect", width = 1.0, height = 0.2, corner_radius = 0.2'),
        ["body 'disc' (#2)", "field 'shape.corner_radius'", "0.2"],
    ),
    "missing shape parameter": (
        disc_toml('type = "ellipse", a = 0.1'),
        ["body 'disc' (#2)", "field 'shape.b'", "missing"],
    ),
    "unknown shape type": (
        disc_toml('type = "dsic", radius = 0.1'),
        ["field 'shape.type'", "did you mean 'disc'"],
    ),
    "misspelt body key": (
        disc_toml(extra="positon = [0.0, 1.0]"),
        ["body 'disc' (#2)", "field 'positon'", "did you mean 'position'"],
    ),
    "zero mass": (
        disc_toml().replace("density = 1000.0", "mass = 0.0"),
        ["body 'disc' (#2)", "field 'mass'", "must be > 0, got 0.0"],
    ),
    "negative density": (
        disc_toml().replace("1000.0", "-5.0"),
        ["field 'density'", "must be > 0, got -5.0"],
    ),
    "no mass or density": (
        disc_toml().replace("density = 1000.0", ""),
        ["body 'disc' (#2)", "field 'mass'", "missing", "'density'"],
    ),
    "mass and density": (disc_toml(extra="mass = 1.0"), ["field 'mass'", "not both"]),
    "zero inertia": (disc_toml(extra="inertia = 0.0"), ["field 'inertia'", "> 0"]),
    "missing position": (
        disc_toml().replace("position = [0.0, 0.5]", ""),
        ["field 'position'", "missing required field"],
    ),
    "scalar position": (
        disc_toml().replace("[0.0, 0.5]", "0.5"),
        ["field 'position'", "expected a list of 2 numbers", "0.5"],
    ),
    "three-component position": (
        disc_toml().replace("[0.0, 0.5]", "[0.0, 0.5, 1.0]"),
        ["field 'position'", "list of 2 numbers"],
    ),
    "string in vector": (
        disc_toml(extra='velocity = [1.0, "fast"]'),
        ["field 'velocity[1]'", "expected a number"],
    ),
    "infinite position": (
        disc_toml().replace("[0.0, 0.5]", "[inf, 0.5]"),
        ["field 'position[0]'", "must be finite, got inf"],
    ),
    "number for a flag": (disc_toml(extra="fixed = 1"), ["field 'fixed'", "true or false"]),
    "restitution above one": (
        disc_toml(extra="restitution = 1.5"),
        ["field 'restitution'", "between 0 and 1"],
    ),
    "missing shape": (
        disc_toml().replace('shape = { type = "disc", radius = 0.1 }', ""),
        ["body 'disc' (#2)", "field 'shape'", "missing"],
    ),
    "scalar shape": (
        disc_toml().replace('{ type = "disc", radius = 0.1 }', "0.1"),
        ["field 'shape'", "expected a table"],
    ),
    "non-convex polygon": (
        disc_toml('type = "polygon", points = [[0, 0], [1, 0], [0.2, 0.2], [0, 1]]'),
        ["body 'disc' (#2)", "field 'shape.points'", "convex"],
    ),
    "self-intersecting polygon": (
        disc_toml('type = "polygon", points = [[0, 0], [1, 1], [1, 0], [0, 1]]'),
        ["body 'disc' (#2)", "field 'shape.points'"],
    ),
    "polygon point not a pair": (
        disc_toml('type = "polygon", points = [[0, 0], [1, 0], 5]'),
        ["field 'shape.points[2]'", "list of 2 numbers"],
    ),
    "bowl on a moving body": (
        disc_toml('type = "bowl", radius = 1.0, start_angle = -2.5, end_angle = -0.6'),
        ["body 'disc' (#2)", "field 'shape.type'", "no area", "'thickness'", "fixed = true"],
    ),
    "wall on a moving body": (
        disc_toml('type = "wall", start = [0, 0], end = [1, 0]'),
        ["field 'shape.type'", "fixed"],
    ),
    "moving fixed body": (
        FLOOR.replace('"floor"', '"ground"') + "velocity = [1.0, 0.0]\n",
        ["body 'ground' (#2)", "field 'velocity'", "fixed"],
    ),
    "mass on fixed body": (
        FLOOR.replace('"floor"', '"ground"') + "mass = 1.0\n",
        ["body 'ground' (#2)", "field 'mass'", "infinite mass"],
    ),
    "duplicate name": (disc_toml().replace('"disc"', '"floor"', 1), ["field 'name'", "duplicate"]),
    "unnamed body with bad value": (
        '[[body]]\nshape = { type = "disc", radius = 0.1 }\nmass = -1.0\nposition = [0, 1]\n',
        ["body #2: field 'mass'", "must be > 0, got -1.0"],
    ),
}


@pytest.mark.parametrize("case", list(BAD_BODIES))
def test_bad_body_is_reported_with_file_body_and_field(tmp_path, case):
    body, parts = BAD_BODIES[case]
    expect_error(write(tmp_path, body), *parts)


def test_overlapping_bodies_name_both_and_the_depth(tmp_path):
    path = write(tmp_path, disc_toml().replace("[0.0, 0.5]", "[0.0, 0.05]"))
    message = expect_error(path, "body 'floor' (#1)", "body 'disc' (#2)", "field 'position'")
    assert "overlap by 0.05 m" in message


def test_overlap_between_two_moving_bodies(tmp_path):
    second = (
        disc_toml().replace('name = "disc"', 'name = "other"').replace("[0.0, 0.5]", "[0.15, 0.5]")
    )
    path = write(tmp_path, disc_toml() + second)
    message = expect_error(path, "body 'disc' (#2)", "body 'other' (#3)")
    assert "overlap by 0.05 m" in message


@pytest.mark.parametrize(
    ("bodies", "parts"),
    [
        # centre on the floor: the contact finder drops contacts deeper than half the body
        (
            disc_toml().replace("[0.0, 0.5]", "[0.0, 0.0]"),
            ["body 'floor' (#1)", "body 'disc' (#2)"],
        ),
        (
            disc_toml()
            + disc_toml('type = "disc", radius = 0.02')
            .replace('name = "disc"', 'name = "pebble"')
            .replace("[0.0, 0.5]", "[0.01, 0.52]"),
            ["body 'disc' (#2) and body 'pebble' (#3)", "lies inside 'disc'"],
        ),
        (
            '[[body]]\nname = "box"\nfixed = true\nposition = [0.0, 1.0]\n'
            'shape = { type = "box_walls", width = 1.0, height = 1.0 }\n'
            # a plank across the right wall, its centre inside: 0.15 m through, far deeper than
            # its half-thickness (so the contact finder drops it; sampling finds it)
            + disc_toml(
                'type = "polygon", points = [[-0.2, -0.01], [0.2, -0.01], [0.2, 0.01], [-0.2, 0.01]]'
            ).replace("[0.0, 0.5]", "[0.45, 1.5]"),
            ["body 'box' (#2) and body 'disc' (#3)", "overlap by at least 0.15 m"],
        ),
    ],
    ids=["centre on floor", "inside another body", "across a box wall"],
)
def test_deep_overlaps_are_found(tmp_path, bodies, parts):
    message = expect_error(write(tmp_path, bodies), "field 'position'", *parts)
    assert "overlap" in message


def test_body_entirely_behind_a_wall_is_not_an_overlap(tmp_path):
    scene = load_scene(write(tmp_path, disc_toml().replace("[0.0, 0.5]", "[0.0, -0.5]")))
    assert len(scene.contacts()) == 0


def test_half_disc_centre_of_mass_and_inertia():
    r, m = 0.3, 2.0
    data = {
        "body": [
            {
                "name": "half",
                "shape": {"type": "half_disc", "radius": r},
                "mass": m,
                "position": [1.0, 2.0],  # the centre of the arc
                "angle": math.pi / 2,
                "angular_velocity": 2.0,
            }
        ]
    }
    body = scene_from_dict(data).bodies[0]
    c = 4 * r / (3 * math.pi)
    np.testing.assert_allclose(body.position, [1.0 - c, 2.0], atol=1e-15)
    np.testing.assert_allclose(body.velocity, [0.0, -2.0 * c], atol=1e-15)
    assert body.inertia == pytest.approx(m * r**2 / 2 - m * c**2, rel=1e-12)


def test_small_overlap_within_tolerance_is_accepted(tmp_path):
    scene = load_scene(write(tmp_path, disc_toml().replace("[0.0, 0.5]", "[0.0, 0.0999999999999]")))
    assert min(scene.contacts().gap) == pytest.approx(-1e-13, abs=1e-15)


@pytest.mark.parametrize(
    ("header", "parts"),
    [
        ("[scene]\ngravity = 9.81\n", ["[scene]: field 'gravity'", "list of 2 numbers"]),
        ("[scene]\ngravity = [0, nan]\n", ["[scene]: field 'gravity[1]'", "finite"]),
        ("[scene]\ncontact_tolerance = -1e-3\n", ["field 'contact_tolerance'", "> 0"]),
        ("[scene]\ngravty = [0, -1]\n", ["[scene]: field 'gravty'", "did you mean 'gravity'"]),
        ("[simulaton]\ndt = 0.01\n", ["field 'simulaton'", "did you mean 'simulation'"]),
        ("[simulation]\ndt = 0.0\n", ["[simulation]: field 'dt'", "> 0"]),
        ("[simulation]\ndt = 2.0\nduration = 1.0\n", ["field 'dt'", "duration"]),
        ("[simulation]\nmethod = 4\n", ["[simulation]: field 'method'", "string"]),
        ('[simulation]\nmethod = "rk5"\n', ["field 'method'", "did you mean 'rk45'"]),
        ("gravity = [0.0, -1.0]\n", ["field 'gravity'", "belongs in the [scene] table"]),
        ('[simulation]\nstabilisation = "yes"\n', ["field 'stabilisation'", "true or false"]),
    ],
)
def test_bad_scene_tables(tmp_path, header, parts):
    expect_error(write(tmp_path, disc_toml(), header=header), *parts)


def test_body_written_as_a_single_table(tmp_path):
    path = tmp_path / "single.toml"
    path.write_text('[body]\nname = "d"\nshape = { type = "disc", radius = 0.1 }\n')
    expect_error(path, "field 'body'", "[[body]]")


def test_no_bodies(tmp_path):
    path = tmp_path / "empty.toml"
    path.write_text('[scene]\nname = "empty"\n')
    expect_error(path, "field 'body'", "at least one")


def test_toml_syntax_error_gives_the_line(tmp_path):
    path = tmp_path / "syntax.toml"
    path.write_text(
        '[scene]\nname = "x"\n\n[[body]]\nname = "d"\nshape = { type = "disc" radius = 0.1 }\n'
    )
    message = expect_error(path, "line 6", "TOML syntax error")
    assert "Traceback" not in message


def test_missing_file(tmp_path):
    path = tmp_path / "nowhere.toml"
    expect_error(path, "file not found")
    expect_error(tmp_path, "cannot read the file")


def test_dict_api_names_the_source():
    with pytest.raises(SceneError, match=r"^<dict>: body 'disc' \(#1\): field 'shape\.radius'"):
        scene_from_dict({"body": [disc_body(radius=-0.1)]})
    with pytest.raises(SceneError, match=r"^my-test: .*field 'mass'"):
        scene_from_dict({"body": [disc_body(mass=1.0)]}, source="my-test")


def test_scene_error_is_a_value_error_and_no_numpy_warning(tmp_path, recwarn):
    path = write(tmp_path, disc_toml(extra="inertia = inf"))
    with pytest.raises(ValueError):
        load_scene(path)
    assert not recwarn.list


def test_scene_dataclass_direct_construction():
    scene = Scene("empty", [])
    assert scene.poses().shape == (0, 3) and scene.inverse_masses.shape == (0, 3)


# -- ellipses placed exactly touching (issue #13: refused by up to 4.8 mm) ------------------


def _turn(th: float, v) -> np.ndarray:
    c, s = math.cos(th), math.sin(th)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _support(a: float, b: float, th: float, u: np.ndarray) -> np.ndarray:
    """The point of a centred ellipse turned by ``th`` farthest along ``u`` (where its outward
    normal is ``u``): the reference for placing bodies against it, independent of the loader."""
    local = _turn(-th, u)
    t = math.atan2(b * local[1], a * local[0])
    return _turn(th, (a * math.cos(t), b * math.sin(t)))


def _ellipse(name: str, a: float, b: float, position, angle: float) -> dict:
    return {"name": name, "shape": {"type": "ellipse", "a": a, "b": b}, "density": 1.0,
            "position": [float(x) for x in position], "angle": angle}  # fmt: skip


def _touching_pairs(rng) -> dict[str, tuple[list, np.ndarray]]:
    """Bodies placed exactly touching a random ellipse (turned, 0.05..1.5 m axes), each with
    the unit direction that moves the second body into the first."""
    a, b = rng.uniform(0.05, 1.5, 2)
    th = rng.uniform(-math.pi, math.pi)
    phi = rng.uniform(-math.pi, math.pi)
    n = np.array([math.cos(phi), math.sin(phi)])  # normal at the touch, out of the ellipse
    a2, b2, th2, r = (
        *rng.uniform(0.05, 1.5, 2),
        rng.uniform(-math.pi, math.pi),
        rng.uniform(0.01, 1),
    )
    tip = _support(a, b, th, n)
    side = np.array(
        [n[1], -n[0]]
    )  # a wall from -5 side to 5 side faces n (material on the -n side)
    corner = [[0.0, 0.0]] + [
        [0.2 * math.cos(phi + d), 0.2 * math.sin(phi + d)] for d in (0.5, -0.5)
    ]
    low = _support(a, b, th, np.array([0.0, -1.0]))
    return {
        "ellipse": ([_ellipse("e1", a, b, (0, 0), th),
                     _ellipse("e2", a2, b2, tip - _support(a2, b2, th2, -n), th2)], -n),
        "disc": ([_ellipse("e", a, b, (0, 0), th), disc_body("d", r, tip + r * n)], -n),
        "polygon corner": ([_ellipse("e", a, b, (0, 0), th),
                            {"name": "p", "shape": {"type": "polygon", "points": corner},
                             "density": 1.0, "position": list(tip)}], -n),
        "floor": ([{"name": "floor", "fixed": True,
                    "shape": {"type": "wall", "start": [-5.0, 0.0], "end": [5.0, 0.0]}},
                   _ellipse("e", a, b, (0.3, -low[1]), th)], np.array([0.0, -1.0])),
        "wall": ([{"name": "wall", "fixed": True,
                   "shape": {"type": "wall", "start": list(-5 * side), "end": list(5 * side)}},
                  _ellipse("e", a, b, -_support(a, b, th, -n), th)], -n),
    }  # fmt: skip


@pytest.mark.parametrize("pair", ["ellipse", "disc", "polygon corner", "floor", "wall"])
def test_exact_touch_on_an_ellipse_loads_and_one_micrometre_inside_is_refused(pair):
    rng = np.random.default_rng(9)
    for _ in range(25):
        bodies, into = _touching_pairs(rng)[pair]
        scene = scene_from_dict({"scene": {"gravity": [0.0, 0.0]}, "body": bodies})
        assert min(scene.contacts().gap, default=0.0) > -1e-9
        moved = [dict(body) for body in bodies]
        moved[1]["position"] = list(np.asarray(bodies[1]["position"]) + 1e-6 * into)
        with pytest.raises(SceneError, match=r"overlap by (at least )?1e-06 m at t = 0"):
            scene_from_dict({"scene": {"gravity": [0.0, 0.0]}, "body": moved})


# -- angles: reduced at load, refused beyond precision, degrees warned (issue #13, #14) -----


@pytest.mark.parametrize("angle", [4.0, -4.0, math.pi, -math.pi, 7.5, -1e6, 1e12, 5e14])
def test_body_angle_is_reduced_to_minus_pi_pi_exactly(angle):
    """Reference: the angle modulo 2 pi in 50-digit arithmetic (mpmath), folded into
    (-pi, pi]; the centre of mass of an off-centre shape follows the same turn."""
    mpmath = pytest.importorskip("mpmath")
    with mpmath.workdps(50):
        exact = mpmath.mpf(angle) - 2 * mpmath.pi * mpmath.floor(
            (mpmath.mpf(angle) + mpmath.pi) / (2 * mpmath.pi)
        )  # in [-pi, pi)
        exact = float(exact if exact > -mpmath.pi else exact + 2 * mpmath.pi)
    half = {"name": "h", "shape": {"type": "half_disc", "radius": 0.5}, "density": 1.0,
            "position": [1.0, 2.0], "angle": angle}  # fmt: skip
    body = scene_from_dict({"body": [half]}).bodies[0]
    assert -math.pi < body.angle <= math.pi
    # equal as angles (-pi and pi are one angle; the float -pi lies just inside (-pi, pi])
    assert abs(math.remainder(body.angle - exact, 2 * math.pi)) <= 4e-16
    c = 4 * 0.5 / (3 * math.pi)  # the centroid above the arc's centre, turned by the angle
    np.testing.assert_allclose(
        body.position, [1.0 - c * math.sin(exact), 2.0 + c * math.cos(exact)], rtol=0, atol=1e-15
    )


def test_an_angle_in_range_is_kept_bit_for_bit():
    body = scene_from_dict({"body": [disc_body(angle=0.3)]}).bodies[0]
    assert body.angle == 0.3


def test_angle_at_the_precision_limit_is_refused_naming_the_field():
    with pytest.raises(SceneError) as err:
        scene_from_dict({"body": [disc_body(angle=2.0**49)]})
    assert str(err.value) == (
        "<dict>: body 'disc' (#1): field 'angle': must be below 5.63e+14 rad in magnitude, got "
        "5.6295e+14: doubles there are 0.125 rad apart, so the angle meant is lost; give it "
        "modulo 2 pi"
    )


def test_an_angle_that_looks_like_degrees_warns_once_from_the_callers_line():
    from runtime.io.scene_file import SceneWarning

    with pytest.warns(SceneWarning) as caught:
        scene_from_dict({"body": [disc_body(angle=90)]})
    assert [str(w.message) for w in caught] == [
        "<dict>: body 'disc' (#1): field 'angle': angles are in radians: 90 looks like degrees "
        "(90 deg = 1.5708 rad)"
    ]
    assert caught[0].filename == __file__  # attributed to this call, not to the loader
    bowl = {"name": "bowl", "fixed": True,
            "shape": {"type": "bowl", "radius": 1.0, "start_angle": -10.0, "end_angle": -5.0}}  # fmt: skip
    with pytest.warns(SceneWarning, match=r"field 'shape\.start_angle': .*-10 looks like degrees"):
        scene_from_dict({"body": [bowl]})


@pytest.mark.parametrize("angle", [0.3, 3.0, 6.0, 7.5, 400.0, -1e6])
def test_angles_that_do_not_look_like_degrees_do_not_warn(angle, recwarn):
    scene_from_dict({"body": [disc_body(angle=angle)]})
    assert not recwarn.list


# -- energies and momenta float64 can hold (issue #13: inf energies written as a success) ----


@pytest.mark.parametrize(
    ("bodies", "message"),
    [
        (
            [disc_body(mass=1e300, position=(0.0, 1e9))],
            "body 'disc' (#1): field 'position': its potential energy overflows float64 "
            "(mass 1e+300 kg at (0, 1e+09) m)",
        ),
        (
            [
                disc_body(mass=1e300, position=(0.0, 1e7)),
                disc_body("b", mass=1e300, position=(0.0, -1e7)),
            ],
            "body 'disc' (#1): field 'position': its share of the energy scale, m |g| (H + 2 r), "
            "overflows float64 (mass 1e+300 kg, H = 2e+07 m the height the scene spans)",
        ),
        (
            [disc_body(mass=1.5e308, velocity=(1.5, 0.0))],
            "body 'disc' (#1): field 'velocity': its momentum overflows float64 "
            "(mass 1.5e+308 kg, speed 1.5 m/s)",
        ),
        (
            [
                disc_body(mass=1e307, position=(0.0, 1.0)),
                disc_body("twin", mass=1e307, position=(0.5, 1.0)),
            ],
            "body 'twin' (#2): field 'position': the scene's total potential energy overflows "
            "float64 (with this body)",
        ),
    ],
    ids=["m g h", "energy scale", "momentum", "total"],
)
def test_energies_and_momenta_that_overflow_are_refused_naming_body_and_field(bodies, message):
    for body in bodies:
        body.pop("density")
    with pytest.raises(SceneError) as err:
        scene_from_dict({"body": bodies})
    assert str(err.value) == f"<dict>: {message}"


def test_the_largest_finite_energies_still_load():
    """The check is an overflow test, not a size limit: 1e306 kg twins at y = 1 m load, and
    their energy sum is finite (reference: m g y summed by hand)."""
    bodies = [
        disc_body(mass=1e306, position=(0.0, 1.0)),
        disc_body("twin", mass=1e306, position=(0.5, 1.0)),
    ]
    for body in bodies:
        body.pop("density")
    scene = scene_from_dict({"body": bodies})
    assert sum(b.mass * 9.81 * b.position[1] for b in scene.bodies) == pytest.approx(1.962e307)


# -- [simulation] stabilisation reaches the scene (issue #13; simulate reads it: the lead) ---


@pytest.mark.parametrize("flag", [True, False])
def test_stabilisation_flag_in_the_file_is_carried_by_the_scene(tmp_path, flag):
    header = GOOD_HEADER + f"stabilisation = {str(flag).lower()}\n"
    scene = load_scene(write(tmp_path, disc_toml(), header=header))
    assert scene.simulation.stabilisation is flag
    assert load_scene(write(tmp_path, disc_toml())).simulation.stabilisation is False


# -- tolerances against tiny bodies (issue #13: a suggested tolerance the loader refused) ----


def _tiny(kind: str, size: float) -> dict:
    shape = {
        "disc": {"type": "disc", "radius": size},
        "ellipse": {"type": "ellipse", "a": 3 * size, "b": size},
        "rounded_rect": {"type": "rounded_rect", "width": 2 * size, "height": 2.2 * size,
                         "corner_radius": 0.3 * size},
        "polygon": {"type": "polygon", "points": [[0, 0], [2 * size, 0], [0, 2 * size]]},
    }[kind]  # fmt: skip
    return {"name": "grain", "shape": shape, "density": 1.0, "position": [0.0, 0.0]}


@pytest.mark.parametrize("kind", ["disc", "ellipse", "rounded_rect", "polygon"])
def test_the_suggested_tolerance_is_one_the_loader_accepts(kind):
    """Down to the smallest body: following the message (both tolerances at the suggested
    value) loads; below that, the body itself is refused with the smallest size stated."""
    import re

    for size in np.geomspace(1e-50, 1e-4, 37):
        try:
            scene_from_dict({"body": [_tiny(kind, float(size))]})
            continue  # the defaults fit
        except SceneError as exc:
            message = str(exc)
        found = re.search(r"set it to at most (\S+) m", message)
        if found is None:
            assert message.startswith("<dict>: body 'grain' (#1): field 'shape': half-width "), (
                message
            )
            assert "is below 2e-50 m, the smallest moving body" in message, message
            continue
        assert ", and overlap_tolerance" in message or float(size) > 1e-9
        value = float(found[1])
        tolerances = {"contact_tolerance": value, "overlap_tolerance": value}
        scene = scene_from_dict({"scene": tolerances, "body": [_tiny(kind, float(size))]})
        assert scene.contact_tolerance == value


# -- bodies behind the back face of a wall, bowl or box (issue #14: "swap start and end") ---


def _wall(start, end, name: str = "wall", **extra) -> dict:
    shape = {"type": "wall", "start": [float(v) for v in start], "end": [float(v) for v in end]}
    return {"name": name, "fixed": True, "shape": shape, **extra}


def test_a_body_behind_a_turned_wall_is_refused_exactly_where_it_is_level_and_near():
    """Reference, in the wall's own frame (x along start -> end, y to its front, the left):
    refused iff 0 <= x <= L and -3 r < y < 0 (its bounding circle within its diameter of the
    back face), with the depth -y in the message; checked for discs on a grid around walls
    turned and placed at random."""
    import re

    rng = np.random.default_rng(14)
    r, length = 0.1, 2.0
    for _ in range(6):
        th, origin = rng.uniform(-math.pi, math.pi), rng.uniform(-5, 5, 2)
        along, left = (
            np.array([math.cos(th), math.sin(th)]),
            np.array([-math.sin(th), math.cos(th)]),
        )
        # a wall's material is on the right of start -> end: its front is to the left
        wall = _wall(origin, origin + length * along)
        for x in (-0.15, -0.05, 0.01, 0.7, 1.99, 2.05):  # not at the ends: rounding
            for y in (-0.6, -0.31, -0.29, -0.2, -0.05, 0.1, 0.5):
                body = disc_body(position=origin + x * along + y * left)
                refused = 0 <= x <= length and -3 * r < y < 0
                try:
                    scene_from_dict({"scene": {"gravity": [0.0, 0.0]}, "body": [wall, body]})
                    assert not refused, (th, x, y)
                except SceneError as exc:
                    message = str(exc)
                    if not refused:  # only a genuine overlap may refuse it otherwise
                        assert "overlap" in message and -r < y < r, (th, x, y, message)
                        continue
                    assert message.startswith("<dict>: body 'wall' (#1): field 'shape': body "
                                              "'disc' (#2) is at the back of this wall"), message  # fmt: skip
                    depth = float(re.search(r"its centre (\S+) m behind it", message)[1])
                    assert depth == pytest.approx(-y, rel=1e-3)
                    assert "swap start and end to make it face 'disc'" in message


def test_a_plate_of_two_walls_back_to_back_shields_the_body_resting_on_it():
    """A body on the top face is behind the bottom face's back, but the top face lies between:
    not refused. Without the top face it is."""
    top, bottom = _wall((-1, 0), (1, 0), "top"), _wall((1, -0.02), (-1, -0.02), "bottom")
    scene = scene_from_dict({"body": [top, bottom, disc_body(position=(0.0, 0.1))]})
    assert min(scene.contacts().gap) == pytest.approx(0.0, abs=1e-15)
    with pytest.raises(SceneError, match="body 'bottom' .* is at the back of this wall"):
        scene_from_dict({"body": [bottom, disc_body(position=(0.0, 0.1))]})


@pytest.mark.parametrize(
    ("fixed", "position", "message"),
    [
        (
            {"type": "bowl", "radius": 1.0, "start_angle": -2.5, "end_angle": -0.6},
            (0.0, -1.1),
            "body 'disc' (#2) is outside this bowl (its centre 0.1 m behind its arc), at its "
            "back: a bowl holds bodies inside its circle (radius 1 m); move 'disc' inside, or "
            "use a fixed disc for a surface to rest on from outside",
        ),
        (
            {"type": "box_walls", "width": 1.0, "height": 0.5},
            (0.0, -0.15),
            "body 'disc' (#2) is outside this box (its centre 0.15 m behind its floor): box "
            "walls face inwards; move 'disc' inside, or use walls facing it",
        ),
        (
            {"type": "box_walls", "width": 1.0, "height": 0.5},
            (0.65, 0.25),
            "body 'disc' (#2) is outside this box (its centre 0.15 m behind its right side): "
            "box walls face inwards; move 'disc' inside, or use walls facing it",
        ),
    ],
    ids=["under a bowl", "under a box", "beside a box"],
)
def test_a_body_at_the_back_of_a_bowl_or_box_gets_the_fix_for_it(fixed, position, message):
    bodies = [{"name": "c", "fixed": True, "shape": fixed}, disc_body(position=position)]
    with pytest.raises(SceneError) as err:
        scene_from_dict({"body": bodies})
    assert str(err.value) == f"<dict>: body 'c' (#1): field 'shape': {message}"
    inside = (0.0, -0.9) if fixed["type"] == "bowl" else (0.0, 0.1)
    scene_from_dict({"body": [bodies[0], disc_body(position=inside)]})  # in front: loads


def test_a_wall_turned_by_its_body_angle_faces_the_other_way():
    floor = _wall((-2, 0), (2, 0), "floor", angle=math.pi)
    with pytest.raises(SceneError, match="body 'floor' .* is at the back of this wall"):
        scene_from_dict({"body": [floor, disc_body(position=(0.0, 0.1))]})
