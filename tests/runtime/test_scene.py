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
    contacts = scene.find_contacts()
    for contact in contacts:
        assert contact.gap >= -TOUCH, (contact, scene.bodies[contact.body1].name)
    for a, b in TOUCHING[path.stem]:
        pair = {scene.index(a), scene.index(b)}
        gaps = [c.gap for c in contacts if {c.body1, c.body2} == pair]
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
    gaps = sorted(c.gap for c in far.find_contacts())
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
        ["body 'disc' (#2)", "field 'shape.type'", "concave", "not supported", "fixed"],
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
            + disc_toml().replace("[0.0, 0.5]", "[0.52, 1.5]"),  # centre beyond the wall
            ["body 'box' (#2) and body 'disc' (#3)", "overlap by at least 0.0"],
        ),
    ],
    ids=["centre on floor", "inside another body", "across a box wall"],
)
def test_deep_overlaps_are_found(tmp_path, bodies, parts):
    message = expect_error(write(tmp_path, bodies), "field 'position'", *parts)
    assert "overlap" in message


def test_body_entirely_behind_a_wall_is_not_an_overlap(tmp_path):
    scene = load_scene(write(tmp_path, disc_toml().replace("[0.0, 0.5]", "[0.0, -0.5]")))
    assert scene.find_contacts() == []


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
    assert min(c.gap for c in scene.find_contacts()) == pytest.approx(-1e-13, abs=1e-15)


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
