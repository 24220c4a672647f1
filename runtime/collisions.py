"""Impacts: velocity jumps at contacts that approach, with the same A matrix as the forces.

Simultaneous policy: all touching contacts are solved together as an LCP on velocities,
A p + (1 + e) d'_- >= 0, p >= 0, p.(A p + (1 + e) d'_-) = 0, where d'_- are the gap velocities
before the impact and p the impulses; afterwards d'_+ = d'_- + A p >= -e d'_-. The restitution of a
contact is the larger of its two bodies' (as Box2D); below `bounce_speed` it is 0, so a bouncing
body comes to rest in finite time instead of chattering (no Zeno loop).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from runtime import lcp


def impact_velocities(
    dynamics, contacts: Sequence, rows, velocities: np.ndarray, bounce_speed: float
) -> np.ndarray:
    """Velocities (n, 3) just after resolving the impacts among `contacts`."""
    bodies = dynamics.scene.bodies
    restitution = np.array(
        [max(bodies[c.body1].restitution, bodies[c.body2].restitution) for c in contacts]
    )
    approach = -np.minimum(rows.gap_velocity, 0.0)
    restitution = np.where(approach > bounce_speed, restitution, 0.0)
    a_matrix, _, jm = dynamics.effective_mass_matrix(rows)
    impulses = lcp.solve(a_matrix, (1.0 + restitution) * rows.gap_velocity)
    return velocities + (jm.T @ impulses).reshape(-1, 3)
