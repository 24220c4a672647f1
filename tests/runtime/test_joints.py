"""Joints (issue #16) against closed forms and conservation laws.

* a rod on a pin: the physical pendulum about the pivot, I_p = m (L^2 + h^2)/12 + m (L/2)^2,
  theta'' = -(m g L/2) cos(theta) / I_p, large amplitude (released horizontal), integrated here
  by solve_ivp (DOP853, rtol 1e-12) apart from the engine; and the pin's drift;
* a double pendulum of two discs on distance joints: energy (no dissipation; joints do no work);
  nothing but the exact b term holds a joint (no projection, no stabilisation unless asked);
* a bob on a distance joint striking a wall 30 degrees past the bottom (contact and joint in one
  island): one degree of freedom, so the tangential speed reverses with the restitution e and the
  bob rises back to y = -L cos(30 deg) (1 - e^2); the rod's length holds through the impact.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from runtime.io.scene_file import scene_from_dict
from runtime.solve.forces import Stabilisation
from runtime.step.simulation import simulate

G = 9.81


def _rod_scene(length: float, height: float, mass: float) -> dict:
    """A rod lying along +x from a pin at the origin (its left end), released at rest."""
    return {
        "scene": {"gravity": [0.0, -G]},
        "simulation": {"duration": 10.0, "dt": 1e-3, "method": "rk4"},
        "body": [
            {
                "name": "rod",
                "shape": {"type": "rounded_rect", "width": length, "height": height,
                          "corner_radius": 0.0},
                "mass": mass,
                "position": [length / 2, 0.0],
            }
        ],
        "joint": [
            {"type": "pin", "body1": "rod", "body2": "world", "anchor1": [-length / 2, 0.0],
             "anchor2": [0.0, 0.0]}
        ],
    }  # fmt: skip


def test_rod_on_a_pin_is_the_physical_pendulum_about_the_pivot():
    length, height, mass = 1.0, 0.05, 2.0
    run = simulate(scene_from_dict(_rod_scene(length, height, mass)))
    pivot_inertia = mass * (length**2 + height**2) / 12 + mass * (length / 2) ** 2
    torque = mass * G * length / 2

    def pendulum(_t, y):
        return [y[1], -torque * math.cos(y[0]) / pivot_inertia]

    exact = solve_ivp(pendulum, (0.0, 10.0), [0.0, 0.0], method="DOP853", rtol=1e-12,
                      atol=1e-14, dense_output=True)  # fmt: skip
    theta = run.poses[:, 0, 2]
    error = np.max(np.abs(np.unwrap(theta) - exact.sol(run.t)[0]))
    assert error <= 1e-6, error
    assert np.min(np.unwrap(theta)) < -3.0  # it swings through the full half turn
    x, y = run.poses[:, 0, 0], run.poses[:, 0, 1]
    drift = np.hypot(x - 0.5 * length * np.cos(theta), y - 0.5 * length * np.sin(theta))
    assert np.max(drift) < 1e-9, np.max(drift)
    energy = run.energy - run.energy[0]
    assert np.max(np.abs(energy)) < 1e-8 * mass * G * length, np.max(np.abs(energy))


def _disc(name: str, position, mass: float = 1.0, radius: float = 0.1, **more) -> dict:
    return {"name": name, "shape": {"type": "disc", "radius": radius}, "mass": mass,
            "position": list(position), **more}  # fmt: skip


def _double_pendulum(dt: float) -> tuple[float, float, np.ndarray]:
    """Energy drift (relative to m g times the largest drop), largest rod-length error (m) and
    the poses of the double pendulum released horizontal, 10 s of RK4 at ``dt``."""
    scene = scene_from_dict(
        {
            "scene": {"gravity": [0.0, -G]},
            "simulation": {"duration": 10.0, "dt": dt},
            "body": [_disc("a", (1.0, 0.0)), _disc("b", (2.0, 0.0), mass=0.5)],
            "joint": [
                {"type": "distance", "body1": "a", "body2": "world", "anchor2": [0.0, 0.0]},
                {"type": "distance", "body1": "b", "body2": "a"},
            ],
        }
    )
    run = simulate(scene)
    q = run.poses
    r1 = np.hypot(q[:, 0, 0], q[:, 0, 1])
    r2 = np.hypot(q[:, 1, 0] - q[:, 0, 0], q[:, 1, 1] - q[:, 0, 1])
    scale = 1.5 * G * 2.0
    drift = np.max(np.abs(run.energy - run.energy[0])) / scale
    return drift, max(np.max(np.abs(r1 - 1.0)), np.max(np.abs(r2 - 1.0))), q


def test_double_pendulum_on_distance_joints_conserves_energy():
    """Released horizontal, it turns chaotic (the outer bob at up to 8.9 m/s). Joints do no
    work, so the energy drifts only by RK4's truncation error, O(h^4): over 10 s, measured
    3.4e-7 at dt = 2 ms, 2.1e-8 at 1 ms, 1.3e-9 at 0.5 ms, 8.3e-11 at 0.25 ms (order 4.00 at
    each halving; the rod lengths 5.8e-7, 3.7e-8, 2.3e-9, 1.4e-10 m, order 4 too). So the
    issue's 1e-8 holds from dt = 0.5 ms (at 1 ms it is 2.1x over), and is asserted there; the
    order between 1 and 0.5 ms is the second assertion: work done by a joint (a wrong bias, a
    force with a component along the motion) would drift at a rate that does not fall as h^4."""
    drift, lengths, q = _double_pendulum(5e-4)
    assert drift < 1e-8, drift
    assert lengths < 1e-8, lengths
    assert np.ptp(q[:, 1, 1]) > 2.0  # it moved: the outer bob fell and swung
    coarse, coarse_lengths, _ = _double_pendulum(1e-3)
    assert 3.7 < math.log2(coarse / drift) < 4.3, (coarse, drift)
    assert 3.7 < math.log2(coarse_lengths / lengths) < 4.3, (coarse_lengths, lengths)


@pytest.mark.parametrize("restitution", [1.0, 0.5])
def test_pendulum_bob_bounces_off_a_wall_with_its_restitution(restitution):
    length, radius, past = 1.0, 0.1, math.radians(30.0)
    wall_x = -length * math.sin(past) - radius
    scene = scene_from_dict(
        {
            "scene": {"gravity": [0.0, -G]},
            "simulation": {"duration": 1.6, "dt": 1e-3},
            "body": [
                {"name": "wall", "fixed": True,
                 "shape": {"type": "wall", "start": [wall_x, 0.5], "end": [wall_x, -1.5]}},
                _disc("bob", (length, 0.0), restitution=restitution),
            ],
            "joint": [{"type": "distance", "body1": "bob", "body2": "world",
                       "anchor2": [0.0, 0.0]}],
        }
    )  # fmt: skip
    run = simulate(scene)
    assert len(run.impact_times) == 1, run.impact_times
    q, v = run.poses[:, 1], run.velocities[:, 1]
    radial = np.hypot(q[:, 0], q[:, 1])
    assert np.max(np.abs(radial - length)) < 1e-9, np.max(np.abs(radial - length))
    radial_speed = (q[:, 0] * v[:, 0] + q[:, 1] * v[:, 1]) / radial
    assert np.max(np.abs(radial_speed)) < 1e-9
    after = run.t > run.impact_times[0]
    top = np.max(q[after, 1])
    expected = -length * math.cos(past) * (1.0 - restitution**2)
    if restitution == 1.0:
        expected = 0.0  # back to where it was released; it reaches it at t = 2 t_hit
    assert top == pytest.approx(expected, abs=1e-6), (top, expected)


def test_newtons_cradle_on_distance_joints_passes_the_swing_to_the_last_disc():
    """Five touching discs of restitution 1, each hung on a distance joint; the first released
    from 20 degrees meets the row at the bottom: the last leaves with its speed and rises to
    the same height, the others stay (joints and contacts in one island at the impact)."""
    radius, length, lift = 0.1, 1.0, math.radians(20.0)
    bodies, joints = [], []
    for k in range(5):
        x = 2 * radius * k
        bodies.append(_disc(f"b{k}", (x, -length), radius=radius, restitution=1.0))
        joints.append({"type": "distance", "body1": f"b{k}", "body2": "world",
                       "anchor2": [x, 0.0]})  # fmt: skip
    bodies[0]["position"] = [-length * math.sin(lift), -length * math.cos(lift)]
    run = simulate(
        scene_from_dict(
            {
                "scene": {"gravity": [0.0, -G]},
                "simulation": {"duration": 1.2, "dt": 1e-3},
                "body": bodies,
                "joint": joints,
            }  # fmt: skip
        )
    )
    assert len(run.impact_times) == 1
    after = run.t > run.impact_times[0]
    assert np.max(np.abs(run.velocities[after, :4])) < 1e-9
    rest = np.array([[2 * radius * k, -length] for k in range(4)])  # each at its bottom
    assert np.max(np.abs(run.poses[after, :4, :2] - rest)) < 1e-9
    top = np.max(run.poses[after, 4, 1])
    assert top == pytest.approx(-length * math.cos(lift), abs=1e-6)
    assert np.ptp(run.energy) < 1e-9 * G * length


def test_joint_drift_is_corrected_only_with_stabilisation():
    """A pin whose anchors start 1e-4 m apart (moved after loading): without stabilisation the
    exact b term keeps d'' = 0, so the offset stays; with Baumgarte stabilisation (time scale
    T = 0.02 s, critically damped) it decays as (1 + t/T) e^(-t/T)."""
    scene = scene_from_dict(_rod_scene(1.0, 0.05, 2.0))
    rod = scene.bodies[0]
    rod.position = (rod.position[0], rod.position[1] + 1e-4)
    scale = 0.02

    def offset(run):
        q = run.poses[:, 0]
        return np.hypot(q[:, 0] - 0.5 * np.cos(q[:, 2]), q[:, 1] - 0.5 * np.sin(q[:, 2]))

    free = offset(simulate(scene, duration=0.2))
    assert np.max(np.abs(free - 1e-4)) < 1e-9, np.max(np.abs(free - 1e-4))
    run = simulate(scene, duration=0.2, stabilisation=Stabilisation.critically_damped(scale))
    decay = 1e-4 * (1 + run.t / scale) * np.exp(-run.t / scale)
    assert np.max(np.abs(offset(run) - decay)) < 1e-9, np.max(np.abs(offset(run) - decay))


def test_rod_on_a_pin_resting_on_a_support_carries_the_static_load():
    """A horizontal rod pinned at its left end rests on a fixed disc at x_s: statics about the
    pin gives the support force N = m g (L/2) / x_s, and the rod stays at rest."""
    length, height, mass, support = 1.0, 0.05, 2.0, 0.8
    data = _rod_scene(length, height, mass)
    data["simulation"]["duration"] = 0.5
    data["body"].insert(0, {"name": "support", "fixed": True,
                            "shape": {"type": "disc", "radius": 0.05},
                            "position": [support, -height / 2 - 0.05]})  # fmt: skip
    run = simulate(scene_from_dict(data))
    assert np.max(np.abs(run.poses[:, 1] - run.poses[0, 1])) < 1e-12
    expected = mass * G * (length / 2) / support
    for contacts, forces in zip(run.contacts, run.contact_forces, strict=True):
        assert len(contacts) == 1
        assert forces[0] == pytest.approx(expected, rel=1e-9)


def test_pin_between_two_moving_bodies_conserves_energy():
    """A rod on a pin to the world with a disc pinned 0.5 m beyond its free end (0.2 m from
    the disc's centre, so the two never touch): a double physical pendulum, no dissipation."""
    data = _rod_scene(1.0, 0.05, 2.0)
    data["simulation"]["duration"] = 5.0
    data["body"].append(_disc("disc", (1.7, 0.0), radius=0.1, mass=0.7))
    data["joint"].append({"type": "pin", "body1": "disc", "body2": "rod",
                          "anchor1": [-0.2, 0.0], "anchor2": [1.0, 0.0]})  # fmt: skip
    run = simulate(scene_from_dict(data))
    rod, disc = run.poses[:, 0], run.poses[:, 1]
    end = rod[:, :2] + 1.0 * np.column_stack([np.cos(rod[:, 2]), np.sin(rod[:, 2])])
    anchor = disc[:, :2] - 0.2 * np.column_stack([np.cos(disc[:, 2]), np.sin(disc[:, 2])])
    # RK4 at 1 ms, no stabilisation, the disc spinning at up to 36 rad/s: the pin drifts
    # 1.15e-6 m and the energy 1.1e-5 J in 5 s (7.2e-8 m at 0.5 ms, 4.5e-9 m at 0.25 ms: h^4)
    assert np.max(np.hypot(*(end - anchor).T)) < 2e-6
    assert np.ptp(disc[:, 2]) > 0.5  # the disc turns about its pin
    assert run.impact_times.size == 0
    assert np.max(np.abs(run.energy - run.energy[0])) < 1e-6 * 2.7 * G * 2.0


def test_a_press_is_undone_at_the_joints_by_the_least_energy_impulse():
    """LinkedForces.hold_joints after a press (a velocity change dv on a jointed body): the
    joints' d' is back to what it was before the press, and the correction is W J^T lambda
    (the least kinetic energy change, checked against lstsq here); without a press, nothing."""
    from runtime.collide.contact_set import Contacts
    from runtime.solve.linked_forces import LinkedForces
    from runtime.solve.rows import Rows
    from runtime.step.classify import Frame

    data = _rod_scene(1.0, 0.05, 2.0)
    data["body"].append(_disc("disc", (1.7, 0.0), radius=0.1, mass=0.7))
    data["joint"].append({"type": "pin", "body1": "disc", "body2": "rod",
                          "anchor1": [-0.2, 0.0], "anchor2": [1.0, 0.0]})  # fmt: skip
    scene = scene_from_dict(data)
    links = LinkedForces(scene)
    q = scene.poses() + np.array([[0.0, 0.0, 0.3], [0.0, 0.0, -0.2]])  # any pose: J at q
    v = np.array([[0.1, -0.2, 0.4], [0.3, 0.1, -1.0]])
    empty = Rows(*(np.zeros(0),) * 2, np.zeros((0, 6)), np.zeros(0), *(np.zeros(0, int),) * 2)

    def frame(velocities):
        return Frame(Contacts.empty(), [], empty, np.zeros(0, int), velocities, np.zeros(2),
                     np.zeros(0))  # fmt: skip

    before = frame(v)
    assert links.hold_joints(q, before, (before, "solution"), None)[1] == "solution"
    pressed = frame(v + np.array([[0.0, 0.0, 0.0], [0.05, -0.02, 0.3]]))
    held, solution = links.hold_joints(q, before, (pressed, None), lambda f: "solved")
    assert solution == "solved"
    rows = links.joints.rows(q, v)
    jac = rows.dense_jacobian(2)
    assert np.allclose(jac @ held.velocities.ravel(), jac @ v.ravel(), atol=1e-14, rtol=0)
    weight = scene.inverse_masses.ravel()
    dv = held.velocities.ravel() - pressed.velocities.ravel()
    target = jac @ (v - pressed.velocities).ravel()
    lam = np.linalg.lstsq((jac * weight) @ jac.T, target, rcond=None)[0]
    assert np.allclose(dv, weight * (jac.T @ lam), atol=1e-14, rtol=0)


def test_an_impulse_on_a_pinned_rod_turns_it_about_the_pin():
    """World.apply_impulse at the centre of a rod pinned at its end: angular momentum about
    the pin gives w = P (L/2) / I_p and v = w L/2 (the pin's reaction impulse included)."""
    from runtime.step.world import World

    length, height, mass, push = 1.0, 0.05, 2.0, 0.3
    data = _rod_scene(length, height, mass)
    data["scene"]["gravity"] = [0.0, 0.0]
    world = World(scene_from_dict(data))
    world.apply_impulse("rod", [0.0, push])
    pivot_inertia = mass * (length**2 + height**2) / 12 + mass * (length / 2) ** 2
    w = push * (length / 2) / pivot_inertia
    assert world.velocities[0] == pytest.approx([0.0, w * length / 2, w], rel=1e-12, abs=1e-15)
    for _ in range(100):
        world.step(1e-3)
    assert world.poses[0, 2] == pytest.approx(0.1 * w, rel=1e-9)


def test_a_joint_to_a_fixed_body_is_one_to_the_world_at_its_anchor():
    """Anchors are in each body's shape coordinates: a joint to a fixed body turned by 90
    degrees at (0, 2) with anchor [1, 0] is a joint to the world at (0, 3); written the other
    way round (the fixed body first) it is the same joint; a moving body's anchor is moved to
    its centre-of-mass coordinates (a half-disc's centroid is not its shape origin)."""
    bob = {"name": "bob", "shape": {"type": "half_disc", "radius": 0.3}, "mass": 1.0,
           "position": [0.0, 0.0]}  # fmt: skip
    ceiling = {"name": "ceiling", "fixed": True, "position": [0.0, 2.0], "angle": math.pi / 2,
               "shape": {"type": "disc", "radius": 0.05}}  # fmt: skip
    joint = {"type": "distance", "body1": "bob", "body2": "ceiling", "anchor1": [0.0, 0.0],
             "anchor2": [1.0, 0.0]}  # fmt: skip
    flipped = {**joint, "body1": "ceiling", "body2": "bob", "anchor1": [1.0, 0.0],
               "anchor2": [0.0, 0.0]}  # fmt: skip
    made = [scene_from_dict({"body": [ceiling, bob], "joint": [j]}) for j in (joint, flipped)]
    assert made[0].joints == made[1].joints
    (j,) = made[0].joints
    centroid = 4 * 0.3 / (3 * math.pi)  # of the half-disc, above its arc's centre
    assert (j.body1, j.body2) == (1, -1)
    assert j.anchor1 == pytest.approx((0.0, -centroid), abs=1e-15)
    assert j.anchor2 == pytest.approx((0.0, 3.0), abs=1e-15)
    assert j.length == pytest.approx(3.0, rel=1e-15)


def _chain_of_two_rods(joint: str = "joint") -> dict:
    """Two rods 1 m x 0.1 m, overlapping by 0.1 m at the pin that links them (at x = 1), the
    first pinned to the world at its left end: a double physical pendulum released level."""
    rod = {"type": "rounded_rect", "width": 1.0, "height": 0.1, "corner_radius": 0.0}
    link = {"body1": "b", "body2": "a", "anchor1": [-0.45, 0.0], "anchor2": [0.45, 0.0]}
    data = {
        "scene": {"gravity": [0.0, -G]},
        "simulation": {"duration": 3.0, "dt": 1e-3, "method": "rk4"},
        "body": [
            {"name": "a", "shape": rod, "mass": 1.0, "position": [0.5, 0.0]},
            {"name": "b", "shape": rod, "mass": 1.0, "position": [1.4, 0.0]},
        ],
        "joint": [{"type": "pin", "body1": "a", "body2": "world", "anchor1": [-0.5, 0.0],
                   "anchor2": [0.0, 0.0]}],
    }  # fmt: skip
    if joint == "joint":
        data["joint"].append({"type": "pin", **link})
    else:
        data["spring"] = [{**link, "rest_length": 0.0, "stiffness": 100.0}]
    return data


def test_bodies_a_joint_links_never_touch_each_other():
    """Rods pinned where they overlap (a chain's links, Box2D's default for joints): loaded,
    no contact between them at any record, and the double pendulum conserves energy (1e-8 of
    m g L over 3 s) with both pins held to 1e-8 m. A spring is no joint: the same overlap
    linked by a spring is refused at load, naming the two bodies."""
    scene = scene_from_dict(_chain_of_two_rods())
    assert scene.joined_pairs == ((0, 1),)
    assert len(scene.contacts()) == 0
    run = simulate(scene)
    assert all(len(c) == 0 for c in run.contacts)
    energy = run.energy - run.energy[0]
    assert np.max(np.abs(energy)) < 1e-8 * 2.0 * G, np.max(np.abs(energy))
    q = run.poses
    ends_a = q[:, 0, :2] + 0.45 * np.column_stack([np.cos(q[:, 0, 2]), np.sin(q[:, 0, 2])])
    ends_b = q[:, 1, :2] - 0.45 * np.column_stack([np.cos(q[:, 1, 2]), np.sin(q[:, 1, 2])])
    assert np.max(np.hypot(*(ends_a - ends_b).T)) < 1e-8
    root = q[:, 0, :2] - 0.5 * np.column_stack([np.cos(q[:, 0, 2]), np.sin(q[:, 0, 2])])
    assert np.max(np.hypot(*root.T)) < 1e-8
    with pytest.raises(ValueError, match="overlap"):
        scene_from_dict(_chain_of_two_rods("spring"))


def test_run_records_the_rod_tension_of_a_pendulum():
    """A bob on a distance joint (anchored at its centre: a point-mass pendulum), released
    level: at every record the rod's force is the radial equation's, f = -m |v|^2 / L - m g.n
    (n from the pivot to the bob), and at the lowest point T = -f = m g + m v^2 / L, which is
    3 m g there (v^2 = 2 g L from the energy)."""
    mass, length = 0.7, 1.5
    run = simulate(scene_from_dict({
        "scene": {"gravity": [0.0, -G]},
        "simulation": {"duration": 2.0, "dt": 1e-3},
        "body": [_disc("bob", (length, 0.0), mass=mass)],
        "joint": [{"type": "distance", "body1": "bob", "body2": "world", "anchor2": [0.0, 0.0]}],
    }))  # fmt: skip
    assert run.joint_names == ["joint #1"] and run.joint_forces.shape == (len(run.t), 1)
    position, velocity = run.poses[:, 0, :2], run.velocities[:, 0, :2]
    n = position / np.hypot(*position.T)[:, None]
    speed2 = np.sum(velocity**2, axis=1)
    radial = -mass * speed2 / length - mass * (n @ np.array([0.0, -G]))
    assert np.allclose(run.joint_forces[:, 0], radial, rtol=0, atol=1e-9 * mass * G)
    low = int(np.argmin(position[:, 1]))
    assert 0 < low < len(run.t) - 1  # it swung through the bottom
    tension = -run.joint_forces[low, 0]
    assert tension == pytest.approx(mass * G + mass * speed2[low] / length, rel=1e-6)
    assert tension == pytest.approx(3 * mass * G, rel=1e-5)


def test_a_run_without_joints_records_no_joint_forces():
    run = simulate(scene_from_dict({
        "scene": {"gravity": [0.0, -G]},
        "simulation": {"duration": 0.01, "dt": 1e-3},
        "body": [_disc("d", (0.0, 0.0))],
    }))  # fmt: skip
    assert run.joint_names == [] and run.joint_forces.shape == (len(run.t), 0)
