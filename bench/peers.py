"""The pymunk (Chipmunk2D) side of the report: the same scenes, stepped by a game engine.

A `runtime.Scene` is translated shape by shape, so both engines start from one scene file:
a full convex arc becomes a `pymunk.Circle` (the cylinder, the discs), a straight edge a
`pymunk.Segment` (the incline), a concave arc (the bowl) N straight segments with their end
points on the arc (pymunk has no concave curves), a convex polygon a `pymunk.Poly`.
Friction and elasticity are 0, as in the frictionless, inelastic scenes; mass, inertia and the
initial state are the scene's.

Chipmunk2D steps with a fixed dt (semi-implicit Euler, positions first) and resolves contacts
with `iterations` sweeps of sequential impulses; those two and N are what the report sweeps.
Each configuration is run twice: a timed pass that records only the state a user would read
(pose and velocity), and an untimed pass that also collects contact impulses and depths through
`Body.each_arbiter` (Python callbacks that would otherwise cost pymunk as much as its step).
"""

from __future__ import annotations

import itertools
import math
import time
from dataclasses import dataclass

import numpy as np
import pymunk

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
            shape.friction = 0.0
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
    """States, contact force magnitude (impulse / dt) per step, deepest overlap."""
    space, body = build_space(scene, config)
    states = np.empty((steps + 1, 6))
    states[0] = _state(body)
    force = np.zeros(steps + 1)
    force[0] = np.nan  # no impulse has been computed before the first step
    acc = {"impulse": 0.0, "depth": 0.0}

    def visit(arbiter: pymunk.Arbiter) -> None:
        acc["impulse"] += abs(arbiter.total_impulse)
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


def simulate(
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
