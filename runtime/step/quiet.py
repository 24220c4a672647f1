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
  touch gap) and is not a dip candidate (approaching at the start, moving apart at the end)
  unless the search would drop it unchecked (:func:`_screened`: its Hermite cubic stays far
  above 0); a touching one (separating or lifting) ends open;
* where both bodies of a watched contact fly free (no resting contact: constant acceleration,
  so RK4 moves them along parabolas, exactly up to rounding) and its circles are at their
  centres of mass, its edge on a fixed body, its gap over the whole step is known in closed
  form (:func:`least_gap_in_flight`): above the floor at every instant, neither a dip nor a
  fast pair needs the search -- a disc flying off a cylinder, a ball falling past a floor;
* no watched pair of a body with several features (a corner, an arc's ends) closed in, whose
  pair the search asks the contact finder again; and no touching contact of such a body may
  have run off the end of its feature (runtime.step.clearance.may_slide_off), whose island (a
  resting one) or pair (one moving apart) the search asks again.

Anything else goes to the search, which decides as before: the check only skips work whose
outcome is known, so a quiet step is the same step, to the bit.
"""

from __future__ import annotations

import math

import numpy as np

from generated.compiled import circle_circle, circle_edge
from runtime import settings
from runtime.collide.broadphase import sweep
from runtime.collide.candidates import CIRCLE_CIRCLE, CIRCLE_EDGE
from runtime.compiled import leaf, njit
from runtime.solve.kernel_set import by_case, gaps_by_case
from runtime.step.classify import LIFTING, OPEN, RESTING, SEPARATING
from runtime.step.clearance import clear, may_slide_off, moved
from runtime.step.events import cubic_roots, hermite_coefficients

SLACK = 1e-9  # relative: the room a distance test keeps, for rounding of the NumPy twins
# (runtime.collide.sweep, runtime.step.pair_scan) that the search computes the same tests with


@leaf
def _motion(q0, v0, a0, fixed, b):
    """Pose, velocity and acceleration of body b in free flight (a fixed body: its pose, the
    rest 0)."""
    if fixed[b]:
        return q0[b, 0], q0[b, 1], q0[b, 2], 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    return (
        q0[b, 0], q0[b, 1], q0[b, 2], v0[b, 0], v0[b, 1], v0[b, 2], a0[b, 0], a0[b, 1], a0[b, 2],
    )  # fmt: skip


@leaf
def _pose_at(m, t):
    """The pose at time t of a body with :func:`_motion` m: q + v t + a t^2 / 2."""
    return (
        m[0] + t * (m[3] + 0.5 * t * m[6]),
        m[1] + t * (m[4] + 0.5 * t * m[7]),
        m[2] + t * (m[5] + 0.5 * t * m[8]),
    )


@leaf
def _circle_path(m, still, cx, cy):
    """(start, velocity, half the acceleration) of the point (cx, cy) (body axes) of a body with
    :func:`_motion` m (``still``: a fixed body); None where it is not a parabola (a point off
    the centre of mass of a moving body turns with it)."""
    if still:
        c, s = math.cos(m[2]), math.sin(m[2])
        return (m[0] + c * cx - s * cy, m[1] + s * cx + c * cy, 0.0, 0.0, 0.0, 0.0), True
    if cx != 0.0 or cy != 0.0:
        return (0.0, 0.0, 0.0, 0.0, 0.0, 0.0), False
    return (m[0], m[1], m[3], m[4], 0.5 * m[6], 0.5 * m[7]), True


@njit
def least_gap_in_flight(k, case, body1, body2, geometry, q0, v0, a0, fixed, h):
    """The least gap of contact k over a step of length h from poses ``q0``, velocities ``v0``
    and accelerations ``a0``, for a contact whose bodies fly free (the caller checks: no
    resting contact, so their accelerations stay ``a0`` at every RK4 stage and their poses
    follow q(t) = q + v t + a t^2 / 2); -inf where that does not give it in closed form
    (another case, a circle off its moving body's centre of mass, an edge on a moving body).

    The gaps are the generated kernels' (generated/compiled); only the instants where the
    least one can lie come from the motion: for a circle on a fixed edge, d is then exactly
    quadratic in t (d''' = 0), d + d' t + d'' t^2 / 2 with d, d', d'' at the start, least at an
    end or its vertex; for two circles, the ends and the instants where the squared distance of
    their centres, a quartic in t, is stationary. Less a rounding allowance (1e-12 of the
    lengths involved): the integrator's states are these parabolas only up to rounding."""
    g = geometry[k]
    i, j = body1[k], body2[k]
    m1, m2 = _motion(q0, v0, a0, fixed, i), _motion(q0, v0, a0, fixed, j)
    one, ok1 = _circle_path(m1, fixed[i], g[0], g[1])
    if not ok1:
        return -math.inf
    if case[k] == CIRCLE_EDGE:
        if not fixed[j]:
            return -math.inf
        cx1, cy1, r1, ex2, ey2, nx2, ny2 = g[0], g[1], g[2], g[3], g[4], g[5], g[6]
        d0 = circle_edge.gap(*m1[:3], *m2[:3], cx1, cy1, r1, ex2, ey2, nx2, ny2)
        rate = circle_edge.gap_velocity(*m1[:6], *m2[:6], cx1, cy1, ex2, ey2, nx2, ny2)
        half = 0.5 * circle_edge.gap_acceleration(*m1, *m2, cx1, cy1, ex2, ey2, nx2, ny2)
        least = min(d0, d0 + h * (rate + h * half))
        if half > 0.0 and 0.0 < -rate / (2.0 * half) < h:
            t = -rate / (2.0 * half)
            least = min(least, d0 + t * (rate + t * half))
        scale = abs(m1[0]) + abs(m1[1]) + abs(m2[0]) + abs(m2[1]) + abs(g[3]) + abs(g[4]) + g[2]
    elif case[k] == CIRCLE_CIRCLE:
        two, ok2 = _circle_path(m2, fixed[j], g[3], g[4])
        if not ok2:
            return -math.inf
        ax, ay = one[0] - two[0], one[1] - two[1]  # the centres' difference A + B t + C t^2
        bx, by = one[2] - two[2], one[3] - two[3]
        cx, cy = one[4] - two[4], one[5] - two[5]
        times = cubic_roots(  # where |A + B t + C t^2|^2 is stationary: (A + B t + C t^2).(B + 2 C t)
            ax * bx + ay * by, bx * bx + by * by + 2.0 * (ax * cx + ay * cy),
            3.0 * (bx * cx + by * cy), 2.0 * (cx * cx + cy * cy), 0.0, h,
        )  # fmt: skip
        times.append(0.0)
        times.append(h)
        least = math.inf
        for t in times:
            p1, p2 = _pose_at(m1, t), _pose_at(m2, t)
            least = min(least, circle_circle.gap(*p1, *p2, g[0], g[1], g[2], g[3], g[4], g[5]))
        scale = abs(one[0]) + abs(one[1]) + abs(two[0]) + abs(two[1]) + g[2] + abs(g[5])
    else:
        return -math.inf
    travel = (math.hypot(one[2], one[3]) + h * math.hypot(one[4], one[5])) * h
    return least - 1e-12 * (scale + travel)


@njit
def _screened(g0, r0, g1, r1, h):
    """Whether the event search drops this open contact (d' < 0 at the start, > 0 at the end)
    without checking its real gap: runtime.step.events.find_dip looks no further where the
    Hermite cubic through (d, d') at both ends keeps its minimum farther from 0 than
    settings.DIP_SCREEN of its variation. Taken here with the least of the same cubic over the
    step (its ends included: no higher than the search's interior minimum) and room of 1e-9 of
    the terms for the search's own rounding -- a resting pile's contacts that drifted just past
    the hold gap and creep back and forth by far less than it."""
    c0, c1, c2, c3 = hermite_coefficients(g0, r0, g1, r1, h)
    low = min(g0, g1)
    for s in cubic_roots(c1, 2.0 * c2, 3.0 * c3, 0.0, 0.0, 1.0):  # its stationary points
        low = min(low, c0 + s * (c1 + s * (c2 + s * c3)))
    screen = settings.DIP_SCREEN
    room = 1e-9 * (abs(g0) + abs(g1) + h * (abs(r0) + abs(r1)))
    return (1.0 + screen) * low - screen * max(g0, g1) > room


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
    modes, gap0, rate0, touch, creep, fast_pair, fixed, depths, rows, body_start, feature, v0,
    a0, h,
):  # fmt: skip
    """True if the trial step from poses ``q0`` to the state (q1, v1) has nothing for the
    event search to find (see the module docstring). ``modes``, ``gap0``, ``rate0``: the
    frame's contacts at the start (``feature``: their features); ``margin``: the frame's
    per-body margins; ``fixed``: fixed bodies; ``depths``, ``rows``, ``body_start``: the
    deepest contact on each body and the scene's feature tables (runtime.step.clearance);
    ``v0``, ``a0``, ``h``: the trial's start velocities, start accelerations and length."""
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
    for k in range(m):
        if modes[k] != OPEN and may_slide_off(k, q0, q1, radii, switches, body1, body2,
                                              feature, rows, body_start, touch):  # fmt: skip
            return False
    watched = 0
    for k in range(m):
        if modes[k] == OPEN or modes[k] == SEPARATING or modes[k] == LIFTING:
            watched += 1
    if watched == 0:
        return True
    gap1, rate1 = np.empty(m), np.empty(m)
    gaps_by_case(q1, v1, by_case(case), body1, body2, geometry, static2, gap1, rate1)
    floor = settings.TOUCH_LOCATE * touch
    rests = np.zeros(n, np.bool_)
    for k in range(m):
        if modes[k] == RESTING:
            rests[body1[k]] = rests[body2[k]] = True
    for k in range(m):
        mode = modes[k]
        if not (mode == OPEN or mode == SEPARATING or mode == LIFTING):
            continue
        g0, r0, g1, v1k = gap0[k], rate0[k], gap1[k], rate1[k]
        if not (math.isfinite(g1) and math.isfinite(v1k) and math.isfinite(r0)):
            return False  # (the search takes a secant's rate for a rate that is not finite)
        if g1 <= floor:  # may have crossed (or returned to) d = 0
            return False
        i, j = body1[k], body2[k]
        closing = g1 <= g0 or r0 < 0.0
        if closing and (switches[i] or switches[j]):  # may meet at another feature
            return False
        # may have dipped below 0 between the ends (unless the search would not look)
        dip = mode == OPEN and r0 < 0.0 and v1k > -creep and not _screened(g0, r0, g1, v1k, h)
        size = min(half_width[i], half_width[j])
        if not math.isfinite(size):
            size = max(radii[i], radii[j])
        travel = (moved(q0, q1, radii, i) + moved(q0, q1, radii, j)) * grow
        sampled = travel > fast_pair * size  # a fast pair: the search samples it
        if (dip or sampled) and (  # unless it stays above the floor all through the step
            rests[i]
            or rests[j]
            or not least_gap_in_flight(k, case, body1, body2, geometry, q0, v0, a0, fixed, h)
            > floor
        ):
            return False
    return True
