"""The engine against exact or high-precision references (issue: runtime, "Done means")."""

import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import runtime
from runtime.step.stepper import Stepper

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "scenes"
G = 9.81


def _pendulum_reference(phi0: float, length: float, times: np.ndarray) -> np.ndarray:
    """phi(t) of a frictionless point pendulum, solve_ivp at rtol 1e-12."""
    sol = solve_ivp(
        lambda _t, y: [y[1], -G / length * math.sin(y[0])],
        (0.0, float(times[-1])),
        [phi0, 0.0],
        method="DOP853",
        rtol=1e-12,
        atol=1e-14,
        t_eval=times,
    )
    return sol.y[0]


def test_disc_in_bowl_follows_the_pendulum_and_its_contact_force():
    """Centre on the exact pendulum of length R - r to 1e-6 rad over 10 s (RK4, dt 1e-3), and the
    contact force equals m (g cos phi + v^2 / (R - r)) to 1e-8 relative at every sampled step."""
    scene = runtime.load_scene(SCENES / "disc_in_bowl.toml")
    run = runtime.simulate(scene, duration=10.0, dt=1e-3, method="rk4", record_every=50)
    disc = scene.index("disc")
    mass = scene.bodies[disc].mass
    poses = np.array(run.poses)[:, disc]
    vel = np.array(run.velocities)[:, disc]
    phi = np.arctan2(poses[:, 0], -poses[:, 1])
    reference = _pendulum_reference(0.3, 0.9, np.array(run.t))
    assert np.max(np.abs(phi - reference)) < 1e-6
    speed2 = vel[:, 0] ** 2 + vel[:, 1] ** 2
    expected = mass * (G * np.cos(phi) + speed2 / 0.9)
    forces = np.array([f[0] for f in run.contact_forces])
    assert np.max(np.abs(forces / expected - 1.0)) < 1e-8
    assert np.max(np.abs(vel[:, 2])) == 0.0  # frictionless: no torque about the disc's centre


@pytest.mark.parametrize("dt, tolerance", [(0.02, 1e-8), (0.05, 1e-6), (0.1, 1e-5)])
def test_large_rk4_steps_keep_the_bowl_contact_resting(dt, tolerance):
    """At steps of 1/100 to 1/20 of the period the integrator carries the disc up to 3e-5 m off
    the bowl per step; the contact stays resting (no impacts) and every step reports the force
    m (g cos phi + v^2 / (R - r)) of its state (measured: 2.9e-9, 1.2e-7, 2.2e-6 relative)."""
    scene = runtime.load_scene(SCENES / "disc_in_bowl.toml")
    run = runtime.simulate(scene, duration=2.0, dt=dt, method="rk4")
    disc = scene.index("disc")
    poses, vel = np.array(run.poses)[:, disc], np.array(run.velocities)[:, disc]
    phi = np.arctan2(poses[:, 0], -poses[:, 1])
    expected = scene.bodies[disc].mass * (G * np.cos(phi) + (vel[:, :2] ** 2).sum(1) / 0.9)
    assert run.impact_times.size == 0 and all(len(f) == 1 for f in run.contact_forces)
    forces = np.array([f[0] for f in run.contact_forces])
    assert np.max(np.abs(forces / expected - 1.0)) < tolerance


def test_disc_on_incline_slides_with_g_sin30():
    scene = runtime.load_scene(SCENES / "disc_on_incline.toml")
    run = runtime.simulate(scene, duration=0.3, dt=1e-3, method="rk4", record_every=10)
    disc = scene.index("disc")
    vel = np.array(run.velocities)[:, disc]
    t = np.array(run.t)
    along = np.array([math.cos(math.radians(30)), math.sin(math.radians(30))])
    speed_down = -(vel[:, :2] @ along)
    assert np.max(np.abs(speed_down - G * 0.5 * t)) < 1e-10 * G
    assert np.max(np.abs(vel[:, :2] @ np.array([-along[1], along[0]]))) < 1e-12
    assert np.max(np.abs(vel[:, 2])) == 0.0
    mass = scene.bodies[disc].mass
    forces = np.array([f[0] for f in run.contact_forces])
    assert np.max(np.abs(forces / (mass * G * math.cos(math.radians(30))) - 1.0)) < 1e-10


def test_disc_leaves_the_cylinder_at_the_predicted_angle():
    """cos phi = (2/3) cos phi0 + v0^2 / (3 g (R + r)) with phi0 = 0, v0 = 0.1, R + r = 0.6:
    where the unconstrained d'' turns positive, and where the disc leaves. The contact only
    pushes (f >= 0) all the way: a one-contact island whose warm-started guess kept the held
    contact with f = -b/A < 0 glued the disc ~20 steps past the angle, pulling up to 49 N."""
    scene = runtime.load_scene(SCENES / "disc_over_cylinder.toml")
    run = runtime.simulate(scene, duration=1.5, dt=1e-3, method="rk4")
    disc = scene.index("disc")
    weight = scene.bodies[disc].mass * G
    predicted = math.acos(2.0 / 3.0 + 0.1**2 / (3 * G * 0.6))
    assert min(float(np.min(f, initial=0.0)) for f in run.contact_forces) >= -1e-9 * weight
    free_flight = [i for i, c in enumerate(run.contacts) if not len(c)]
    left = math.atan2(*run.poses[free_flight[0], disc, :2])  # the first sample off the cylinder
    assert 0.0 < left - predicted < 0.015  # under 5 steps of its rotation (3.3 rad/s) later
    stepper = Stepper(scene)
    angles, free = [], []
    for poses, vel, contacts in zip(run.poses, run.velocities, run.contacts, strict=True):
        if not len(contacts):
            break
        angles.append(math.atan2(poses[disc, 0], poses[disc, 1]))
        free.append(stepper.contact_forces(contacts, poses, vel).free_rates[0])
    free = np.array(free)
    k = int(np.argmax(free > 0))  # first sample where the unconstrained d'' is positive
    assert k > 0
    leave = angles[k - 1] + (angles[k] - angles[k - 1]) * free[k - 1] / (free[k - 1] - free[k])
    assert abs(leave - predicted) < 1e-5


def test_plank_on_cylinder_conserves_energy_and_lifts_off():
    scene = runtime.load_scene(SCENES / "plank_on_cylinder.toml")
    run = runtime.simulate(scene, duration=3.0, dt=1e-3, method="rk4", record_every=10)
    energy = np.array(run.energy)
    assert np.max(np.abs(energy - energy[0])) < 1e-6 * abs(energy[0])
    in_contact = [bool(c) for c in run.contacts]
    lift = run.t[in_contact.index(False)]
    assert 0.9 < lift < 1.02


def test_scene_of_discs_and_walls_imports_no_vertex_kernel():
    """Only the kernels of the cases the scene can produce are imported on the general path
    (rk45; the compiled fixed-step engine is one program over the four cases,
    runtime/solve/kernel_set.py)."""
    code = (
        "import sys, runtime;"
        "s = runtime.load_scene('scenes/disc_pile.toml');"
        "runtime.simulate(s, duration=0.01, dt=1e-3, method='rk45');"
        "print(sorted(m for m in sys.modules if m.startswith('generated.')))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True, check=True
    )
    loaded = eval(out.stdout.strip())  # a printed list of module names
    assert loaded and all("vertex" not in m for m in loaded), loaded


@pytest.mark.parametrize("method", ["euler", "midpoint", "rk4", "rk45"])
def test_every_method_keeps_the_disc_on_the_incline(method):
    scene = runtime.load_scene(SCENES / "disc_on_incline.toml")
    run = runtime.simulate(scene, duration=0.1, dt=1e-3, method=method)
    assert run.max_penetration < 1e-9
