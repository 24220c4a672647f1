"""Swept contact search: the contacts that can close within a step, so fast bodies cannot tunnel.

Why this module exists: the contact finder reports features within a fixed tolerance of each
other, so a disc moving 1.7 m per step is never seen next to a 1 cm wall: before the step it is
too far, after the step it is through. Here each body gets a margin, a bound on how far any of its
points can move in the step (speed of the centre plus |w| times the bounding radius, times the
step, doubled, plus |g| h^2 for the change of velocity), and the contact tolerance of a pair is
inflated by the margins of its two bodies. Every feature pair that can meet during the step is
then among the contacts found at its start, so its kernel gap can be watched over the step and its
time of impact located (runtime.step.impact_time). If a body still moves farther than its margin (a
large contact force), :func:`outran` says so and the search is repeated with wider margins.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from runtime.collide import contacts as _contacts


def margins(
    velocities: np.ndarray, h: float, radii: np.ndarray, moving: np.ndarray, gravity: float
) -> np.ndarray:
    """(n,) bound on the distance any point of each body moves in a step of length h
    (``moving``: 1.0 for moving bodies, 0.0 for fixed ones; ``gravity``: |g|)."""
    speed = np.hypot(velocities[:, 0], velocities[:, 1]) + np.abs(velocities[:, 2]) * radii
    return (2.0 * speed * h + gravity * h * h) * moving


def displacement(start: np.ndarray, end: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """(n,) distance moved by the farthest point of each body between two poses (to first
    order in the rotation)."""
    d = end - start
    return np.hypot(d[:, 0], d[:, 1]) + np.abs(d[:, 2]) * radii


def outran(start: np.ndarray, end: np.ndarray, radii: np.ndarray, margin: np.ndarray) -> bool:
    return bool(np.any(displacement(start, end, radii) > margin))


def swept_contacts(scene, poses: np.ndarray, margin: np.ndarray) -> list:
    """Contacts at ``poses`` whose gap is at most the scene's contact tolerance plus the margins
    of their two bodies.  Transitional: as runtime.collide.contacts.Contact objects, for the
    current engine (``scene.contacts(poses, margins=margin)`` gives them as Contacts)."""
    return _contacts.contact_objects(scene.contacts(poses, margins=margin))


def pair_contacts(
    shapes: list, fixed: list[bool], i: int, j: int, poses: np.ndarray, tolerance: float
) -> list:
    """The contacts between bodies i < j only, with the scene's body indices.  Transitional:
    Contact objects, for the current engine."""
    found = _contacts.find_contact_objects(
        [shapes[i], shapes[j]], poses[[i, j]], [fixed[i], fixed[j]], tolerance
    )
    index = (i, j)
    return [replace(c, body1=index[c.body1], body2=index[c.body2]) for c in found]
