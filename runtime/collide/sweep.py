"""Swept contact search: the contacts that can close within a step, so fast bodies cannot tunnel.

Why this module exists: the contact finder reports features within a fixed tolerance of each
other, so a disc moving 1.7 m per step is never seen next to a 1 cm wall: before the step it is
too far, after the step it is through. Here each body gets a margin, a bound on how far any of its
points can move in the step (speed of the centre plus |w| times the bounding radius, times the
step, doubled, plus |g| h^2 for the change of velocity), and the contact tolerance of a pair is
inflated by the margins of its two bodies. Every feature pair that can meet during the step is
then among the contacts found at its start, so its kernel gap can be watched over the step and its
time of impact located (runtime.step.events). If a body still moves farther than its margin (a
large contact force), :func:`outran` says so and the search is repeated with wider margins.
"""

from __future__ import annotations

import math

import numpy as np

from runtime.compiled import njit


def margins(
    velocities: np.ndarray, h: float, radii: np.ndarray, moving: np.ndarray, gravity: float
) -> np.ndarray:
    """(n,) bound on the distance any point of each body moves in a step of length h
    (``moving``: 1.0 for moving bodies, 0.0 for fixed ones; ``gravity``: |g|)."""
    out = np.empty(len(radii))
    _margins(velocities, float(h), radii, moving, float(gravity), out)
    return out


@njit
def _margins(v, h, radii, moving, gravity, out):
    """:func:`margins` in one compiled loop (NumPy's seven array operations cost ~5 us a step
    for a scene of a few bodies)."""
    for i in range(radii.size):
        speed = math.hypot(v[i, 0], v[i, 1]) + abs(v[i, 2]) * radii[i]
        out[i] = (2.0 * speed * h + gravity * h * h) * moving[i]


def displacement(start: np.ndarray, end: np.ndarray, radii: np.ndarray) -> np.ndarray:
    """(n,) distance moved by the farthest point of each body between two poses (to first
    order in the rotation)."""
    d = end - start
    return np.hypot(d[:, 0], d[:, 1]) + np.abs(d[:, 2]) * radii


def outran(start: np.ndarray, end: np.ndarray, radii: np.ndarray, margin: np.ndarray) -> bool:
    return bool((displacement(start, end, radii) > margin).any())
