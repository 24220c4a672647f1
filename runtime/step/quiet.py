"""Whether a trial step is quiet -- nothing for the event search to find -- in one compiled call.

Why: most steps of most scenes have no impact in them (a disc rolling in a bowl, a pile at
rest, a ball between bounces), yet the event search (runtime.step.events) builds island labels,
per-island trajectories and brackets in Python to find nothing, and the step checks whether a
body outran its margin: tens of microseconds a step, several times the physics of a small
scene. This check looks at the same numbers -- the trial's end state, the watched contacts'
d and d' there by the same generated kernels (runtime.solve.kernel_set.gaps_by_case) -- and
says "quiet" only where every test the search and the step make is clear with room to spare:

* no body moved farther than its margin (else runtime.step.stepper widens the contacts);
* no body is fast (settings.FAST_PAIR: the search then samples pairs and looks for unwatched
  meetings), and no watched pair moved fast against each other;
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
from runtime.compiled import njit
from runtime.solve.kernel_set import by_case, gaps_by_case
from runtime.step.classify import LIFTING, OPEN, SEPARATING

SLACK = 1e-9  # relative: the room a distance test keeps, for rounding of the NumPy twins
# (runtime.collide.sweep, runtime.step.pair_scan) that the search computes the same tests with


@njit
def _moved(q0, q1, radii, i):
    """How far the farthest point of body i moved (runtime.collide.sweep.displacement)."""
    dx, dy = q1[i, 0] - q0[i, 0], q1[i, 1] - q0[i, 1]
    return math.sqrt(dx * dx + dy * dy) + abs(q1[i, 2] - q0[i, 2]) * radii[i]


@njit
def is_quiet(
    q0, q1, v1, margin, radii, half_width, switches, case, body1, body2, geometry, static2,
    modes, gap0, rate0, touch, creep, fast_pair,
):  # fmt: skip
    """True if the trial step from poses ``q0`` to the state (q1, v1) has nothing for the
    event search to find (see the module docstring). ``modes``, ``gap0``, ``rate0``: the
    frame's contacts at the start; ``margin``: the frame's per-body margins."""
    n = q0.shape[0]
    grow = 1.0 + SLACK
    for i in range(n):
        moved = _moved(q0, q1, radii, i) * grow  # (not finite: not quiet, as NaN fails all)
        if not (moved == 0.0 or (moved <= margin[i] and moved <= fast_pair * half_width[i])):
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
        travel = (_moved(q0, q1, radii, i) + _moved(q0, q1, radii, j)) * grow
        if travel > fast_pair * size:  # a fast pair: the search samples it
            return False
    return True
