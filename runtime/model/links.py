"""Joints and springs: what links two bodies (or a body and the world) besides contacts.

Why a model of its own: a scene file names the bodies and gives the anchors in each body's shape
coordinates; the engine wants body indices and anchors in body coordinates (origin at the centre
of mass, docs/conventions.md). A link to a fixed body or to the world is stored as a link to the
world with its anchor in world coordinates (a fixed body never moves), so the engine sees only
two kinds of ends: a moving body, or the world (``body2 = WORLD``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

__all__ = [
    "JOINT_KINDS",
    "WORLD",
    "Joint",
    "Spring",
    "anchor_in_body",
    "anchor_in_world",
    "body_point_in_world",
    "link_segments",
]

WORLD = -1  # body index of the world end of a link
JOINT_KINDS = {"pin": "pin_joint", "distance": "distance_joint"}  # scene word -> generated joint

Vec2 = tuple[float, float]


@dataclass(frozen=True)
class Joint:
    """A pin joint (anchor 1 held on anchor 2: two rows) or a distance joint (|p1 - p2| held at
    ``length``: one row). ``body1`` moves; ``body2`` is a moving body or WORLD; anchors in body
    coordinates (anchor 2 in world coordinates for WORLD)."""

    name: str
    kind: str  # "pin" or "distance"
    body1: int
    body2: int
    anchor1: Vec2
    anchor2: Vec2
    length: float = 0.0

    @property
    def generated(self) -> str:
        """The generated kernel module of this joint (generated/<name>.py)."""
        return JOINT_KINDS[self.kind]


@dataclass(frozen=True)
class Spring:
    """A linear spring with a dashpot between two anchors: force k (|s| - rest_length) + c s'
    along s = p1 - p2 (N), pulling the anchors together when stretched. Ends as for
    :class:`Joint`."""

    name: str
    body1: int
    body2: int
    anchor1: Vec2
    anchor2: Vec2
    rest_length: float
    stiffness: float  # N/m
    damping: float = 0.0  # N s/m


def anchor_in_body(body, anchor: Sequence[float]) -> Vec2:
    """A point given in ``body``'s shape coordinates, in its body coordinates (centre of mass
    origin): shifted by the body's ``origin``."""
    return (float(anchor[0]) + body.origin[0], float(anchor[1]) + body.origin[1])


def anchor_in_world(body, anchor: Sequence[float]) -> Vec2:
    """A point given in ``body``'s shape coordinates, in world coordinates at its pose now."""
    return body_point_in_world(body, anchor_in_body(body, anchor))


def body_point_in_world(body, point: Sequence[float]) -> Vec2:
    """A point given in ``body``'s body coordinates, in world coordinates at its pose now."""
    x, y = float(point[0]), float(point[1])
    c, s = math.cos(body.angle), math.sin(body.angle)
    return (body.position[0] + c * x - s * y, body.position[1] + s * x + c * y)


def anchor_points(poses: np.ndarray, body: np.ndarray, anchor: np.ndarray) -> np.ndarray:
    """(m, 2) world positions of anchors ``anchor`` (m, 2, body coordinates) of bodies ``body``
    (m,) at ``poses``; WORLD anchors are already in world coordinates."""
    out = np.array(anchor, dtype=float, copy=True)
    moving = body >= 0
    q = poses[body[moving]]
    c, s = np.cos(q[:, 2]), np.sin(q[:, 2])
    a = anchor[moving]
    out[moving, 0] = q[:, 0] + c * a[:, 0] - s * a[:, 1]
    out[moving, 1] = q[:, 1] + s * a[:, 0] + c * a[:, 1]
    return out


def link_segments(links: Sequence, poses: np.ndarray) -> np.ndarray:
    """(3 k, 2) points of the k links' segments anchor 1 -> anchor 2 at ``poses``, each followed
    by a NaN row (one polyline for plotting)."""
    body1 = np.array([link.body1 for link in links], dtype=np.int64)
    body2 = np.array([link.body2 for link in links], dtype=np.int64)
    a1 = np.array([link.anchor1 for link in links], dtype=float).reshape(-1, 2)
    a2 = np.array([link.anchor2 for link in links], dtype=float).reshape(-1, 2)
    out = np.full((3 * len(links), 2), np.nan)
    out[0::3] = anchor_points(poses, body1, a1)
    out[1::3] = anchor_points(poses, body2, a2)
    return out
