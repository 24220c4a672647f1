"""Large angles keep contacts exact (issue #13: 1e12 rad gave 4.7e-6 m of unreported penetration).

Why: an angle is only as precise as its float spacing (1.2e-4 rad at 1e12), and every contact
point is rotated by it. The World wraps angles beyond settings.ANGLE_WRAP to (-pi, pi] between
steps (a long spin), and the loader reduces a scene file's angle exactly (atan2 of its sine and
cosine). References: a free spin is exact (theta = w t), the lowest corner of a box is a
closed form, and 1e12 mod 2 pi is computed with mpmath at 50 digits.
"""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
import strategies

import runtime
from runtime import settings

CORNERS = np.array([[0.2, 0.1], [-0.2, 0.1], [-0.2, -0.1], [0.2, -0.1]])  # the 0.4 x 0.2 box
BOX = {"type": "rounded_rect", "width": 0.4, "height": 0.2, "corner_radius": 0.0}
SHAPE_TOML = {
    "box": '{ type = "rounded_rect", width = 0.4, height = 0.2, corner_radius = 0.0 }',
    "disc": '{ type = "disc", radius = 0.1 }',
}
FLOOR = {"name": "floor", "fixed": True,
         "shape": {"type": "wall", "start": [-5.0, 0.0], "end": [5.0, 0.0]}}  # fmt: skip


def _lowest_corner(angle: float) -> float:
    """y of the box's lowest corner (body at the origin, turned by ``angle``)."""
    return float(np.min(np.sin(angle) * CORNERS[:, 0] + np.cos(angle) * CORNERS[:, 1]))


def test_a_box_spinning_past_the_wrap_angle_keeps_its_contacts_exact():
    """A box spinning at 700 rad/s (no gravity) 1 cm above a floor at its lowest: its angle
    passes 1e3 rad and is wrapped; over 1120 rad the angle stays within 1e-10 rad of w t (mod
    2 pi; measured 1.6e-11), the gap to the floor reported by the contact finder within 1e-10 m
    of the exact lowest corner (measured 3.2e-12), no impact is found (the corner comes within
    1 cm every 2.2 ms) and nothing else moves."""
    w, dt = 700.0, 2e-3
    y0 = math.hypot(0.2, 0.1) + 0.01
    box = {"name": "box", "shape": BOX, "density": 1000.0, "position": [0.0, y0],
           "angular_velocity": w}  # fmt: skip
    scene = runtime.scene_from_dict({"scene": {"gravity": [0.0, 0.0]}, "body": [FLOOR, box]})
    run = runtime.simulate(scene, duration=1.6, dt=dt)
    angle = run.poses[:, 1, 2]
    assert np.max(np.abs(angle)) <= settings.ANGLE_WRAP + w * dt
    assert np.any(run.t * w > settings.ANGLE_WRAP)  # it did pass the wrap angle
    error = np.remainder(angle - w * run.t + math.pi, 2 * math.pi) - math.pi
    assert np.max(np.abs(error)) <= 1e-10
    for k in range(0, len(run.t), 5):
        found = scene.contacts(run.poses[k], tolerance=0.2)
        exact = y0 + _lowest_corner(w * run.t[k])
        assert abs(float(np.min(found.gap)) - exact) <= 1e-10, run.t[k]
    assert run.impact_times.size == 0
    assert np.all(run.poses[:, 1, :2] == [0.0, y0]) and np.all(run.velocities[:, 1, 2] == w)


def _reduced(angle: float) -> float:
    """``angle`` mod 2 pi in (-pi, pi], to the last bit (mpmath, 50 digits)."""
    mpmath.mp.dps = 50
    x = mpmath.mpf(angle)
    return float(x - 2 * mpmath.pi * mpmath.nint(x / (2 * mpmath.pi)))


@pytest.mark.parametrize("kind", ["box", "disc"])
def test_a_scene_file_angle_of_1e12_rests_on_the_floor_without_penetration(tmp_path, kind):
    """A box (on a corner, so it tips over and lands on its side) and a disc at angle 1e12 rad,
    placed touching the floor at that angle: the run reports no penetration beyond what a
    located impact leaves (Run.min_gap and the sampled overlap of tests/strategies.py below
    1e-10 m; measured 1.7e-12 m after the box lands; unreduced, 4.7e-6 m), and it is the run
    of the same scene at 1e12 mod 2 pi = -0.6576 rad to 1e-12 (the loader reduces; 1 ulp)."""
    reduced = _reduced(1e12)
    shape = SHAPE_TOML[kind]
    y = 0.1 if kind == "disc" else -_lowest_corner(reduced)
    runs = []
    for angle in (1e12, reduced):
        path = tmp_path / f"{kind}-{angle!r}.toml"
        path.write_text(
            "[simulation]\nduration = 0.5\ndt = 1e-3\n\n"
            '[[body]]\nname = "floor"\nfixed = true\n'
            'shape = { type = "wall", start = [-5.0, 0.0], end = [5.0, 0.0] }\n\n'
            f'[[body]]\nname = "{kind}"\nshape = {shape}\ndensity = 1000.0\n'
            f"position = [0.0, {y!r}]\nangle = {angle!r}\n"
        )
        scene = runtime.load_scene(path)
        assert scene.poses()[1, 2] == pytest.approx(reduced, abs=4e-16)
        runs.append((scene, runtime.simulate(scene)))
    (scene, run), (_, reference) = runs
    assert run.max_penetration <= 1e-10
    depth, _, what = strategies.deepest_penetration(scene, run.poses, 1e-10)
    assert depth <= 1e-10, what
    np.testing.assert_allclose(run.poses, reference.poses, rtol=0, atol=1e-12)
    if kind == "box":  # it tipped over onto its long side
        assert run.impact_times.size > 0
        assert abs(np.sin(2 * run.poses[-1, 1, 2])) <= 1e-6 and run.poses[-1, 1, 1] == (
            pytest.approx(0.1, abs=1e-9)
        )
