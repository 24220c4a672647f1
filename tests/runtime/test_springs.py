"""Springs, damping and mutual gravitation (issue #16) against closed forms, and the promise that
a scene without them runs exactly as before (model only what a scene needs).

* a mass on a spring: x(t) = L + x0 cos(w t), w = sqrt(k/m); with damping c:
  x0 e^(-g t) (cos(w_d t) + g/w_d sin(w_d t)), g = c/(2m), w_d = sqrt(w^2 - g^2);
* linear and angular damping: v(t) = v0 e^(-k t), w(t) = w0 e^(-k t);
* two bodies in a mutual circular orbit: period 2 pi sqrt(r^3 / (G (m1 + m2))), radius, energy
  (with -G m1 m2 / r) and angular momentum kept;
* two bodies on a spring spinning under gravity: energy (with k (|s| - L)^2 / 2) kept;
* a scene with the keys at zero (damping 0, mutual_gravity 0) steps bit for bit as without them,
  and a plain scene imports none of the link modules or joint kernels.
"""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from runtime.io.scene_file import scene_from_dict
from runtime.step.simulation import simulate

ROOT = Path(__file__).resolve().parents[2]


def _disc(name: str, position, mass: float = 1.0, radius: float = 0.1, **more) -> dict:
    return {"name": name, "shape": {"type": "disc", "radius": radius}, "mass": mass,
            "position": list(position), **more}  # fmt: skip


def _scene(bodies, duration: float, dt: float = 1e-3, gravity=(0.0, 0.0), **tables) -> dict:
    return {"scene": {"gravity": list(gravity), **tables.pop("scene", {})},
            "simulation": {"duration": duration, "dt": dt}, "body": bodies, **tables}  # fmt: skip


@pytest.mark.parametrize("damping", [0.0, 0.8])
def test_mass_on_a_spring_follows_the_closed_form(damping):
    mass, stiffness, rest, x0 = 2.0, 50.0, 1.0, 0.2
    spring = {"body1": "m", "body2": "world", "anchor2": [0.0, 0.0], "rest_length": rest,
              "stiffness": stiffness, "damping": damping}  # fmt: skip
    run = simulate(scene_from_dict(
        _scene([_disc("m", (rest + x0, 0.0), mass=mass)], 5.0, spring=[spring])
    ))  # fmt: skip
    w = math.sqrt(stiffness / mass)
    g = damping / (2 * mass)
    wd = math.sqrt(w * w - g * g)
    t = run.t
    exact = rest + x0 * np.exp(-g * t) * (np.cos(wd * t) + g / wd * np.sin(wd * t))
    error = np.max(np.abs(run.poses[:, 0, 0] - exact))
    assert error < 1e-8, error
    assert np.max(np.abs(run.poses[:, 0, 1:])) == 0.0  # along the spring only
    if damping == 0.0:
        assert np.ptp(run.energy) < 1e-9 * 0.5 * stiffness * x0**2, np.ptp(run.energy)
    else:  # the energy goes down, to the closed form's
        v = np.gradient(exact, t)
        closed = 0.5 * mass * v**2 + 0.5 * stiffness * (exact - rest) ** 2
        assert np.all(np.diff(run.energy) <= 1e-12)
        assert run.energy[-1] == pytest.approx(closed[-1], rel=1e-3)


def test_linear_and_angular_damping_decay_exponentially():
    k_lin, k_ang = 0.7, 1.3
    body = _disc("d", (0.0, 0.0), velocity=[3.0, -1.0], angular_velocity=5.0,
                 linear_damping=k_lin, angular_damping=k_ang)  # fmt: skip
    run = simulate(scene_from_dict(_scene([body], 3.0)))
    v, t = run.velocities[:, 0], run.t
    for got, v0, k in ((v[:, 0], 3.0, k_lin), (v[:, 1], -1.0, k_lin), (v[:, 2], 5.0, k_ang)):
        exact = v0 * np.exp(-k * t)
        assert np.max(np.abs(got - exact)) < 1e-10 * abs(v0), np.max(np.abs(got - exact))
    x_exact = 3.0 / k_lin * (1.0 - np.exp(-k_lin * t))
    assert np.max(np.abs(run.poses[:, 0, 0] - x_exact)) < 1e-10


def test_two_bodies_in_a_mutual_circular_orbit():
    grav, m1, m2, r = 1.0, 3.0, 1.0, 2.0
    speed = math.sqrt(grav * (m1 + m2) / r)  # relative speed of a circular orbit
    period = 2 * math.pi * math.sqrt(r**3 / (grav * (m1 + m2)))
    a = _disc("a", (-r * m2 / (m1 + m2), 0.0), mass=m1, velocity=[0.0, -speed * m2 / (m1 + m2)])
    b = _disc("b", (r * m1 / (m1 + m2), 0.0), mass=m2, velocity=[0.0, speed * m1 / (m1 + m2)])
    run = simulate(
        scene_from_dict(_scene([a, b], period, dt=period / 4000, scene={"mutual_gravity": grav}))
    )
    q, v = run.poses, run.velocities
    separation = np.hypot(*(q[:, 1, :2] - q[:, 0, :2]).T)
    assert np.max(np.abs(separation - r)) < 1e-8 * r, np.max(np.abs(separation - r))
    assert np.allclose(q[-1, :, :2], q[0, :, :2], atol=1e-8 * r, rtol=0)  # back after a period
    phase = np.unwrap(np.arctan2(q[:, 1, 1] - q[:, 0, 1], q[:, 1, 0] - q[:, 0, 0]))
    assert phase[len(phase) // 2] == pytest.approx(math.pi, abs=1e-8)  # half a turn at T/2
    energy = -grav * m1 * m2 / (2 * r)  # kinetic + potential of a circular orbit
    assert np.max(np.abs(run.energy - energy)) < 1e-10 * abs(energy)
    mass = np.array([m1, m2])[None, :]
    spin = np.sum(mass * (q[:, :, 0] * v[:, :, 1] - q[:, :, 1] * v[:, :, 0]), axis=1)
    assert np.ptp(spin) < 1e-10 * abs(spin[0]), np.ptp(spin)


def test_spinning_dumbbell_on_a_spring_under_gravity_conserves_energy():
    spring = {"body1": "a", "body2": "b", "anchor1": [0.05, 0.0], "rest_length": 0.8,
              "stiffness": 40.0}  # fmt: skip
    a = _disc("a", (0.0, 0.0), velocity=[0.0, 2.0], angular_velocity=3.0)
    b = _disc("b", (1.0, 0.0), mass=0.5, velocity=[0.5, -1.0])
    run = simulate(scene_from_dict(_scene([a, b], 4.0, gravity=(0.0, -9.81), spring=[spring])))
    kinetic0 = 0.5 * (2.0**2 + 0.005 * 3.0**2) + 0.25 * 1.25
    drift = np.max(np.abs(run.energy - run.energy[0])) / kinetic0
    assert drift < 1e-8, drift
    assert np.ptp(np.hypot(*(run.poses[:, 1, :2] - run.poses[:, 0, :2]).T)) > 0.1  # it stretched


PLAIN = {
    "scene": {"gravity": [0.0, -9.81]},
    "simulation": {"duration": 0.6, "dt": 1e-3},
    "body": [
        {"name": "floor", "fixed": True,
         "shape": {"type": "wall", "start": [-2.0, 0.0], "end": [2.0, 0.0]}},
        _disc("ball", (0.0, 0.5), restitution=0.6, velocity=[0.3, 0.0], angular_velocity=1.0),
        {"name": "box", "shape": {"type": "rounded_rect", "width": 0.3, "height": 0.2,
                                  "corner_radius": 0.0},
         "density": 100.0, "position": [0.6, 0.3], "angle": 0.3},
    ],
}  # fmt: skip


def test_keys_at_zero_run_bit_for_bit_as_without_them():
    zero = {**PLAIN, "scene": {**PLAIN["scene"], "mutual_gravity": 0.0}}
    zero["body"] = [dict(b) for b in PLAIN["body"]]
    for body in zero["body"][1:]:
        body.update(linear_damping=0.0, angular_damping=0.0)
    scene = scene_from_dict(zero)
    assert not scene.linked
    with_keys, without = simulate(scene), simulate(scene_from_dict(PLAIN))
    assert len(with_keys.impact_times) >= 1  # the ball bounced, the box landed
    assert np.array_equal(with_keys.poses, without.poses)
    assert np.array_equal(with_keys.velocities, without.velocities)
    assert np.array_equal(with_keys.energy, without.energy)


def test_plain_scene_imports_no_link_module():
    code = (
        "import sys, json\n"
        "from runtime.io.scene_file import scene_from_dict\n"
        "from runtime.step.simulation import simulate\n"
        f"simulate(scene_from_dict({PLAIN!r}), duration=0.05)\n"
        "print(json.dumps(sorted(m for m in sys.modules if 'joint' in m or 'linked' in m\n"
        "                        or 'applied' in m)))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, check=True, timeout=600)  # fmt: skip
    assert out.stdout.strip() == "[]", out.stdout


def test_spring_carries_part_of_a_resting_discs_weight():
    """A disc resting on a floor, a stretched spring to a point above it: the floor carries
    N = m g - k (|s| - L) and the disc stays (the spring's force enters b at every stage)."""
    mass, stiffness, rest = 2.0, 30.0, 0.4
    spring = {"body1": "disc", "body2": "world", "anchor2": [0.0, 1.1], "rest_length": rest,
              "stiffness": stiffness}  # fmt: skip
    data = _scene([dict(PLAIN["body"][0]), _disc("disc", (0.0, 0.1), mass=mass)], 0.5,
                  gravity=(0.0, -9.81), spring=[spring])  # fmt: skip
    run = simulate(scene_from_dict(data))
    assert np.max(np.abs(run.poses[:, 1] - run.poses[0, 1])) < 1e-12
    expected = mass * 9.81 - stiffness * (1.0 - rest)
    assert expected > 0
    for forces in run.contact_forces:
        assert forces.shape == (1,) and forces[0] == pytest.approx(expected, rel=1e-12)


def test_ensembles_take_damping_and_refuse_links():
    """Copies of a damped disc each follow x(t) = v0 (1 - e^(-k t)) / k; copies of a scene with
    a spring are refused with one line (the links would need re-indexing per copy)."""
    import runtime

    damped = _disc("d", (0.0, 0.0), linear_damping=0.5)
    scene = scene_from_dict(_scene([damped], 0.1))
    speeds = np.array([[1.0, 0.0], [2.0, 0.0]])
    ensemble = runtime.simulate_ensemble(scene, {"d.velocity": speeds}, duration=0.1, dt=1e-3)
    exact = speeds[:, 0] * (1.0 - math.exp(-0.05)) / 0.5
    assert np.allclose(ensemble.poses[:, -1, 0, 0], exact, rtol=1e-12, atol=0)
    spring = {"body1": "d", "body2": "world", "rest_length": 0.0, "stiffness": 1.0}
    linked = scene_from_dict(_scene([damped], 0.1, spring=[spring]))
    with pytest.raises(ValueError, match=r"copies of a scene with joints, springs or mutual"):
        runtime.simulate_ensemble(linked, {"d.velocity": speeds}, duration=0.1, dt=1e-3)
