"""The peers of the report: the same scenes stepped by two game engines, pymunk and Box2D.

## pymunk (Chipmunk2D)

A `runtime.Scene` is translated shape by shape, so both engines start from one scene file:
a full convex arc becomes a `pymunk.Circle` (the cylinder, the discs), a straight edge a
`pymunk.Segment` (the incline), a concave arc (the bowl) N straight segments with their end
points on the arc (pymunk has no concave curves), a convex polygon a `pymunk.Poly`.
Elasticity is the body's restitution; friction gives each contact the scene's coefficient
sqrt(mu1 mu2): Chipmunk multiplies its shapes' frictions, so each shape gets sqrt(mu) of its
body. Mass, inertia and the initial state are the scene's.

Chipmunk2D steps with a fixed dt (semi-implicit Euler, positions first) and resolves contacts
with `iterations` sweeps of sequential impulses; those two and N are what the report sweeps.
Each configuration is run twice: a timed pass that records only the state a user would read
(pose and velocity), and an untimed pass that also collects contact impulses and depths through
`Body.each_arbiter` (Python callbacks that would otherwise cost pymunk as much as its step).

## Box2D (2.3.10, the `box2d` package on PyPI, optional)

Translated the same way: full circles as `b2CircleShape`, straight edges and the bowl's chords as
`b2EdgeShape`, a convex polygon as `b2PolygonShape`, with the scene's mass and inertia (about
the centre of mass) set directly, and each fixture the body's friction (Box2D mixes them as
sqrt(mu1 mu2), as we do). Box2D gives polygons and edges a "skin" (`b2_polygonRadius`,
1 cm) that keeps them apart by that much; it is set to 0 so the surfaces are the scene's (as
pymunk's radius 0), which leaves Box2D's own resting overlap, `b2_linearSlop` = 5 mm, compiled
in and not settable: what its position solver tolerates before pushing bodies apart. Box2D
computes in float32. It steps with a fixed dt (sequential impulses: `velocity_iterations`,
then `position_iterations` of position correction), sleeping off, continuous collision on (its
default). Its sweep is dt, velocity iterations and, for the bowl, N.
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass

import numpy as np
import pymunk

try:
    import Box2D
except ImportError:  # the optional peer: `pip install -e '.[peers]'`
    Box2D = None

from bench.references import Trajectory

COLLISION_SLOP = 1e-4  # m: pymunk's default (0.1) would let bodies sink by up to 10 cm


@dataclass(frozen=True)
class PeerConfig:
    """One point of pymunk's sweep."""

    dt: float
    iterations: int = 10
    segments: int = 64  # straight segments per concave arc (only scenes with a bowl use it)

    def label(self, with_segments: bool) -> str:
        """The line of the diagram this point belongs to."""
        parts = [f"N={self.segments}"] if with_segments else []
        if self.iterations != 10:
            parts.append(f"{self.iterations} it")
        return "pymunk" + (" " + ", ".join(parts) if parts else "")


def _world(body, p) -> tuple[float, float]:
    """A point of a fixed body's shape in world coordinates."""
    c, s = math.cos(body.angle), math.sin(body.angle)
    x, y = body.position
    return (x + c * p[0] - s * p[1], y + s * p[0] + c * p[1])


def arc_polyline(arc, segments: int) -> list[tuple[float, float]]:
    """`segments` + 1 points on an arc, ends included (chords: the polygon lies inside)."""
    a0, span = arc.start_angle, arc.end_angle - arc.start_angle
    return [arc.point(a0 + span * k / segments) for k in range(segments + 1)]


def _static_shapes(space: pymunk.Space, body, segments: int) -> list[pymunk.Shape]:
    """pymunk shapes of one fixed body of the scene, attached to the space's static body."""
    shapes: list[pymunk.Shape] = []
    for edge in body.shape.edges:
        if hasattr(edge, "radius") and edge.radius > 0 and edge.full:
            centre = _world(body, edge.centre)
            shapes.append(pymunk.Circle(space.static_body, edge.radius, centre))
        elif hasattr(edge, "radius"):
            pts = [_world(body, p) for p in arc_polyline(edge, segments)]
            shapes += [
                pymunk.Segment(space.static_body, p, q, 0.0) for p, q in itertools.pairwise(pts)
            ]
        elif hasattr(edge, "start"):
            a, b = _world(body, edge.start), _world(body, edge.end)
            shapes.append(pymunk.Segment(space.static_body, a, b, 0.0))
        else:
            raise NotImplementedError(f"no pymunk shape for {type(edge).__name__} edges")
    return shapes


def _moving_body(body) -> tuple[pymunk.Body, list[pymunk.Shape]]:
    """A dynamic pymunk body with the scene body's mass, inertia, shape and initial state."""
    pb = pymunk.Body(body.mass, body.inertia)
    pb.position = body.position
    pb.angle = body.angle
    pb.velocity = body.velocity
    pb.angular_velocity = body.angular_velocity
    edges = body.shape.edges
    if len(edges) == 1 and hasattr(edges[0], "radius") and edges[0].full:
        shapes = [pymunk.Circle(pb, edges[0].radius, edges[0].centre)]
    elif all(hasattr(e, "start") for e in edges) and body.shape.closed:
        shapes = [pymunk.Poly(pb, [e.start for e in edges], radius=0.0)]
    else:
        raise NotImplementedError(f"no pymunk shape for moving body {body.name!r}")
    return pb, shapes


def build_space(scene, config: PeerConfig) -> tuple[pymunk.Space, pymunk.Body]:
    """The scene as a pymunk space, and the pymunk body of its one moving body."""
    space = pymunk.Space()
    space.gravity = tuple(scene.gravity)
    space.iterations = config.iterations
    space.collision_slop = COLLISION_SLOP
    moving = None
    for body in scene.bodies:
        if body.fixed:
            shapes = _static_shapes(space, body, config.segments)
            space.add(*shapes)
        else:
            if moving is not None:
                raise NotImplementedError("the report scenes have one moving body")
            moving, shapes = _moving_body(body)
            space.add(moving, *shapes)
        for shape in shapes:
            shape.friction = math.sqrt(body.friction)  # pymunk: mu1' mu2' = sqrt(mu1 mu2)
            shape.elasticity = body.restitution
    return space, moving


def _state(body: pymunk.Body) -> tuple[float, ...]:
    x, y = body.position
    vx, vy = body.velocity
    return (x, y, body.angle, vx, vy, body.angular_velocity)


def _timed_pass(scene, config: PeerConfig, steps: int) -> tuple[np.ndarray, float]:
    """States (steps + 1, 6) and the wall time of stepping while reading the state."""
    space, body = build_space(scene, config)
    states = np.empty((steps + 1, 6))
    states[0] = _state(body)
    step, dt = space.step, config.dt
    start = time.perf_counter()
    for k in range(1, steps + 1):
        step(dt)
        states[k] = _state(body)
    return states, time.perf_counter() - start


def _detail_pass(scene, config: PeerConfig, steps: int) -> tuple[np.ndarray, np.ndarray, float]:
    """States, normal contact force magnitude (impulse / dt) per step, deepest overlap."""
    space, body = build_space(scene, config)
    states = np.empty((steps + 1, 6))
    states[0] = _state(body)
    force = np.zeros(steps + 1)
    force[0] = np.nan  # no impulse has been computed before the first step
    acc = {"impulse": 0.0, "depth": 0.0}

    def visit(arbiter: pymunk.Arbiter) -> None:
        acc["impulse"] += abs(arbiter.total_impulse.dot(arbiter.normal))  # without friction
        for point in arbiter.contact_point_set.points:
            acc["depth"] = max(acc["depth"], -point.distance)

    for k in range(1, steps + 1):
        space.step(config.dt)
        states[k] = _state(body)
        acc["impulse"] = 0.0
        body.each_arbiter(visit)
        # Chipmunk moves the bodies first and then finds the contacts: the impulse of this step
        # belongs to the pose after it.
        force[k] = acc["impulse"] / config.dt
    return states, force, acc["depth"]


def simulate_pymunk(
    scene, duration: float, config: PeerConfig, with_segments: bool, repeats: int = 3
) -> Trajectory:
    """Run `scene` in pymunk; the wall time is the best of `repeats` timed passes (pymunk is
    cheap, and the best of a few runs is the least disturbed by other processes)."""
    steps = int(round(duration / config.dt))
    states, wall = _timed_pass(scene, config, steps)
    for _ in range(repeats - 1):
        wall = min(wall, _timed_pass(scene, config, steps)[1])
    detail, force, depth = _detail_pass(scene, config, steps)
    if not np.array_equal(states, detail, equal_nan=True):
        raise RuntimeError("pymunk is not deterministic here: the two passes differ")
    return Trajectory(
        engine="pymunk",
        method=config.label(with_segments),
        setting=f"dt=1/{1 / config.dt:.0f}",
        t=np.arange(steps + 1) * config.dt,
        pose=states[:, :3],
        velocity=states[:, 3:],
        force=force,
        penetration=float(depth),
        wall_time=wall,
    )


def version() -> str:
    return f"pymunk {pymunk.version} (Chipmunk2D {pymunk.chipmunk_version.split('-')[0]})"


# -- Box2D ----------------------------------------------------------------------------------------


@dataclass(frozen=True)
class Box2DConfig:
    """One point of Box2D's sweep."""

    dt: float
    iterations: int = 8  # velocity iterations (Box2D's recommended default)
    position_iterations: int = 3
    segments: int = 64

    def label(self, with_segments: bool) -> str:
        parts = [f"N={self.segments}"] if with_segments else []
        if self.iterations != 8:
            parts.append(f"{self.iterations} it")
        return "Box2D" + (" " + ", ".join(parts) if parts else "")


def box2d_available() -> bool:
    return Box2D is not None


def box2d_version() -> str:
    return f"Box2D {Box2D.__version__} (pybox2d, float32)"


def _box2d_static(world, body, segments: int) -> None:
    """The fixed body's edges as Box2D shapes of the world's one static body (no skin)."""
    ground = world.CreateStaticBody()
    for edge in body.shape.edges:
        if hasattr(edge, "radius") and edge.radius > 0 and edge.full:
            shape = Box2D.b2CircleShape(radius=edge.radius, pos=_world(body, edge.centre))
            ground.CreateFixture(shape=shape, friction=body.friction, restitution=body.restitution)
            continue
        if hasattr(edge, "radius"):
            points = [_world(body, p) for p in arc_polyline(edge, segments)]
        elif hasattr(edge, "start"):
            points = [_world(body, edge.start), _world(body, edge.end)]
        else:
            raise NotImplementedError(f"no Box2D shape for {type(edge).__name__} edges")
        for a, b in itertools.pairwise(points):
            shape = Box2D.b2EdgeShape(vertices=[a, b])
            shape.radius = 0.0
            ground.CreateFixture(shape=shape, friction=body.friction, restitution=body.restitution)


def _box2d_moving(world, body):
    """A dynamic Box2D body with the scene body's shape, mass, inertia and initial state."""
    b = world.CreateDynamicBody(
        position=body.position,
        angle=body.angle,
        linearVelocity=body.velocity,
        angularVelocity=body.angular_velocity,
        bullet=False,
    )
    edges = body.shape.edges
    if len(edges) == 1 and hasattr(edges[0], "radius") and edges[0].full:
        shape = Box2D.b2CircleShape(radius=edges[0].radius, pos=edges[0].centre)
    elif all(hasattr(e, "start") for e in edges) and body.shape.closed and len(edges) <= 8:
        shape = Box2D.b2PolygonShape(vertices=[e.start for e in edges])
        shape.radius = 0.0
    else:
        raise NotImplementedError(f"no Box2D shape for moving body {body.name!r}")
    b.CreateFixture(shape=shape, density=1.0, friction=body.friction, restitution=body.restitution)
    b.massData = Box2D.b2MassData(mass=body.mass, center=(0.0, 0.0), I=body.inertia)
    return b


def build_box2d_world(scene, config: Box2DConfig):
    """The scene as a Box2D world, and the Box2D body of its one moving body."""
    world = Box2D.b2World(gravity=tuple(scene.gravity), doSleep=False)
    moving = None
    for body in scene.bodies:
        if body.fixed:
            _box2d_static(world, body, config.segments)
        elif moving is not None:
            raise NotImplementedError("the report scenes have one moving body")
        else:
            moving = _box2d_moving(world, body)
    return world, moving


def _box2d_state(b) -> tuple[float, ...]:
    (x, y), (vx, vy) = b.position, b.linearVelocity
    return (x, y, b.angle, vx, vy, b.angularVelocity)


def _apply(xf, p) -> np.ndarray:
    """A Box2D transform applied to a local point."""
    c, s = xf.q.c, xf.q.s
    return np.array([xf.position[0] + c * p[0] - s * p[1], xf.position[1] + s * p[0] + c * p[1]])


def _separations(contact) -> list[float]:
    """The separations of a contact's manifold points, as b2WorldManifold::Initialize computes
    them (pybox2d does not expose them): negative is overlap."""
    m = contact.manifold
    fa, fb = contact.fixtureA, contact.fixtureB
    xa, xb = fa.body.transform, fb.body.transform
    ra, rb = fa.shape.radius, fb.shape.radius
    if m.pointCount == 0:
        return []
    if m.type_ == Box2D.b2Manifold.e_circles:
        pa, pb = _apply(xa, m.localPoint), _apply(xb, m.points[0].localPoint)
        return [float(np.hypot(*(pb - pa))) - ra - rb]
    face, other = (xa, xb) if m.type_ == Box2D.b2Manifold.e_faceA else (xb, xa)
    c, s = face.q.c, face.q.s
    n = np.array(
        [c * m.localNormal[0] - s * m.localNormal[1], s * m.localNormal[0] + c * m.localNormal[1]]
    )
    plane = _apply(face, m.localPoint)
    return [
        float((_apply(other, m.points[i].localPoint) - plane) @ n) - ra - rb
        for i in range(m.pointCount)
    ]


def _box2d_timed(scene, config: Box2DConfig, steps: int) -> tuple[np.ndarray, float]:
    world, body = build_box2d_world(scene, config)
    states = np.empty((steps + 1, 6))
    states[0] = _box2d_state(body)
    step, dt = world.Step, config.dt
    vi, pi = config.iterations, config.position_iterations
    start = time.perf_counter()
    for k in range(1, steps + 1):
        step(dt, vi, pi)
        states[k] = _box2d_state(body)
    return states, time.perf_counter() - start


def _box2d_detail(scene, config: Box2DConfig, steps: int):
    """States, contact force magnitude (normal impulse / dt) per step, deepest overlap."""
    world, body = build_box2d_world(scene, config)
    states = np.empty((steps + 1, 6))
    states[0] = _box2d_state(body)
    force = np.zeros(steps + 1)
    force[0] = np.nan
    depth = 0.0
    for k in range(1, steps + 1):
        world.Step(config.dt, config.iterations, config.position_iterations)
        states[k] = _box2d_state(body)
        impulse = 0.0
        for edge in body.contacts:
            contact = edge.contact
            if not contact.touching:
                continue
            impulse += sum(
                contact.manifold.points[i].normalImpulse for i in range(contact.manifold.pointCount)
            )
            depth = max([depth, *(-s for s in _separations(contact))])
        force[k] = impulse / config.dt
    return states, force, depth


def simulate_box2d(
    scene, duration: float, config: Box2DConfig, with_segments: bool, repeats: int = 3
) -> Trajectory:
    """Run `scene` in Box2D; the wall time is the best of `repeats` timed passes."""
    steps = int(round(duration / config.dt))
    states, wall = _box2d_timed(scene, config, steps)
    for _ in range(repeats - 1):
        wall = min(wall, _box2d_timed(scene, config, steps)[1])
    detail, force, depth = _box2d_detail(scene, config, steps)
    if not np.array_equal(states, detail, equal_nan=True):
        raise RuntimeError("Box2D is not deterministic here: the two passes differ")
    return Trajectory(
        engine="Box2D",
        method=config.label(with_segments),
        setting=f"dt=1/{1 / config.dt:.0f}",
        t=np.arange(steps + 1) * config.dt,
        pose=states[:, :3],
        velocity=states[:, 3:],
        force=force,
        penetration=float(depth),
        wall_time=wall,
    )
