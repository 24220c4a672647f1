"""Whether a trial step is quiet -- nothing for the event search to find -- in one compiled call.

Why: most steps of most scenes have no impact in them (a disc rolling in a bowl, a pile at
rest, a ball between bounces), yet the event search (runtime.step.events) builds island labels,
per-island trajectories and brackets in Python to find nothing, and the step checks whether a
body outran its margin: tens of microseconds a step, several times the physics of a small
scene. This check looks at the same numbers -- the trial's end state, the watched contacts'
d and d' there by the same generated kernels (runtime.solve.kernel_set.gaps_by_case) -- and
says "quiet" only where every test the search and the step make is clear with room to spare:

* no body moved farther than its margin (else runtime.step.stepper widens the contacts);
* no watched pair moved fast against each other (settings.FAST_PAIR: the search samples its
  gaps); a fast body is allowed where each pair the search would sample for unwatched meetings
  (runtime.step.pair_scan) is clear (runtime.step.clearance: every feature pair that no
  contact of the frame has is too far apart to touch), so no sample can find a new contact --
  a disc swinging fast in a bowl touches it only where its contact is;
* no watched contact can have crossed d = 0: an open one ends open (d > a thousandth of the
  touch gap) and is not a dip candidate (approaching at the start, moving apart at the end);
  a touching one (separating or lifting) ends open;
* no watched pair of a body with several features (a corner, an arc's ends) closed in, whose
  pair the search asks the contact finder again.

Anything else goes to the search, which decides as before: the check only skips work whose
outcome is known, so a quiet step is the same step, to the bit.
"""

from __future__ import annotations

import math

import numpy as np

from runtime import settings
from runtime.collide.broadphase import sweep
from runtime.compiled import njit
from runtime.solve.kernel_set import by_case, gaps_by_case
from runtime.step.classify import LIFTING, OPEN, SEPARATING
from runtime.step.clearance import clear, moved

SLACK = 1e-9  # relative: the room a distance test keeps, for rounding of the NumPy twins
# (runtime.collide.sweep, runtime.step.pair_scan) that the search computes the same tests with


@njit
def _fast_pairs_clear(
    q0, q1, margin, radii, half_width, fixed, fast_pair, touch, depths, rows, body_start, body1,
    body2, feature,
):  # fmt: skip
    """Whether every pair the event search would sample for unwatched meetings
    (runtime.step.pair_scan.unwatched_meetings: bounding circles widened by the margins overlap,
    and the pair moved against each other more than ``fast_pair`` of the smaller half width)
    is :func:`clear`."""
    reach = (radii + margin) * (1.0 + SLACK)
    pairs = sweep(q0[:, 0].copy(), q0[:, 1].copy(), reach, fixed)
    for p in range(pairs.shape[0]):
        i, j = pairs[p, 0], pairs[p, 1]
        dx = (q1[i, 0] - q0[i, 0]) - (q1[j, 0] - q0[j, 0])
        dy = (q1[i, 1] - q0[i, 1]) - (q1[j, 1] - q0[j, 1])
        travel = math.hypot(dx, dy) + abs(q1[i, 2] - q0[i, 2]) * radii[i]
        travel = (travel + abs(q1[j, 2] - q0[j, 2]) * radii[j]) * (1.0 + SLACK)
        size = min(half_width[i], half_width[j])
        if not math.isfinite(size):
            size = max(radii[i], radii[j])
        if travel > fast_pair * size and not clear(
            i, j, q0, q1, margin, radii, depths, touch, rows, body_start, body1, body2, feature
        ):
            return False
    return True


@njit
def is_quiet(
    q0, q1, v1, margin, radii, half_width, switches, case, body1, body2, geometry, static2,
    modes, gap0, rate0, touch, creep, fast_pair, fixed, depths, rows, body_start, feature,
):  # fmt: skip
    """True if the trial step from poses ``q0`` to the state (q1, v1) has nothing for the
    event search to find (see the module docstring). ``modes``, ``gap0``, ``rate0``: the
    frame's contacts at the start (``feature``: their features); ``margin``: the frame's
    per-body margins; ``fixed``: fixed bodies; ``depths``, ``rows``, ``body_start``: the
    deepest contact on each body and the scene's feature tables (runtime.step.clearance)."""
    n = q0.shape[0]
    grow = 1.0 + SLACK
    fast = False
    for i in range(n):
        far = moved(q0, q1, radii, i) * grow  # (not finite: not quiet, as NaN fails all)
        if not (far == 0.0 or far <= margin[i]):
            return False
        fast |= far > fast_pair * half_width[i]
    if fast and not _fast_pairs_clear(
        q0, q1, margin, radii, half_width, fixed, fast_pair, touch, depths, rows, body_start,
        body1, body2, feature,
    ):  # fmt: skip
        return False
    m = case.size
    watched = 0
    for k in range(m):
        if modes[k] == OPEN or modes[k] == SEPARATING or modes[k] == LIFTING:
            watched += 1
    if watched == 0:
        return True
    gap1, rate1 = np.empty(m), np.empty(m)
    gaps_by_case(q1, v1, by_case(case), body1, body2, geometry, static2, gap1, rate1)
    floor = settings.TOUCH_LOCATE * touch
    for k in range(m):
        mode = modes[k]
        if not (mode == OPEN or mode == SEPARATING or mode == LIFTING):
            continue
        g0, v0, g1, v1k = gap0[k], rate0[k], gap1[k], rate1[k]
        if not (math.isfinite(g1) and math.isfinite(v1k) and math.isfinite(v0)):
            return False  # (the search takes a secant's rate for a rate that is not finite)
        if g1 <= floor:  # may have crossed (or returned to) d = 0
            return False
        if mode == OPEN and v0 < 0.0 and v1k > -creep:  # may have dipped below 0 in between
            return False
        i, j = body1[k], body2[k]
        closing = g1 <= g0 or v0 < 0.0
        if closing and (switches[i] or switches[j]):  # may meet at another feature
            return False
        size = min(half_width[i], half_width[j])
        if not math.isfinite(size):
            size = max(radii[i], radii[j])
        travel = (moved(q0, q1, radii, i) + moved(q0, q1, radii, j)) * grow
        if travel > fast_pair * size:  # a fast pair: the search samples it
            return False
    return True
