"""Time of impact: where, inside a step, an open contact's gap d reaches 0.

Why this module exists: an impact handled at the end of a step happens after the bodies have
sunk into each other (by up to the approach speed times the step), which loses energy, breaks
bounce heights and lets fast bodies tunnel. The engine therefore integrates a trial step, looks
at the gap d and its rate d' (both from the generated kernels) of every open contact at both ends,
and, where d changes sign, finds the instant with d = 0 and restarts from there.

* :func:`brackets` decides from (d, d') at both ends which contacts cross zero in the step and
  gives each an interval and a first guess: the root of the cubic Hermite interpolant of d (exact
  for free flight, where d is a quadratic in time). It also catches a contact that dips below
  zero and comes back within the step (d > 0 at both ends, d' < 0 then > 0, the cubic dips below
  0), and a touching contact that separates and comes back (a small bounce shorter than a step).
* :func:`locate` refines a bracket by safeguarded Newton on d(t), with the kernel's exact d' as
  the slope: each evaluation re-integrates the step from its start to t, so the restart state is
  a genuine integrator state with d = 0 (to ``gap_tol``), not an interpolation.
* :class:`ImpactSearch` puts them together for one trial step: brackets for all watched
  contacts, then, in order of their guesses, the earliest located impact that the contact
  finder confirms (a kernel's gap is that of a whole line or circle: beyond an edge's or arc's
  end it can cross zero with nothing there) and that is not a graze (a tangent touch, d = 0
  with d' = 0 up to rounding, which must not deflect a body skimming past); and, for the pairs
  that closed in, a feature the contact finder sees penetrating at the trial's end that was not
  watched at its start (the pair met at another feature within the step).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from runtime.collide import sweep
from runtime.model.shapes import Ellipse
from runtime.step.collisions import Mode, contact_key

CROSS = "cross"  # open at the start, penetrating at the end
DIP = "dip"  # open at both ends, below zero in between
RETURN = "return"  # touching and separating at the start, penetrating at the end


@dataclass
class Bracket:
    """Contact ``index`` crosses d = 0 in (lo, hi) (times from the step start); first ``guess``."""

    index: int
    lo: float
    hi: float
    guess: float
    kind: str
    cubic: np.ndarray  # the Hermite cubic of d over the step, in s = t / h
    h: float

    def curvature(self, t: float) -> float:
        """d'' at t from the cubic."""
        s = t / self.h
        return float((2.0 * self.cubic[2] + 6.0 * self.cubic[3] * s) / self.h**2)


def hermite(g0: float, v0: float, g1: float, v1: float, h: float) -> np.ndarray:
    """Coefficients (c0, c1, c2, c3) of p(s) = sum c_k s^k, s = t / h, with p(0) = g0,
    p(1) = g1, dp/dt = v0 at 0 and v1 at h."""
    c2 = 3.0 * (g1 - g0) - h * (2.0 * v0 + v1)
    c3 = 2.0 * (g0 - g1) + h * (v0 + v1)
    return np.array([g0, h * v0, c2, c3])


def _real_roots(c: np.ndarray, lo: float, hi: float) -> list[float]:
    """Real roots in [lo, hi] of the polynomial with coefficients c (lowest first), sorted."""
    coeffs = np.trim_zeros(c[::-1], "f")
    if coeffs.size < 2:
        return []
    roots = np.roots(coeffs)
    real = roots[np.abs(roots.imag) <= 1e-9 * (1.0 + np.abs(roots.real))].real
    return sorted(float(r) for r in real if lo <= r <= hi)


def _extremum(c: np.ndarray, minimum: bool) -> float | None:
    """s in (0, 1) of the cubic's interior minimum (or maximum), if it has one."""
    for s in _real_roots(np.array([c[1], 2.0 * c[2], 3.0 * c[3]]), 0.0, 1.0):
        curvature = 2.0 * c[2] + 6.0 * c[3] * s
        if 0.0 < s < 1.0 and (curvature > 0 if minimum else curvature < 0):
            return s
    return None


def _value(c: np.ndarray, s: float) -> float:
    return float(c[0] + s * (c[1] + s * (c[2] + s * c[3])))


def _first_root(c: np.ndarray, lo: float, hi: float) -> float:
    """First root of the cubic in [lo, hi] (s units); regula falsi if it finds none."""
    roots = _real_roots(c, lo, hi)
    if roots:
        return roots[0]
    a, b = _value(c, lo), _value(c, hi)
    return lo + (hi - lo) * a / (a - b) if a != b else 0.5 * (lo + hi)


def brackets(
    g0: np.ndarray,
    v0: np.ndarray,
    g1: np.ndarray,
    v1: np.ndarray,
    h: float,
    touching: np.ndarray,
) -> list[Bracket]:
    """The contacts whose gap reaches 0 during a step of length h, sorted by first guess.

    ``g0, v0`` are d and d' at the start, ``g1, v1`` at the end; ``touching`` marks contacts
    that touch (and separate) at the start: for them only a return to d < 0 counts. A DIP
    bracket's ``hi`` and a RETURN bracket's ``lo`` come from the cubic, so the caller must check
    the sign of the real d there.
    """
    g0, v0, g1, v1 = (np.asarray(a, dtype=float) for a in (g0, v0, g1, v1))
    touching = np.asarray(touching, dtype=bool)
    maybe = np.where(touching, g1 < 0, (g1 <= 0) | ((v0 < 0) & (v1 > 0)))
    found = []
    for k in np.flatnonzero(maybe).tolist():
        c = hermite(g0[k], v0[k], g1[k], v1[k], h)
        if touching[k]:
            top = _extremum(c, minimum=False)
            if top is not None:
                found.append(Bracket(k, top * h, h, _first_root(c, top, 1.0) * h, RETURN, c, h))
        elif g1[k] <= 0:
            found.append(Bracket(k, 0.0, h, _first_root(c, 0.0, 1.0) * h, CROSS, c, h))
        else:
            low = _extremum(c, minimum=True)
            if low is not None and _value(c, low) < 0:
                found.append(Bracket(k, 0.0, low * h, _first_root(c, 0.0, low) * h, DIP, c, h))
    found.sort(key=lambda b: b.guess)
    return found


def locate(
    gap: Callable[[float], tuple[float, float]],
    lo: float,
    hi: float,
    guess: float,
    *,
    gap_tol: float,
    time_tol: float,
    max_iterations: int = 60,
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


class ImpactSearch:
    """The first impact of a trial step, for one scene's engine."""

    def __init__(self, dynamics, shapes: list, fixed: list, touch: float, tolerance: float):
        self.dynamics, self.shapes, self.fixed = dynamics, shapes, fixed
        self.touch, self.tolerance = touch, tolerance
        self.n = len(shapes)
        self.radii = np.array([s.bounding_radius for s in shapes], dtype=float)
        # bodies with more than one feature (not a disc): their pairs can switch features
        self.features = [len(s.edges) > 1 or bool(s.vertices) for s in shapes]

    def _split(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        n = self.n
        return y[: 3 * n].reshape(n, 3), y[3 * n :].reshape(n, 3)

    def first(self, frame, traj: Callable[[float], np.ndarray], h: float) -> float | None:
        """Time (from the trial's start) of the first impact among the watched contacts of
        ``frame`` (runtime.step.collisions.Frame) along ``traj`` (t -> state), or None."""
        watched = frame.monitored
        if frame.rows is None or watched.size == 0:
            return None
        contacts = [frame.contacts[k] for k in watched]
        end = self.dynamics.rows(contacts, *self._split(traj(h)))
        found = brackets(
            frame.rows.gap[watched],
            frame.rows.gap_velocity[watched],
            end.gap,
            end.gap_velocity,
            h,
            np.isin(frame.modes[watched], (int(Mode.SEPARATING), int(Mode.LIFTING))),
        )
        resting = {contact_key(c) for c in frame.resting}
        best, unconfirmed = None, set()
        for bracket in found:
            contact = contacts[bracket.index]
            gap = self._gap_function(contact, traj)
            if best is not None:
                if bracket.lo >= best or gap(best)[0] > 0:  # traj(best) is cached: cheap
                    continue
                bracket.hi = min(bracket.hi, best)
            elif bracket.kind == DIP and gap(bracket.hi)[0] > 0:
                continue  # the cubic dipped, the real gap does not
            if bracket.kind == RETURN and gap(bracket.lo)[0] <= 0:
                t, d = bracket.lo, 0.0  # it never really left: touching and approaching at lo
            else:
                t, d = locate(
                    gap,
                    bracket.lo,
                    bracket.hi,
                    bracket.guess,
                    gap_tol=1e-3 * self.touch,
                    time_tol=4.0 * np.finfo(float).eps * h,
                )
            if d > self.touch or _grazes(gap(t)[1], bracket.curvature(t), 1e-6 * self.touch):
                continue
            if self._touches(contact, traj(t), resting):
                best = t
            else:
                unconfirmed.add(_pair(contact))
        closing = end.gap < frame.rows.gap[watched]  # may meet at another feature on the way
        unconfirmed |= {
            _pair(c)
            for c, shut in zip(contacts, closing, strict=True)
            if shut and (self.features[c.body1] or self.features[c.body2])
        }
        if unconfirmed:
            later = self._new_feature(unconfirmed, contacts, traj, h if best is None else best)
            if later is not None:
                best = later
        return best

    def _new_feature(self, pairs: set, watched: list, traj, until: float) -> float | None:
        """Earliest impact, before ``until``, of a feature that a pair reaches only during the
        step: a pair closing in at one feature can meet at another (an edge's contact sliding
        onto its corner, a corner turning into an arc), and a watched kernel that crosses zero
        where the contact finder sees another feature leaves that feature free to sink in later
        in the step. A feature found penetrating at ``until``, not watched at the start and
        clear of the other body (by more than the touch gap) then, is located like any other."""
        keys = {contact_key(c) for c in watched}
        poses = self._split(traj(until))[0]
        earliest = None
        for i, j in sorted(pairs):
            for contact in sweep.pair_contacts(self.shapes, self.fixed, i, j, poses, 0.0):
                if contact_key(contact) in keys or contact.gap >= -self.touch:
                    continue
                gap = self._gap_function(contact, traj)
                start, end = gap(0.0)[0], gap(until)[0]
                if not (start > self.touch and end <= 0):  # clear at the start: not found again
                    continue
                t, d = locate(
                    gap,
                    0.0,
                    until,
                    until * start / (start - end),
                    gap_tol=1e-3 * self.touch,
                    time_tol=4.0 * np.finfo(float).eps * until,
                )
                if d <= self.touch and (earliest is None or t < earliest):
                    earliest = t
        return earliest

    def _gap_function(self, contact, traj) -> Callable[[float], tuple[float, float]]:
        """t -> (d, d') of one contact from the kernels, at the trajectory's state at t. An
        oval's osculating circle moves over the oval, so its geometry is found again each time."""
        i, j = sorted((contact.body1, contact.body2))
        bodies = (contact.body1, contact.body2)
        oval = any(
            _is_oval(self.shapes[b], f) for b, f in zip(bodies, contact.feature, strict=True)
        )
        wanted = contact_key(contact)

        def gap(t: float) -> tuple[float, float]:
            poses, vel = self._split(traj(t))
            use = contact
            if oval:
                tol = self.tolerance + float(np.max(self.radii[[i, j]]))
                fresh = sweep.pair_contacts(self.shapes, self.fixed, i, j, poses, tol)
                use = next((c for c in fresh if contact_key(c) == wanted), contact)
            rows = self.dynamics.rows([use], poses, vel)
            return float(rows.gap[0]), float(rows.gap_velocity[0])

        return gap

    def _touches(self, contact, state: np.ndarray, resting: set) -> bool:
        """Whether the pair of ``contact`` touches at ``state`` at a feature not resting before."""
        i, j = sorted((contact.body1, contact.body2))
        poses = self._split(state)[0]
        found = sweep.pair_contacts(self.shapes, self.fixed, i, j, poses, self.touch)
        return any(contact_key(c) not in resting for c in found)


def _pair(contact) -> tuple[int, int]:
    return min(contact.body1, contact.body2), max(contact.body1, contact.body2)


def _grazes(rate: float, curvature: float, dip: float) -> bool:
    """Whether a located zero of d is a graze, not an impact: d is at a minimum there (d'' > 0)
    and dips below 0 by at most ``dip`` (d'^2 / 2 d'', rounding level: 1e-15 m by default): a
    tangent touch, where d = 0 is met with d' = 0 up to rounding -- an impulse there would
    deflect a body that only skims past."""
    return rate < 0 < curvature and rate * rate <= 2.0 * curvature * dip


def _is_oval(shape, feature) -> bool:
    kind, index = feature
    return kind == "edge" and isinstance(shape.edges[index], Ellipse)
