"""Moving bodies behind the back face of a fixed wall, bowl or box at t = 0.

Why: walls, bowls and boxes are one-sided (runtime/model/shapes.py): contacts exist only in
front of an edge, and its back is material.  A wall drawn the wrong way round (start and end
swapped) leaves the body behind it, where nothing touches it; the body then falls through and
the run's tunnelling guard blames the time step.  So a moving body whose centre is behind an
open chain's edge, level with the edge (within its span), and near it (closer than
BACK_FACE_REACH of its own size) is refused at load, naming the edge and the fix.  A body
beside the edge's end, far behind it, or shielded from it by another fixed edge (the top face
of a plate drawn as two walls back to back) is left alone.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from runtime.collide.contacts import candidate_pairs
from runtime.io.scene_table import Table, body_label
from runtime.model.scene import Scene
from runtime.model.shapes import Arc, Segment
from runtime.settings import BACK_FACE_REACH

__all__ = ["check_facing"]

_BOX_PARTS = ("right side", "floor", "left side")  # box_walls' edges, in shape_library's order


def check_facing(scene: Scene) -> None:
    """Refuse the first moving body found behind a fixed open chain's edge (see the module)."""
    bodies = scene.bodies
    radii = np.array([float(b.shape.bounding_radius) for b in bodies])
    reach = np.where(scene.fixed, radii, (1.0 + 2.0 * BACK_FACE_REACH) * radii)
    centres = scene.poses()[:, :2]
    first, second = candidate_pairs(centres, reach, np.asarray(scene.fixed, dtype=bool))
    walls = {k: _world_edges(b) for k, b in enumerate(bodies) if b.fixed}
    for i, j in zip(first.tolist(), second.tolist(), strict=True):
        wall, body = (i, j) if bodies[i].fixed else (j, i)
        if not bodies[wall].fixed or bodies[body].fixed or bodies[wall].shape.closed:
            continue
        c = centres[body]
        for index, edge in enumerate(walls[wall]):
            found = _behind(edge, c)
            if found is None or found[0] >= reach[body]:
                continue
            depth, foot = found
            others = [e for k, es in walls.items() for e in es if e is not edge]
            if not any(_crosses(e, c, foot) for e in others):
                _fail(scene, wall, body, index, depth)


def _world_edges(body: Any) -> list[tuple]:
    """A fixed body's edges in world coordinates: ("seg", a, b, normal) or ("arc", centre,
    signed radius, start angle, span)."""
    x, y, th = body.pose
    c, s = math.cos(th), math.sin(th)

    def place(p) -> np.ndarray:
        return np.array([x + c * p[0] - s * p[1], y + s * p[0] + c * p[1]])

    edges: list[tuple] = []
    for e in body.shape.edges:
        if isinstance(e, Segment):
            edges.append(("seg", place(e.start), place(e.end), place(e.normal) - place((0, 0))))
        elif isinstance(e, Arc):
            edges.append(("arc", place(e.centre), e.radius, e.start_angle + th, e.span))
    return edges


def _behind(edge: tuple, p: np.ndarray) -> tuple[float, np.ndarray] | None:
    """(how far ``p`` is behind the edge, its foot on the edge) if ``p`` is behind the edge
    and level with it, else None."""
    if edge[0] == "seg":
        _, a, b, n = edge
        u = b - a
        t = float((p - a) @ u / (u @ u))
        front = float((p - a) @ n)
        return (-front, a + t * u) if front < 0 and 0.0 <= t <= 1.0 else None
    _, centre, radius, start, span = edge
    v = p - centre
    d = math.hypot(*v)
    if d == 0.0 or (math.atan2(v[1], v[0]) - start) % math.tau > span:
        return None
    depth = d - abs(radius) if radius < 0 else radius - d  # a bowl's back is outside its circle
    return (depth, centre + abs(radius) * v / d) if depth > 0 else None


def _crosses(edge: tuple, p: np.ndarray, q: np.ndarray) -> bool:
    """Whether the segment from ``p`` to ``q`` crosses ``edge`` (end points excluded)."""
    d = q - p
    if edge[0] == "seg":
        _, a, b, _ = edge
        e = b - a
        den = d[0] * e[1] - d[1] * e[0]
        if den == 0.0:
            return False
        w = a - p
        s, t = (w[0] * e[1] - w[1] * e[0]) / den, (w[0] * d[1] - w[1] * d[0]) / den
        return 0.0 < s < 1.0 and 0.0 <= t <= 1.0
    _, centre, radius, start, span = edge
    w = p - centre
    qa, qb, qc = d @ d, 2 * (w @ d), w @ w - radius * radius
    disc = qb * qb - 4 * qa * qc
    if qa == 0.0 or disc < 0:
        return False
    for s in ((-qb - math.sqrt(disc)) / (2 * qa), (-qb + math.sqrt(disc)) / (2 * qa)):
        hit = w + s * d
        if 0.0 < s < 1.0 and (math.atan2(hit[1], hit[0]) - start) % math.tau <= span:
            return True
    return False


def _fail(scene: Scene, wall: int, body: int, index: int, depth: float) -> None:
    shape, name = scene.bodies[wall].shape, scene.bodies[body].name
    other = body_label(body, name)
    kinds = [type(e) for e in shape.edges]
    centre = f"its centre {depth:.3g} m behind"
    if kinds == [Segment]:
        what = (
            f"{other} is at the back of this wall ({centre} it), where walls have no contacts "
            f"(material on the right of start -> end); swap start and end to make it face "
            f"{name!r}, or move {name!r} in front"
        )
    elif kinds == [Arc]:
        what = (
            f"{other} is outside this bowl ({centre} its arc), at its back: a bowl holds bodies "
            f"inside its circle (radius {abs(shape.edges[0].radius):g} m); move {name!r} inside, "
            "or use a fixed disc for a surface to rest on from outside"
        )
    elif kinds == [Segment] * 3:
        what = (
            f"{other} is outside this box ({centre} its {_BOX_PARTS[index]}): box walls face "
            f"inwards; move {name!r} inside, or use walls facing it"
        )
    else:
        what = f"{other} is at the back of edge {index} of this chain ({centre} it); reverse its points"
    Table({}, scene.source, body_label(wall, scene.bodies[wall].name)).fail("shape", what)
