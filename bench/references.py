"""Exact and high-precision references for the work-precision report, and the errors against them.

Both engines (ours in runtime/, pymunk in bench/peers.py) are reduced to the same `Trajectory`
of the one moving body, and every error is measured here by the same code, so a difference in
the report is a difference of the engines and not of the bookkeeping.

The references are built from the scene files (radii, initial state, gravity read from the
`Scene`), so a tweak of a scene moves its reference with it:

- disc in a bowl: a pendulum of length L = R - r, phi'' = -(g/L) sin phi, solved by scipy's
  DOP853 at rtol 1e-12 (frictionless: the disc does not turn); normal force m (g cos phi + L phi'^2);
- disc rolling in a bowl (friction): the same pendulum in g / (1 + I / (m r^2)) (2g/3 for a
  uniform disc), rolling (contact point at rest) while |F_t| <= mu N, which is checked;
- disc or block on an incline: closed form, it slides with g sin(slope) along the wall, less
  mu g cos(slope) with friction (a block; the energy then falls by the friction's work);
- disc over a cylinder: an inverted pendulum of length R + r until the normal force
  m (g cos phi - (R + r) phi'^2) vanishes, then a parabola; the leaving angle has the closed form
  cos phi = (2/3) cos phi0 + v0^2 / (3 g (R + r));
- plank on a cylinder: no closed form; energy is conserved (frictionless, no impacts).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

ODE_RTOL = 1e-12  # the pendulum references: far below any error the report measures
ODE_ATOL = 1e-14


@dataclass
class Trajectory:
    """One run of one scene by either engine, as the error measures need it.

    `pose`/`velocity` are those of the moving body's centre of mass, `force` the magnitude of
    the total contact force on it at each recorded time as the engine reports it (0 without
    contact, NaN where the engine has none to report: pymunk before its first step),
    `penetration` the deepest overlap seen (m) and `wall_time` the seconds the stepping took.
    """

    engine: str  # "ours" or "pymunk"
    method: str  # line of the diagram: "rk4", "pymunk N=64", ...
    setting: str  # the swept parameter of this point: "dt=0.01", "rtol=1e-06", ...
    t: np.ndarray  # (K,)
    pose: np.ndarray  # (K, 3): x, y, th
    velocity: np.ndarray  # (K, 3): vx, vy, w
    force: np.ndarray  # (K,)
    penetration: float
    wall_time: float
    # instants the engine located where a pressing contact's force reached 0 (ours: Run.lift_times)
    lift_times: np.ndarray = field(default_factory=lambda: np.zeros(0))


@dataclass(frozen=True)
class MovingBody:
    """Mass properties and initial state of the scene's one moving body."""

    mass: float
    inertia: float
    position: np.ndarray
    velocity: np.ndarray
    radius: float | None  # for a disc


def moving_body(scene) -> MovingBody:
    """The single non-fixed body of `scene` (every report scene has exactly one)."""
    (body,) = [b for b in scene.bodies if not b.fixed]
    edges = body.shape.edges
    radius = edges[0].radius if len(edges) == 1 and hasattr(edges[0], "radius") else None
    return MovingBody(
        body.mass,
        body.inertia,
        np.array(body.position, dtype=float),
        np.array(body.velocity, dtype=float),
        radius,
    )


def fixed_arc(scene) -> tuple[np.ndarray, float]:
    """(world centre, signed radius) of the circular edge of the scene's fixed body."""
    (body,) = [b for b in scene.bodies if b.fixed]
    (arc,) = body.shape.edges
    c, s = math.cos(body.angle), math.sin(body.angle)
    centre = np.array(body.position) + np.array(
        [c * arc.centre[0] - s * arc.centre[1], s * arc.centre[0] + c * arc.centre[1]]
    )
    return centre, arc.radius


def gravity(scene) -> float:
    """|g|; the references assume gravity along -y, as in every shipped scene."""
    gx, gy = scene.gravity
    if gx != 0.0 or gy >= 0.0:
        raise ValueError(f"the references need gravity along -y, got {scene.gravity}")
    return -gy


def energy_height(scene, traj: Trajectory) -> np.ndarray:
    """Mechanical energy over m g, in metres: a drift reads as a height gained or lost.

    Dividing by the weight makes scenes with a 31 kg disc and a 1 kg plank comparable, and
    puts the energy error on the same scale as the position errors.
    """
    body = moving_body(scene)
    g = gravity(scene)
    v = traj.velocity
    kinetic = 0.5 * body.mass * (v[:, 0] ** 2 + v[:, 1] ** 2) + 0.5 * body.inertia * v[:, 2] ** 2
    return kinetic / (body.mass * g) + traj.pose[:, 1]


def energy_drift(scene, traj: Trajectory) -> float:
    """max |E(t) - E(0)| / (m g), metres."""
    e = energy_height(scene, traj)
    return float(np.max(np.abs(e - e[0])))


def contact_mu(scene) -> float:
    """The Coulomb coefficient of the contact of the scene's moving body with its one fixed
    body: sqrt(mu1 mu2), as runtime.solve.friction_rows.contact_friction."""
    (fixed,) = [b for b in scene.bodies if b.fixed]
    (body,) = [b for b in scene.bodies if not b.fixed]
    return math.sqrt(fixed.friction * body.friction)


def dropped_share(traj: Trajectory) -> float:
    """Share of the steps (after t = 0) at which the engine reports no contact force although
    the body never leaves the surface: a contact held by impacts instead of a resting force."""
    force = traj.force[1:]
    return float(np.mean(force == 0.0)) if force.size else math.nan


def _finite(value: float) -> float:
    """NaN (a run that lost the body) counts as an infinite error."""
    return value if np.isfinite(value) else math.inf


class Reference:
    """A scene with the errors of a run against its reference; `primary` is the headline one."""

    primary: str = "position"
    curved: bool = True  # does the scene test a curved edge (the project's target)?
    units: dict[str, str] = {}

    def __init__(self, scene, duration: float):
        self.scene = scene
        self.duration = duration

    def errors(self, traj: Trajectory) -> dict[str, float]:
        raise NotImplementedError


class BowlReference(Reference):
    """Disc in a bowl: max position error (m), energy drift, force error (max and rms over the
    steps, in units of mg), the share of steps without contact force, penetration."""

    primary = "position"
    units = {
        "position": "m",
        "energy": "m",
        "force": "× mg",
        "force_rms": "× mg",
        "dropped": "share",
        "penetration": "m",
    }

    def __init__(self, scene, duration: float):
        super().__init__(scene, duration)
        body = moving_body(scene)
        self.centre, radius = fixed_arc(scene)
        self.length = abs(radius) - body.radius
        self.g = gravity(scene)
        self.mass = body.mass
        self.pull = self.g * self.pull_share(body)
        rel = body.position - self.centre
        phi0 = math.atan2(rel[0], -rel[1])
        dphi0 = float(body.velocity @ [math.cos(phi0), math.sin(phi0)]) / self.length
        self.solution = solve_ivp(
            self._rhs,
            (0.0, duration),
            [phi0, dphi0],
            method="DOP853",
            rtol=ODE_RTOL,
            atol=ODE_ATOL,
            dense_output=True,
        )

    def pull_share(self, body: MovingBody) -> float:
        """The share of g that drives the pendulum: all of it when the disc slides (no friction)."""
        return 1.0

    def _rhs(self, _t: float, y: np.ndarray) -> list[float]:
        return [y[1], -self.pull / self.length * math.sin(y[0])]

    def state(self, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(centre positions (K, 2), velocities (K, 2), normal force (K,)) at times t."""
        phi, dphi = self.solution.sol(t)
        s, c = np.sin(phi), np.cos(phi)
        pos = self.centre + self.length * np.c_[s, -c]
        vel = self.length * dphi[:, None] * np.c_[c, s]
        force = self.mass * (self.g * c + self.length * dphi**2)
        return pos, vel, force

    def errors(self, traj: Trajectory) -> dict[str, float]:
        pos, _, force = self.state(traj.t)
        dev = np.abs(traj.force - force) / (self.mass * self.g)
        return {
            "position": _finite(np.max(np.linalg.norm(traj.pose[:, :2] - pos, axis=1))),
            "energy": _finite(energy_drift(self.scene, traj)),
            "force": _finite(np.nanmax(dev)),
            "force_rms": _finite(np.sqrt(np.nanmean(dev**2))),
            "dropped": dropped_share(traj),
            "penetration": traj.penetration,
        }


class RollingBowlReference(BowlReference):
    """Disc rolling in a bowl (friction): as the bowl, in g / (1 + I / (m r^2)), and the slip
    speed of the disc's contact point (m/s), 0 for rolling. Refuses a scene whose mu is too
    small for rolling all the way (|F_t| > mu N somewhere on the reference's path)."""

    units = {**BowlReference.units, "slip": "m/s"}

    def __init__(self, scene, duration: float):
        super().__init__(scene, duration)
        body = moving_body(scene)
        self.radius = body.radius
        times = np.linspace(0.0, duration, 2001)
        phi, dphi = self.solution.sol(times)
        share = body.inertia / (body.inertia + body.mass * body.radius**2)
        tangential = body.mass * self.g * share * np.abs(np.sin(phi))
        normal = body.mass * (self.g * np.cos(phi) + self.length * dphi**2)
        needed = float(np.max(tangential / normal))
        if needed > contact_mu(scene):
            raise ValueError(
                f"the disc would slip: rolling needs mu >= {needed:.3g}, the scene has "
                f"{contact_mu(scene):.3g}"
            )

    def pull_share(self, body: MovingBody) -> float:
        return 1.0 / (1.0 + body.inertia / (body.mass * body.radius**2))

    def errors(self, traj: Trajectory) -> dict[str, float]:
        out = super().errors(traj)
        rel = traj.pose[:, :2] - self.centre
        phi = np.arctan2(rel[:, 0], -rel[:, 1])
        tangent = np.c_[np.cos(phi), np.sin(phi)]
        slip = (
            np.einsum("kc,kc->k", traj.velocity[:, :2], tangent) + self.radius * traj.velocity[:, 2]
        )
        return {**out, "slip": _finite(float(np.max(np.abs(slip))))}


class InclineReference(Reference):
    """A body sliding down an incline (straight edge): position, energy against the friction's
    work (the drift when frictionless), normal force, penetration. With friction (mu of the
    contact > 0) the body must be one that slides flat (a block: a disc would roll) and slide
    from rest or downhill: a = g (sin - mu cos) along the slope, or stay put if tan <= mu."""

    primary = "position"
    curved = False
    units = {
        "position": "m",
        "energy": "m",
        "force": "× mg",
        "dropped": "share",
        "penetration": "m",
    }

    def __init__(self, scene, duration: float):
        super().__init__(scene, duration)
        body = moving_body(scene)
        (wall,) = [b for b in scene.bodies if b.fixed]
        (segment,) = wall.shape.edges
        along = np.subtract(segment.end, segment.start) / segment.length
        g_vec = np.asarray(scene.gravity, dtype=float)
        pull, press = float(g_vec @ along), abs(float(g_vec @ [along[1], -along[0]]))
        self.mu = contact_mu(scene)
        v_along = float(body.velocity @ along)
        sliding = abs(pull) > self.mu * press
        if self.mu > 0 and (
            body.radius is not None or v_along * pull < 0 or v_along and not sliding
        ):
            raise ValueError(
                "the incline reference with friction is for a block at rest or sliding downhill "
                "without stopping"
            )
        slide = pull - math.copysign(self.mu * press, pull) if sliding or v_along else 0.0
        self.acceleration = slide * along  # gravity along the slope, less friction
        self.friction_per_metre = self.mu * press / gravity(scene)  # height lost per metre slid
        self.normal_force = body.mass * press
        self.start, self.v0 = body.position, body.velocity
        self.weight = body.mass * gravity(scene)

    def position(self, t: np.ndarray) -> np.ndarray:
        return self.start + np.outer(t, self.v0) + 0.5 * np.outer(t**2, self.acceleration)

    def errors(self, traj: Trajectory) -> dict[str, float]:
        exact = self.position(traj.t)
        err = np.linalg.norm(traj.pose[:, :2] - exact, axis=1)
        slid = np.linalg.norm(exact - self.start, axis=1)
        energy = energy_height(self.scene, traj) + self.friction_per_metre * slid
        return {
            "position": _finite(np.max(err)),
            "energy": _finite(float(np.max(np.abs(energy - energy[0])))),
            "force": _finite(np.nanmax(np.abs(traj.force - self.normal_force)) / self.weight),
            "dropped": dropped_share(traj),
            "penetration": traj.penetration,
        }


class CylinderReference(Reference):
    """Disc sliding over a cylinder: leaving-angle error (rad), position, energy, penetration."""

    primary = "leaving_angle"
    units = {"leaving_angle": "rad", "position": "m", "energy": "m", "penetration": "m"}

    def __init__(self, scene, duration: float):
        super().__init__(scene, duration)
        body = moving_body(scene)
        self.centre, radius = fixed_arc(scene)
        self.length = radius + body.radius
        self.g = gravity(scene)
        rel = body.position - self.centre
        phi0 = math.atan2(rel[0], rel[1])  # from the top, clockwise
        tangent = np.array([math.cos(phi0), -math.sin(phi0)])
        dphi0 = float(body.velocity @ tangent) / self.length
        v0 = self.length * dphi0
        self.leaving_angle = math.acos(
            2.0 / 3.0 * math.cos(phi0) + v0**2 / (3.0 * self.g * self.length)
        )
        self._on_cylinder = self._solve_on_cylinder(phi0, dphi0)

    def _normal_force_per_mass(self, phi: float, dphi: float) -> float:
        return self.g * math.cos(phi) - self.length * dphi**2

    def _solve_on_cylinder(self, phi0: float, dphi0: float):
        """Inverted pendulum until the normal force vanishes (an event of the ODE)."""

        def leaves(_t, y):
            return self._normal_force_per_mass(y[0], y[1])

        leaves.terminal = True
        sol = solve_ivp(
            lambda _t, y: [y[1], self.g / self.length * math.sin(y[0])],
            (0.0, self.duration),
            [phi0, dphi0],
            method="DOP853",
            rtol=ODE_RTOL,
            atol=ODE_ATOL,
            dense_output=True,
            events=leaves,
        )
        if not sol.t_events[0].size:
            raise ValueError("the disc does not leave the cylinder within the duration")
        self.leaving_time = float(sol.t_events[0][0])
        phi, dphi = sol.y_events[0][0]
        if abs(phi - self.leaving_angle) > 1e-8:  # the ODE agrees with the closed form
            raise AssertionError(f"leaving angle: ODE {phi}, closed form {self.leaving_angle}")
        return sol

    def position(self, t: np.ndarray) -> np.ndarray:
        """Centre of the disc: on the circle before leaving, on a parabola after."""
        t = np.asarray(t, dtype=float)
        out = np.empty((t.size, 2))
        before = t <= self.leaving_time
        phi = self._on_cylinder.sol(t[before])[0]
        out[before] = self.centre + self.length * np.c_[np.sin(phi), np.cos(phi)]
        phi_l, dphi_l = self._on_cylinder.sol(self.leaving_time)
        p_l = self.centre + self.length * np.array([math.sin(phi_l), math.cos(phi_l)])
        v_l = self.length * dphi_l * np.array([math.cos(phi_l), -math.sin(phi_l)])
        tau = t[~before] - self.leaving_time
        out[~before] = p_l + np.outer(tau, v_l) + 0.5 * np.outer(tau**2, [0.0, -self.g])
        return out

    def measured_leaving_angle(self, traj: Trajectory) -> float:
        """The angle where the run's contact force reaches 0.

        The force is a smooth function of phi up to the moment the disc leaves, so the zero of
        the parabola through the last three samples with force (the line through the last two
        when there are only two) is accurate to third (second) order in the sample spacing, and
        the step at which the engine drops the contact does not matter. The zero is kept inside
        the bracket [last sample with force, first sample without], which is all a force that
        comes and goes (pymunk's) can tell.

        An engine that locates the instant itself (ours: runtime.step.lift_events) is measured
        there instead: the disc's centre at that instant, from the first record after it taken
        back along its free flight (a parabola under gravity, as the reference's).
        """
        if traj.lift_times.size:
            return self._angle_at_lift(traj, float(traj.lift_times[0]))
        rel = traj.pose[:, :2] - self.centre
        phi = np.arctan2(rel[:, 0], rel[:, 1])
        touching = np.flatnonzero(traj.force > 0.0)
        if touching.size == 0 or touching[-1] + 1 >= len(phi):
            return math.nan  # never touched, or never left
        i = touching[-1]
        lo, hi = sorted((phi[i], phi[i + 1]))
        run = 1  # samples with force in a row, ending at i
        while run < 3 and i - run >= 0 and traj.force[i - run] > 0.0:
            run += 1
        if run == 1:
            return float(phi[i])
        x, f = phi[i - run + 1 : i + 1], traj.force[i - run + 1 : i + 1]
        if np.ptp(x) == 0.0:
            return float(phi[i])
        roots = np.roots(np.polyfit(x - phi[i], f, run - 1)) + phi[i]
        roots = roots[np.isreal(roots)].real
        if roots.size == 0:
            return float(phi[i])
        zero = roots[np.argmin(np.abs(roots - phi[i]))]  # the zero next to the last sample
        return float(np.clip(zero, lo, hi))

    def _angle_at_lift(self, traj: Trajectory, lift: float) -> float:
        """The angle of the disc's centre at ``lift``, from the first record after it."""
        k = int(np.searchsorted(traj.t, lift, side="right"))
        if k >= len(traj.t):
            return math.nan
        back = traj.t[k] - lift
        centre = traj.pose[k, :2] - back * traj.velocity[k, :2]
        centre[1] -= 0.5 * self.g * back**2  # p(t) = p_k - v_k back + g back^2 / 2, g = -|g| y
        rel = centre - self.centre
        return math.atan2(rel[0], rel[1])

    def errors(self, traj: Trajectory) -> dict[str, float]:
        err = np.linalg.norm(traj.pose[:, :2] - self.position(traj.t), axis=1)
        return {
            "leaving_angle": _finite(abs(self.measured_leaving_angle(traj) - self.leaving_angle)),
            "position": _finite(np.max(err)),
            "energy": _finite(energy_drift(self.scene, traj)),
            "penetration": traj.penetration,
        }


class PlankReference(Reference):
    """Plank on a cylinder: energy drift (the only reference there is) and penetration."""

    primary = "energy"
    units = {"energy": "m", "penetration": "m"}

    def errors(self, traj: Trajectory) -> dict[str, float]:
        return {
            "energy": _finite(energy_drift(self.scene, traj)),
            "penetration": traj.penetration,
        }
