"""Events: where, inside a trial step, a watched contact's gap d first reaches 0, per island.

Why: an impact handled at the end of a step happens after the bodies have sunk into each other
(by up to the approach speed times the step), which loses energy, breaks bounce heights and
lets fast bodies tunnel. The engine integrates a trial step, looks at the gap d and its rate d'
(both from the generated kernels) of every watched contact, and where d reaches 0 finds the
instant and restarts that island from there.

* :func:`brackets` decides from (d, d') at both ends which contacts cross zero in the step and
  gives each an interval and a first guess: the root of the cubic Hermite interpolant of d (exact
  for free flight, where d is a quadratic in time), and a touching contact that separates and
  comes back. A contact that dips below zero and comes back within the step (a near graze) is
  checked against the real gap where the cubic's minimum is near zero (:func:`find_dip`).
* A *fast pair*, one whose bodies move against each other by more than a fraction
  (settings.FAST_PAIR) of the smaller one's half width within the step, is sampled at enough
  instants that it cannot pass through the other body between two samples (a cubic fit of the
  ends misses two discs passing through each other: their gap is positive at both ends).
* :func:`locate` refines a bracket by safeguarded Newton on d(t), with the kernel's exact d' as
  the slope: each evaluation re-integrates the island's step from its start to t, so the restart
  state is a genuine integrator state with d = 0 (to the located gap), not an interpolation.
* :class:`EventSearch` puts them together: per island, the earliest located impact that the
  contact finder confirms (a kernel's gap is that of a whole line or circle: beyond an edge's or
  arc's end it can cross zero with nothing there) and that is not a graze (a tangent touch,
  d = 0 with d' = 0 up to rounding, which must not deflect a body skimming past); and, for the
  pairs that closed in, a feature the contact finder sees penetrating at the trial's end that
  was not watched at its start (the pair met at another feature within the step).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from runtime import settings
from runtime.collide.contact_keys import key_set, member
from runtime.compiled import leaf, njit
from runtime.step import clearance, pair_scan
from runtime.step.classify import LIFTING, SEPARATING

CROSS = "cross"  # open at the start, penetrating at the end
DIP = "dip"  # open at both ends, below zero in between
RETURN = "return"  # touching and separating at the start, penetrating at the end
SINK = "sink"  # touching and separating at the start by its mode, but closing from the start


@dataclass
class Bracket:
    """Watched contact ``index`` crosses d = 0 in (lo, hi) (times from the step start)."""

    index: int
    lo: float
    hi: float
    guess: float
    kind: str
    cubic: tuple[float, ...]  # the Hermite cubic of d over [t0, t0 + span], in s = (t - t0) / span
    t0: float
    span: float

    def curvature(self, t: float) -> float:
        """d'' at t from the cubic."""
        s = (t - self.t0) / self.span
        return float((2.0 * self.cubic[2] + 6.0 * self.cubic[3] * s) / self.span**2)


@leaf
def hermite_coefficients(g0, v0, g1, v1, h):
    """(c0, c1, c2, c3) of p(s) = sum c_k s^k, s = t / h, with p(0) = g0, p(1) = g1,
    dp/dt = v0 at 0 and v1 at h (compiled: the quiet check screens with the same cubic)."""
    c2 = 3.0 * (g1 - g0) - h * (2.0 * v0 + v1)
    c3 = 2.0 * (g0 - g1) + h * (v0 + v1)
    return g0, h * v0, c2, c3


@njit
def _poly(c0, c1, c2, c3, s):
    return c0 + s * (c1 + s * (c2 + s * c3))


@njit
def cubic_roots(c0, c1, c2, c3, lo, hi):
    """Real roots in [lo, hi] of c0 + c1 s + c2 s^2 + c3 s^3, sorted: the interval cut at the
    stationary points (the quadratic's roots), and bisection in every piece whose ends differ
    in sign (to the float resolution of s); a root exactly at a cut counts once."""
    cuts = [lo]
    a, b, c = 3.0 * c3, 2.0 * c2, c1  # the derivative a s^2 + b s + c
    if a != 0.0:
        disc = b * b - 4.0 * a * c
        if disc >= 0.0:
            q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
            for r in (q / a, c / q if q != 0.0 else q / a):
                if lo < r < hi:
                    cuts.append(r)
    elif b != 0.0 and lo < -c / b < hi:
        cuts.append(-c / b)
    cuts.append(hi)
    cuts.sort()
    roots = []
    for k in range(len(cuts) - 1):
        x0, x1 = cuts[k], cuts[k + 1]
        f0, f1 = _poly(c0, c1, c2, c3, x0), _poly(c0, c1, c2, c3, x1)
        if f0 == 0.0:
            if not roots or roots[-1] != x0:
                roots.append(x0)
            continue
        if k == len(cuts) - 2 and f1 == 0.0:
            roots.append(x1)
            continue
        if (f0 < 0.0) == (f1 < 0.0):
            continue
        for _ in range(200):
            mid = 0.5 * (x0 + x1)
            if mid <= x0 or mid >= x1:
                break
            fm = _poly(c0, c1, c2, c3, mid)
            if fm == 0.0:
                x0 = x1 = mid
                break
            if (fm < 0.0) == (f0 < 0.0):
                x0, f0 = mid, fm
            else:
                x1 = mid
        roots.append(0.5 * (x0 + x1))
    return roots


def _real_roots(c, lo: float, hi: float) -> list[float]:
    """Real roots in [lo, hi] of the polynomial with coefficients c (a sequence, lowest first,
    up to a cubic), sorted."""
    c0, c1, c2, c3 = (*(float(x) for x in c), 0.0, 0.0, 0.0)[:4]
    if not (c1 or c2 or c3):
        return []
    return list(cubic_roots(c0, c1, c2, c3, float(lo), float(hi)))


def _extremum(c, minimum: bool) -> float | None:
    """s in (0, 1) of the cubic's interior minimum (or maximum), if it has one."""
    for s in _real_roots((c[1], 2.0 * c[2], 3.0 * c[3]), 0.0, 1.0):
        curvature = 2.0 * c[2] + 6.0 * c[3] * s
        if 0.0 < s < 1.0 and (curvature > 0 if minimum else curvature < 0):
            return s
    return None


def _value(c, s: float) -> float:
    return float(c[0] + s * (c[1] + s * (c[2] + s * c[3])))


def _first_root(c, lo: float, hi: float) -> float:
    """First root of the cubic in [lo, hi] (s units); regula falsi if it finds none."""
    roots = _real_roots(c, lo, hi)
    if roots:
        return roots[0]
    a, b = _value(c, lo), _value(c, hi)
    return lo + (hi - lo) * a / (a - b) if a != b else 0.5 * (lo + hi)


def bracket_one(
    k: int, g0: float, v0: float, g1: float, v1: float, t0: float, span: float, touching: bool
) -> Bracket | None:
    """The bracket of contact k over [t0, t0 + span] from (d, d') at both ends, or None.
    A rate that is not finite (d' of two coincident circle centres: the normal, and so d', is
    undefined there) is taken as the secant's, so the interpolant stays finite."""
    if not (math.isfinite(v0) and math.isfinite(v1)):
        secant = (g1 - g0) / span
        v0 = v0 if math.isfinite(v0) else secant
        v1 = v1 if math.isfinite(v1) else secant
    c = hermite_coefficients(g0, v0, g1, v1, span)
    if touching:
        if g1 >= 0:
            return None
        top = _extremum(c, minimum=False)
        if top is None:  # no way out and back: d falls from the start (the caller decides
            # whether that is more than rounding: EventSearch.first)
            return Bracket(k, t0, t0 + span, t0 + 0.5 * span, SINK, c, t0, span)
        guess = t0 + _first_root(c, top, 1.0) * span
        return Bracket(k, t0 + top * span, t0 + span, guess, RETURN, c, t0, span)
    if g1 <= 0:
        return Bracket(k, t0, t0 + span, t0 + _first_root(c, 0.0, 1.0) * span, CROSS, c, t0, span)
    if not (v0 < 0 < v1):
        return None
    low = _extremum(c, minimum=True)
    if low is None or _value(c, low) >= 0:
        return None
    guess = t0 + _first_root(c, 0.0, low) * span
    return Bracket(k, t0, t0 + low * span, guess, DIP, c, t0, span)


def brackets(
    g0: np.ndarray,
    v0: np.ndarray,
    g1: np.ndarray,
    v1: np.ndarray,
    h: float,
    touching: np.ndarray,
    dips: bool = True,
) -> list[Bracket]:
    """The contacts whose gap reaches 0 during a step of length h, sorted by first guess.

    ``g0, v0`` are d and d' at the start, ``g1, v1`` at the end; ``touching`` marks contacts
    that touch (and separate) at the start: for them only a return to d < 0 counts. A DIP
    bracket's ``hi`` and a RETURN bracket's ``lo`` come from the cubic, so the caller must check
    the sign of the real d there. ``dips``: False leaves out the contacts open at both ends (a
    caller that checks their real gap, :func:`find_dip`).
    """
    dip = (v0 < 0) & (v1 > 0) if dips else False
    maybe = np.where(touching, g1 < 0, (g1 <= 0) | dip)
    found = []
    for k in np.flatnonzero(maybe).tolist():
        b = bracket_one(k, g0[k], v0[k], g1[k], v1[k], 0.0, h, bool(touching[k]))
        if b is not None:
            found.append(b)
    found.sort(key=lambda b: b.guess)
    return found


def find_dip(
    gap: Callable[[float], tuple[float, float]],
    k: int,
    t0: float,
    g0: float,
    v0: float,
    t1: float,
    g1: float,
    v1: float,
) -> Bracket | None:
    """The DIP bracket of contact k, open at t0 and t1 (d' < 0 at t0, d' > 0 at t1), if the
    real gap ``gap(t) -> (d, d')`` goes below 0 in between; None if not.

    The Hermite cubic alone misses a near graze: its error (span^4 / 384 times the fourth
    derivative of d, ~1e-5 of the bodies' size over a quarter half-width of travel) exceeds a
    shallow dip, and two discs passing at +-100 m/s with 1e-7 m of overlap went through
    unnoticed. So the real d is checked at the cubic's minimum whenever that minimum is within
    settings.DIP_SCREEN of its variation from 0, and the interval is narrowed to the side where
    the real d' changes sign, until the real d is <= 0 there (a dip: bracket [t0, t]) or the
    cubic's minimum is clearly positive."""
    for _ in range(settings.DIP_LEVELS):
        span = t1 - t0
        c = hermite_coefficients(g0, v0, g1, v1, span)
        s = _extremum(c, minimum=True)
        s = 0.5 if s is None else s
        low = _value(c, s)
        if low > settings.DIP_SCREEN * (max(g0, g1) - low):
            return None
        t = t0 + s * span
        g, v = gap(t)
        if g <= 0:
            return Bracket(k, t0, t, t0 + _first_root(c, 0.0, s) * span, DIP, c, t0, span)
        if not math.isfinite(v) or not t0 < t < t1:
            return None
        if v < 0:
            t0, g0, v0 = t, g, v
        else:
            t1, g1, v1 = t, g, v
    return None


def locate(
    gap: Callable[[float], tuple[float, float]],
    lo: float,
    hi: float,
    guess: float,
    *,
    gap_tol: float,
    time_tol: float,
    max_iterations: int = settings.LOCATE_ITERATIONS,
) -> tuple[float, float]:
    """(t, d(t)) with |d(t)| <= gap_tol, or d(t) <= 0 within time_tol of the crossing, for a gap
    function ``gap(t) -> (d, d')`` with d(lo) > 0 >= d(hi): Newton steps on d', bisection when a
    step leaves the bracket."""
    t = min(max(guess, lo), hi)
    best = (hi, -math.inf)
    for _ in range(max_iterations):
        d, rate = gap(t)
        if abs(d) <= gap_tol:
            return t, d
        if d > 0:
            lo = t
        else:
            hi, best = t, (t, d)
        if hi - lo <= time_tol:
            break
        step = t - d / rate if rate != 0 and math.isfinite(rate) else math.nan
        t = step if lo < step < hi else 0.5 * (lo + hi)
    if best[1] == -math.inf:
        best = (hi, gap(hi)[0])
    return best


def grazes(rate: float, curvature: float, dip: float) -> bool:
    """Whether a located zero of d is a graze, not an impact: d is at a minimum there (d'' > 0)
    and dips below 0 by at most ``dip`` (d'^2 / 2 d'', rounding level): a tangent touch, where
    d = 0 is met with d' = 0 up to rounding -- an impulse there would deflect a body that only
    skims past."""
    return rate < 0 < curvature and rate * rate <= 2.0 * curvature * dip


class EventSearch:
    """The first impact of each island within a trial step, for one scene's engine.

    ``collider``: pair contacts at a state (runtime.step.stepper.Collision); ``evaluator``:
    kernel rows (runtime.solve.rows.RowEvaluator); ``half_width`` (n,): each body's half width
    (inf for open chains); ``radii`` (n,): bounding radii; ``switches`` (n,): bodies with more
    than one feature, whose pairs can meet at another feature within a step; ``deepest`` (n,):
    the deepest contact the finder admits on each body (runtime.step.clearance).
    """

    def __init__(self, collider, evaluator, touch: float, radii, half_width, switches) -> None:
        self.collider, self.evaluator, self.touch = collider, evaluator, touch
        self.radii, self.half_width, self.switches = radii, half_width, switches
        self.deepest = clearance.deepest(collider.finder.tables)

    def first(
        self,
        frame,
        start: np.ndarray,
        trial_end: tuple[np.ndarray, np.ndarray],
        h: float,
        island_of_body: np.ndarray,
        trajectory: Callable[[int], object],
    ) -> dict[int, float]:
        """{island: time from the trial's start of its first impact} for the islands that have
        one. ``start``: the poses at the trial's start; ``trial_end``: the state at h of the
        whole trial; ``island_of_body``: island label per body (-1 for fixed bodies);
        ``trajectory(island)``: the island's own trajectory (t -> state) for locating."""
        meets = pair_scan.unwatched_meetings(
            self, frame, start, trial_end[0], h, island_of_body, trajectory
        )
        watched = frame.monitored
        if watched.size == 0:  # (resting contacts may still slide off their features)
            best: dict[int, float] = {}
            slid = self._slid_off(frame, start, h, best, island_of_body, trajectory)
            return self._join(meets, best, slid, set(), set(frame.keys.tolist()), {}, trajectory, h)
        contacts = frame.contacts.take(watched)
        # an oval's contact point moves over it: d at the end from its point found there, as
        # every other gap of an oval contact in the search (not the frame's osculating circle)
        ends = self.collider.refresh_ovals(contacts, trial_end[0])
        g1, v1 = self.evaluator.gap_and_rate(ends, *trial_end)
        g0, v0 = frame.rows.gap[watched], frame.rows.gap_velocity[watched]
        modes = frame.modes[watched]
        touching = (modes == SEPARATING) | (modes == LIFTING)
        island = self._islands(contacts, island_of_body)
        gaps: dict[int, Callable] = {}

        def gap_of(k: int) -> Callable:
            if k not in gaps:
                gaps[k] = self._gap_function(contacts, k, trajectory(int(island[k])))
            return gaps[k]

        fast, sampled_counts = self._fast_pairs(contacts, touching, start, trial_end[0], h, gap_of)
        sampled = sampled_counts > 0
        found = brackets(g0, v0, g1, v1, h, touching, dips=False)
        found = [b for b in found if not sampled[b.index]] + fast
        for k in np.flatnonzero(~touching & ~sampled & (g1 > 0) & (v0 < 0) & (v1 > 0)).tolist():
            real = lambda t, k=k: gap_of(k)(t)  # noqa: E731 (made on first use: most screen out)
            dip = find_dip(real, k, 0.0, g0[k], v0[k], h, g1[k], v1[k])
            if dip is not None:
                found.append(dip)
        found.sort(key=lambda b: b.guess)
        resting = key_set(frame.keys[frame.resting]) if found else None  # for _touches
        best: dict[int, float] = {}
        unconfirmed: dict[int, set] = {}
        at_best: dict[int, tuple[float, np.ndarray]] = {}

        def open_at_best(k: int, g: int) -> bool:
            """Whether contact k is open at its island's earliest impact so far: every watched
            contact's d there in one evaluation (a landing pile's event search asked ~30 of
            them, one by one, at the same instant)."""
            t = best[g]
            if g not in at_best or at_best[g][0] != t:
                q = trajectory(g).at(t)[0]
                at_best[g] = t, self.evaluator.gaps(self.collider.refresh_ovals(contacts, q), q)
            return at_best[g][1][k] > 0

        for bracket in found:
            k, g = bracket.index, int(island[bracket.index])
            hi = bracket.hi
            if g in best:
                if bracket.lo >= best[g] or open_at_best(k, g):
                    continue
                hi = min(hi, best[g])
            gap = target = gap_of(k)
            if bracket.kind == SINK:
                # lifting or separating by its mode, it closes from the start: contacts of a
                # falling 30-disc pile with mu = 1 (the frame's friction forces one of several,
                # the trial's, without them, another) sank from d = 4.3e-8 m to -1.7e-7 m and
                # from -5e-14 m to -8.6e-8 m. Located where d falls half the touch gap below
                # where it started (or below 0): an impact there, no new frame at the same state
                level = min(float(g0[k]), 0.0) - 0.5 * self.touch
                if gap(hi)[0] >= level:
                    continue  # rounding

                def target(t: float, level=level, real=gap) -> tuple[float, float]:
                    d, rate = real(t)
                    return d - level, rate

            if bracket.kind == RETURN and gap(bracket.lo)[0] <= 0:
                t, d = bracket.lo, 0.0  # it never really left: touching and approaching at lo
            else:
                t, d = locate(
                    target,
                    bracket.lo,
                    hi,
                    bracket.guess,
                    gap_tol=settings.TOUCH_LOCATE * self.touch,
                    time_tol=settings.TIME_EPS * np.finfo(float).eps * h,
                )
            if d > self.touch or grazes(
                gap(t)[1], bracket.curvature(t), settings.GRAZE * self.touch
            ):
                continue
            if self._touches(contacts, k, trajectory(g).at(t)[0], resting):
                best[g] = t
            else:
                unconfirmed.setdefault(g, set()).add(_pair(contacts, k))
        # may meet at another feature on the way (or turn to it); approaching at the start
        # counts too: two corners that slide past each other are nearer within the step than at
        # either end, and a corner's gap (a distance) cannot reach 0 where it crosses an edge
        closing = (g1 < g0) | (v0 < 0) | sampled
        switching = self.switches[contacts.body1] | self.switches[contacts.body2]
        # ... or moving apart, past the end of its feature: a corner lifting off a rounded
        # box's corner arc ran on past the arc's end, 1.3e-6 m into the side beyond it
        tables, c = self.collider.finder.tables, frame.contacts
        closing |= touching & clearance.sliding_off(
            start, trial_end[0], self.radii, self.switches, watched, c.body1, c.body2,
            c.feature, tables.rows, tables.body_start, self.touch,
        )  # fmt: skip
        for k in np.flatnonzero(closing & switching).tolist():
            unconfirmed.setdefault(int(island[k]), set()).add(_pair(contacts, k))
        for g, pairs in self._slid_off(frame, start, h, best, island_of_body, trajectory).items():
            unconfirmed.setdefault(g, set()).update(pairs)
        keys = set(self.collider.keys(contacts).tolist()) if unconfirmed else set()
        known = set(frame.keys.tolist()) if unconfirmed else set()
        counts = {_pair(contacts, k): int(sampled_counts[k]) for k in np.flatnonzero(sampled)}
        return self._join(meets, best, unconfirmed, keys, known, counts, trajectory, h)

    def _join(self, meets, best, unconfirmed, keys, known, counts, trajectory, h) -> dict:
        """``best`` with the unconfirmed pairs' new features (:meth:`_new_feature`) and the
        unwatched meetings: each island's earliest impact."""
        for g, pairs in unconfirmed.items():
            later = self._new_feature(pairs, keys, trajectory(g), best.get(g, h), known, counts)
            if later is not None:
                best[g] = later
        for g, t in meets.items():
            best[g] = min(best.get(g, t), t)
        return best

    def _slid_off(self, frame, start, h, best, island_of_body, trajectory) -> dict[int, set]:
        """Where a resting contact may have run off the end of its feature by the trial's end
        (or its island's earliest impact; runtime.step.clearance.may_slide_off): the instant it
        left (:meth:`_left`), which becomes its island's event in ``best`` -- the next frame
        there takes the next feature (a disc rolling off a flat face onto a corner's arc, held
        up on the face's line, flew off it and landed again) -- or, where that instant is not
        known (a contact on an ellipse; one at its feature's end from the start), {island:
        pairs} that touch then at a feature the frame did not have, penetrating (a contact held
        on an arc's whole circle past its end let a rounded box's side close in unwatched: an
        ellipse went 4.6e-6 m into it so). One contact search per such island."""
        c, rest = frame.contacts, frame.resting
        rest = rest[self.switches[c.body1[rest]] | self.switches[c.body2[rest]]]
        if rest.size == 0:
            return {}
        one, two = island_of_body[c.body1[rest]], island_of_body[c.body2[rest]]
        island = np.where(one >= 0, one, two)
        tables = self.collider.finder.tables
        known = set(frame.keys.tolist())
        out: dict[int, set] = {}
        for g in np.unique(island).tolist():
            until = best.get(g, h)
            q = trajectory(g).at(until)[0]
            mine = rest[island == g]
            sliding = clearance.sliding_off(
                start, q, self.radii, self.switches, mine, c.body1, c.body2,
                c.feature, tables.rows, tables.body_start, self.touch,
            )  # fmt: skip
            if not sliding.any():
                continue
            left = self._left(frame, mine[sliding], start, trajectory(g), until)
            if left is not None:
                best[g] = left
                continue
            members = (island_of_body == g) | self.collider.fixed
            found = self.collider.finder.find(q, 0.0, None, members)
            keys = self.collider.keys(found).tolist()
            for k in np.flatnonzero(found.gap < -self.touch).tolist():
                if keys[k] not in known:
                    out.setdefault(g, set()).add(_pair(found, k))
        return out

    def _left(self, frame, contacts, start, traj, until: float) -> float | None:
        """The first instant in (0, until] where one of the resting ``contacts`` (indices into
        the frame) that held at the start has left its feature (runtime.step.clearance.room
        <= 0: beyond its end by clearance.LEAVE); None if none held at the start. A root of the
        room, which changes continuously along the trajectory (scipy's brentq), then the first
        instant past it with room <= 0."""
        c, tables = frame.contacts, self.collider.finder.tables

        def room(t: float, which: np.ndarray) -> float:
            return float(np.min(clearance.rooms(which, traj.at(t)[0], c.body1, c.body2,
                                                c.feature, tables.rows, tables.body_start)))  # fmt: skip

        held = contacts[clearance.rooms(contacts, start, c.body1, c.body2, c.feature,
                                        tables.rows, tables.body_start) > 0.0]  # fmt: skip
        if held.size == 0 or room(until, held) > 0.0:
            return None
        tol = settings.TIME_EPS * np.finfo(float).eps * until
        t = brentq(room, 0.0, until, args=(held,), xtol=tol)
        step = tol
        while t < until and room(t, held) > 0.0:
            t, step = min(until, t + step), 2.0 * step
        return t

    @staticmethod
    def _islands(contacts, island_of_body: np.ndarray) -> np.ndarray:
        """Island of each watched contact: that of its moving body (body 1 unless fixed)."""
        one = island_of_body[contacts.body1]
        two = island_of_body[contacts.body2]
        return np.where(one >= 0, one, two)

    def _fast_pairs(self, contacts, touching, q0, q1, h, gap_of) -> tuple[list, np.ndarray]:
        """Brackets of the fast pairs (see the module docstring), found by sampling their
        gaps (``gap_of(k)``: contact k's along its island's trajectory) at instants closer than
        a fraction of the smaller half width of relative travel; and each contact's number of
        samples (0: not sampled): the sampled ones' brackets replace those of the step's ends."""
        counts = pair_scan.samples(self, contacts.body1, contacts.body2, q0, q1)
        out = []
        sampled = counts > 0
        for k in np.flatnonzero(sampled).tolist():
            samples = int(counts[k])
            gap = gap_of(k)
            t_prev, (g_prev, v_prev) = 0.0, gap(0.0)
            for s in range(1, samples + 1):
                t = h * s / samples
                g_now, v_now = gap(t)
                # a touching contact that separated by the previous sample is an open one now
                touches = bool(touching[k]) and g_prev <= self.touch
                if not touches and g_now > 0 and v_prev < 0 < v_now:
                    b = find_dip(gap, k, t_prev, g_prev, v_prev, t, g_now, v_now)
                else:
                    b = bracket_one(k, g_prev, v_prev, g_now, v_now, t_prev, t - t_prev, touches)
                if b is not None:
                    out.append(b)
                    break
                t_prev, g_prev, v_prev = t, g_now, v_now
        return out, counts

    def _gap_function(self, contacts, k: int, traj) -> Callable[[float], tuple[float, float]]:
        """t -> (d, d') of watched contact k along the island's trajectory; an oval's contact
        point moves over the oval, so its geometry is found again each time."""
        if not self.collider.finder.has_ovals:
            watched = self.evaluator.watch(contacts, k)
            return lambda t: watched(*traj.at(t))
        one = contacts.take([k])
        refresh = self.collider.refresh_ovals

        def gap(t: float) -> tuple[float, float]:
            q, v = traj.at(t)
            d, rate = self.evaluator.gap_and_rate(refresh(one, q), q, v)
            return float(d[0]), float(rate[0])

        return gap

    def _touches(self, contacts, k: int, poses: np.ndarray, resting: np.ndarray) -> bool:
        """Whether the pair of contact k touches at ``poses`` at a feature not resting before."""
        i, j = _pair(contacts, k)
        found = self.collider.pair(i, j, poses, self.touch)
        return not np.all(member(self.collider.keys(found), resting))

    def _new_feature(
        self, pairs: set, watched_keys: set, traj, until: float, known: set, samples: dict
    ) -> float | None:
        """Earliest impact, before ``until``, of a feature that a pair reaches only during the
        step: a pair closing in at one feature can meet at another (an edge's contact sliding
        onto its corner, a corner turning into an arc). A feature found penetrating at
        ``until``, not watched at the start and clear of the other body (by more than the touch
        gap) then, is located like any other. One that was behind its edge's line at the start
        (beyond the edge's end: a turning body can bring a corner in across another feature)
        is not a crossing of its kernel's gap; then, and for a fast pair (``samples``: the
        pairs' sample counts), the pair's first touch at a feature not ``known`` (the start's
        contacts) is found with the contact finder (runtime.step.pair_scan)."""
        poses = traj.at(until)[0]
        earliest = None
        for i, j in sorted(pairs):
            found = self.collider.pair(i, j, poses, 0.0)
            located, unexplained = False, False
            for k, key in enumerate(self.collider.keys(found).tolist()):
                if key in watched_keys or found.gap[k] >= -self.touch:
                    continue
                gap = self._gap_function(found, k, traj)
                start, end = gap(0.0)[0], gap(until)[0]
                if not (start > self.touch and end <= 0):
                    unexplained |= key not in known
                    continue
                t, d = locate(
                    gap,
                    0.0,
                    until,
                    until * start / (start - end),
                    gap_tol=settings.TOUCH_LOCATE * self.touch,
                    time_tol=settings.TIME_EPS * np.finfo(float).eps * until,
                )
                if d <= self.touch:
                    located = True
                    earliest = t if earliest is None else min(earliest, t)
            if (unexplained or samples.get((i, j), 0)) and not located:
                t = pair_scan.first_touch(self, i, j, traj, until, known, samples.get((i, j), 1))
                if t is not None:
                    earliest = t if earliest is None else min(earliest, t)
        return earliest


def _pair(contacts, k: int) -> tuple[int, int]:
    i, j = int(contacts.body1[k]), int(contacts.body2[k])
    return min(i, j), max(i, j)
