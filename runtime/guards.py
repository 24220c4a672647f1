"""Checks after each step that stop a run which has gone wrong, instead of letting it go on.

Why: a time step that is too large does not fail loudly by itself. Bodies sink into each other
(an impact missed between two steps) and may fall through; an explicit method pumps energy into
a scene with no energy source. Both produce finite numbers that look like a simulation. These
guards turn them into a :class:`runtime.simulation.SimulationError` naming the step, the time,
the bodies and the size of the problem. Both limits are relative, so they hold for scenes of
any size:

* ``penetration``: the deepest overlap of two bodies, in units of the smaller body's bounding
  radius (a located impact leaves ~1e-12 m; 1e-2 of a body's size is a missed impact);
* ``energy_growth``: the rise of the mechanical energy above its value at t = 0, in units of the
  scene's energy scale (kinetic energy + m |g| x the scene's height, summed over the moving
  bodies). Frictionless contacts do no work and restitution <= 1, so physics only takes energy
  out; a rise is integration error, and a rise of half the scale is a blow-up.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Guards:
    """Limits past which a run stops (None: not checked)."""

    penetration: float | None = 1e-2
    energy_growth: float | None = 0.5

    def __post_init__(self) -> None:
        for name in ("penetration", "energy_growth"):
            value = getattr(self, name)
            if value is not None and not (np.isfinite(value) and value > 0):
                raise ValueError(f"Guards: {name} must be a finite number > 0 or None, got {value}")


def contact_names(scene, contacts) -> str:
    """'a/b, c/d': the body pairs of ``contacts``, sorted, each once ('none' if there are none)."""
    names = sorted({f"{scene.bodies[c.body1].name}/{scene.bodies[c.body2].name}" for c in contacts})
    return ", ".join(names) or "none"


def energy_scale(scene, radii: np.ndarray) -> float:
    """Sum over the moving bodies of (kinetic energy + m |g| (H + 2 r)) at t = 0, where H is the
    height the scene spans (every body's centre +- its bounding radius r)."""
    poses, velocities = scene.poses(), scene.velocities()
    y, g = poses[:, 1], float(np.hypot(*scene.gravity))
    height = float(np.max(y + radii) - np.min(y - radii))
    total = 0.0
    for body, r, v in zip(scene.bodies, radii, velocities, strict=True):
        if not body.fixed:
            kinetic = 0.5 * body.mass * (v[0] ** 2 + v[1] ** 2) + 0.5 * body.inertia * v[2] ** 2
            total += kinetic + body.mass * g * (height + 2.0 * r)
    return total


def deepest_overlap(frame, radii: np.ndarray) -> tuple[float, float, object] | None:
    """(depth, depth / the smaller bounding radius, contact) of the frame's deepest overlap
    relative to body size, or None if nothing overlaps."""
    if frame.rows is None:
        return None
    depth = -np.asarray(frame.rows.gap, dtype=float)
    if not np.any(depth > 0.0):
        return None
    size = np.array([min(radii[c.body1], radii[c.body2]) for c in frame.contacts])
    k = int(np.argmax(depth / size))
    return float(depth[k]), float(depth[k] / size[k]), frame.contacts[k]
