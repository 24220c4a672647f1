"""Fast pairs asked of the contact finder: the first touch of features that no contact watches.

Why: the event search (runtime.step.events) watches the kernel gaps of the contacts found at a
step's start. A body that turns fast within the step (spun by an impact, or spinning) can bring
another corner round onto the other body: a feature pair that was no contact at the start (it
faced away, or the nearest features were two corners), and that the contact finder no longer
reports once it is deep (a deep overlap is no plausible contact). So such pairs are asked of
the contact finder at instants closer than settings.FAST_PAIR of the smaller half width of
their relative travel, and the first touch is found by bisection on its gaps.
"""

from __future__ import annotations

import math

import numpy as np

from runtime import settings
from runtime.collide import sweep
from runtime.collide.broadphase import candidate_pairs
from runtime.step.clearance import clear


class IslandsMeet(Exception):
    """Two islands' bodies that no contact joined at the step's start meet within it: the step
    is done again with every body in one island (runtime.step.stepper)."""


def samples(search, b1: np.ndarray, b2: np.ndarray, q0: np.ndarray, q1: np.ndarray) -> np.ndarray:
    """Samples over a step for each pair (b1, b2) of ``search`` (an EventSearch: its radii and
    half widths): 0 for a slow pair, else enough that the pair moves at most
    settings.FAST_PAIR of the smaller half width between two (at least 2, at most 4096)."""
    radii, half = search.radii, search.half_width
    moved = (q1[b1, :2] - q0[b1, :2]) - (q1[b2, :2] - q0[b2, :2])
    travel = np.hypot(moved[:, 0], moved[:, 1])
    travel += np.abs(q1[b1, 2] - q0[b1, 2]) * radii[b1]
    travel += np.abs(q1[b2, 2] - q0[b2, 2]) * radii[b2]
    size = np.minimum(half[b1], half[b2])
    size = np.where(np.isfinite(size), size, np.maximum(radii[b1], radii[b2]))
    steps = np.clip(np.ceil(travel / (settings.FAST_PAIR * size)), 2, 4096)
    return np.where(travel > settings.FAST_PAIR * size, steps, 0).astype(int)


def first_touch(
    search, i: int, j: int, traj, until: float, known: set, count: int = 1
) -> float | None:
    """The first instant in (0, until] at which bodies i and j touch at a contact not
    ``known``, after being clear of each other: the contact finder asked at ``count``
    instants along ``traj``, then bisection on its smallest gap of such contacts (the
    distance between the bodies, whichever features are nearest), to the gap an impact
    location reaches or to the time resolution; None if they do not touch again."""
    touch = search.touch

    def depth(t: float) -> float:
        found = search.collider.pair(i, j, traj.at(t)[0], touch)
        keys = search.collider.keys(found).tolist()
        gaps = [g for key, g in zip(keys, found.gap.tolist(), strict=True) if key not in known]
        return min(gaps, default=math.inf)

    lo, clear = 0.0, depth(0.0) > 0  # touching at the start (just after an impact): not yet
    for s in range(1, count + 1):
        hi = until * s / count
        d_hi = depth(hi)
        if d_hi > 0:
            lo, clear = hi, True
        elif clear:
            break
    else:
        return None
    time_tol = settings.TIME_EPS * np.finfo(float).eps * until
    for _ in range(settings.LOCATE_ITERATIONS):
        if d_hi >= -settings.TOUCH_LOCATE * touch or hi - lo <= time_tol:
            break
        mid = 0.5 * (lo + hi)
        d = depth(mid)
        if d > 0:
            lo = mid
        else:
            hi, d_hi = mid, d
    return hi


def unwatched_meetings(
    search, frame, q0: np.ndarray, q1: np.ndarray, h: float, island_of_body, trajectory
) -> dict[int, float]:
    """{island: first touch} of the pairs with a fast body at a contact the frame does not
    watch: pairs no watched contact joins (corner against corner at the start, or a body
    swinging its far end round onto the body it rests on), and other features of joined pairs
    (a spinning polygon between two discs brings another corner round onto the disc one corner
    watches); a pair of two islands that meet raises :class:`IslandsMeet`. Pairs whose unwatched
    features are too far apart to touch within the step (runtime.step.clearance) are skipped.
    ``trajectory(island)``: the island's trajectory; ``q0``, ``q1``: the trial's end poses."""
    radii = search.radii
    fast = sweep.displacement(q0, q1, radii) > settings.FAST_PAIR * search.half_width
    if not fast.any():
        return {}
    active = island_of_body >= 0
    usable = active | search.collider.fixed
    first, second = candidate_pairs(q0[:, :2], radii + frame.margin, ~active)
    keep = usable[first] & usable[second] & (fast[first] | fast[second])
    first, second = first[keep], second[keep]
    counts = samples(search, first, second, q0, q1)
    known = set(frame.keys.tolist())
    tables, c = search.collider.finder.tables, frame.contacts
    out: dict[int, float] = {}
    for i, j, count in zip(first.tolist(), second.tolist(), counts.tolist(), strict=True):
        if count == 0 or clear(
            i, j, q0, q1, frame.margin, radii, search.deepest, search.touch, tables.rows,
            tables.body_start, c.body1, c.body2, c.feature,
        ):  # fmt: skip
            continue  # no feature pair that no contact has can come close enough to touch
        gi, gj = int(island_of_body[i]), int(island_of_body[j])
        g = gi if gi >= 0 else gj
        traj = trajectory(g)
        t = first_touch(search, i, j, traj, h, known, count)
        if t is None:
            continue
        if gi >= 0 and gj >= 0 and gi != gj and trajectory(gj) is not traj:
            raise IslandsMeet
        out[g] = min(out.get(g, t), t)
    return out
