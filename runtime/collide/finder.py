"""The contact finder of a set of bodies: broad phase, narrow phase and kernel gaps, compiled.

Why one object per scene: the feature tables (runtime.collide.features), the kernel modules of
the cases the bodies can produce and the candidate buffers are built once; each call then is
three compiled stages over flat arrays -- candidates (runtime.collide.narrowphase: broad phase
and feature choice by geometric distances), the generated kernels' gaps per case
(generated/compiled/<case>.py ``batch_gap``), and the selection with those gaps
(runtime.collide.selection) -- and gives a :class:`~runtime.collide.contact_set.Contacts`.

Only the compiled kernel modules of :func:`possible_cases` are imported ("model only what a
scene needs": a scene of discs and walls never loads a vertex kernel).  A finder keeps
buffers between calls, so one finder must not be used from two threads at once.

Compound bodies: the compiled stages work on units (runtime.collide.features: a body, or one
part of a compound body, with its body's pose), and the contacts found name the bodies.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Sequence
from dataclasses import replace
from itertools import product

import numpy as np

from generated import CASE_ID
from runtime.collide import ovals
from runtime.collide.candidates import COLUMNS
from runtime.collide.contact_keys import ContactKeys
from runtime.collide.contact_set import Contacts
from runtime.collide.features import (
    CLOSED,
    FIXED,
    RADIUS,
    SEGMENTS,
    features,
    scene_tables,
)
from runtime.collide.junctions import join_fixed_edges
from runtime.collide.narrowphase import find_candidates
from runtime.collide.selection import select
from runtime.compiled import njit
from runtime.model.shapes import Shape

CASES = ("vertex_edge", "vertex_circle", "circle_edge", "circle_circle")
EMPTY = Contacts.empty()


def check_bodies(shapes: Sequence[Shape], fixed: Sequence[bool]) -> np.ndarray:
    """``fixed`` as a bool array, after checking the shapes and one flag per shape."""
    for k, s in enumerate(shapes):
        if not isinstance(s, Shape):
            raise ValueError(
                f"shapes[{k}] must be a runtime.model.shapes.Shape, got {type(s).__name__}"
            )
    flags = np.asarray(fixed, dtype=bool).reshape(-1)
    if flags.shape != (len(shapes),):
        raise ValueError(f"fixed must have one flag per shape ({len(shapes)}), got {len(flags)}")
    return flags


def _cases(x: tuple, y: tuple) -> set[str]:
    """The cases a body of kinds x (as body 1) can make with a body of kinds y."""
    corners, ends, _, convex, _ = x
    _, _, segments, y_convex, y_concave = y
    found = set()
    if (corners or ends) and segments:
        found.add("vertex_edge")
    if corners and (y_convex or y_concave or y[0]):  # y[0]: corner on corner, radius 0
        found.add("vertex_circle")
    if convex and segments:
        found.add("circle_edge")
    if convex and (y_convex or y_concave):
        found.add("circle_circle")
    return found


def possible_cases(shapes: Sequence[Shape], fixed: Sequence[bool]) -> set[str]:
    """The cases that can ever occur between these bodies (in any poses), from the feature
    kinds each pair of bodies (not both fixed) brings: the kernel modules the engine needs."""
    flags = check_bodies(shapes, fixed)
    groups: dict = {}
    for s, f in zip(shapes, flags.tolist(), strict=True):
        key = (features(s).kinds(), f)
        groups[key] = groups.get(key, 0) + 1
    found: set[str] = set()
    for (a, fa), (b, fb) in product(groups, repeat=2):
        if (fa and fb) or ((a, fa) == (b, fb) and groups[(a, fa)] < 2):
            continue
        found |= _cases(a, b) | _cases(b, a)
    return found


def _kernel(case: str):
    try:
        return importlib.import_module(f"generated.compiled.{case}").batch_gap
    except ModuleNotFoundError as exc:
        raise RuntimeError(
            f"no generated kernel for contact case {case!r}: run "
            f"`regenerate-equations --cases {case}`"
        ) from exc


def _pair_codes(pairs: Sequence[tuple[int, int]], n: int) -> np.ndarray:
    """Sorted codes min * n + max of body pairs (the pairs kept apart), checked."""
    codes = []
    for i, j in pairs:
        if not (0 <= i < n and 0 <= j < n and i != j):
            raise ValueError(f"a pair kept apart must be two different bodies of {n}: {(i, j)}")
        codes.append(min(i, j) * n + max(i, j))
    return np.unique(np.array(codes, dtype=np.int64))


def check_groups(groups, n: int) -> np.ndarray:
    """``groups`` as an (n,) int64 array of collision groups (integers >= -1), after checking
    it; None gives an empty array (no groups: every pair may touch)."""
    if groups is None:
        return np.zeros(0, dtype=np.int64)
    try:
        g = np.asarray(groups, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"groups must be integers, one per shape, got {groups!r}") from None
    if g.shape != (n,):
        raise ValueError(f"groups must have one group per shape ({n}), got {g.size}")
    bad = np.flatnonzero(~(np.isfinite(g) & (g == np.round(g)) & (g >= -1)))
    if bad.size:
        k = int(bad[0])
        raise ValueError(f"groups must be integers >= -1; groups[{k}] = {float(g[k])!r}")
    return g.astype(np.int64)


class ContactFinder:
    """Finds the contacts of the bodies ``shapes`` (body coordinates, origin at the centre of
    mass; ``fixed``: one flag per body) at any poses: :meth:`find`, :meth:`refresh_ovals`.

    ``groups``: a collision group per body (integers >= -1; default None: one group). Two
    bodies touch only if their groups are equal or one of them is -1: N copies of a scene
    stepped as one (runtime.step.ensemble) never see each other, and share the fixed bodies
    of group -1. ``apart``: pairs of bodies (i, j) that never touch (bodies a joint links)."""

    def __init__(
        self,
        shapes: Sequence[Shape],
        fixed: Sequence[bool],
        groups: Sequence[int] | None = None,
        apart: Sequence[tuple[int, int]] = (),
    ) -> None:
        flags = check_bodies(shapes, fixed)
        self.n = len(shapes)
        self.groups = check_groups(groups, self.n)
        self.apart = _pair_codes(apart, self.n)
        self.cases = frozenset(possible_cases(shapes, flags))
        self.tables = scene_tables(shapes, flags)
        self.keys = ContactKeys.of(shapes)  # contact identity across steps
        self.owner = self.tables.owner
        self.compound = len(self.owner) > self.n  # some body has several units (parts)
        self._unit_groups = self.groups[self.owner] if self.groups.size else self.groups
        self.has_ovals = bool(np.any(np.diff(self.tables.start[:, 4])))
        self._kernels = [(CASE_ID[case], _kernel(case)) for case in sorted(self.cases)]
        self._zeros = np.zeros(self.n)
        self._everyone = np.ones(self.n, dtype=np.bool_)
        # fixed open chains of two or more bodies may meet at reflex joins (junctions), known
        # once their poses are: the joins' columns as each chain's own tables have them
        t = self.tables
        chains = (
            (t.body[:, FIXED] > 0) & (t.body[:, CLOSED] == 0) & (np.diff(t.start[:, SEGMENTS]) > 0)
        )
        self._chains = np.flatnonzero(chains) if np.unique(t.owner[chains]).size > 1 else None
        self._own_rows = t.rows.copy()
        self._joined: bytes | None = None
        self._allocate(8 * len(self.owner) + 16)

    def _allocate(self, capacity: int) -> None:
        self._candidates = np.zeros((capacity, COLUMNS))
        self._kernel_inputs = (
            np.zeros(capacity, dtype=np.int64),  # body1
            np.zeros(capacity, dtype=np.int64),  # body2
            np.zeros((capacity, 7)),  # geometry
            np.zeros(capacity, dtype=np.int64),  # candidates by case
            np.zeros(len(CASE_ID) + 1, dtype=np.int64),  # where each case starts there
        )

    def find(
        self,
        poses: np.ndarray,
        tolerance: float = 0.0,
        margins: np.ndarray | None = None,
        allowed: np.ndarray | None = None,
    ) -> Contacts:
        """All contacts at ``poses`` ((n, 3) of ``(x, y, th)``) whose gap is at most the pair's
        tolerance, ``tolerance + margins[i] + margins[j]`` (``margins``: (n,) per-body widening,
        e.g. how far each body can move in a step; default none), penetrating ones included,
        between bodies of one collision group (or of group -1) both ``allowed`` (an (n,) bool
        mask; default all: the engine's islands ask for the contacts among their bodies and the
        fixed ones). Ordered by pair (lower index, higher index), then by feature."""
        p = poses
        if not (type(p) is np.ndarray and p.dtype == np.float64 and p.shape == (self.n, 3)):
            p = self._poses(poses)
        elif not p.flags.c_contiguous:
            p = np.ascontiguousarray(p)
        base = _tolerance(tolerance)
        widen = self._zeros if margins is None else self._margins(margins)
        allow = self._everyone if allowed is None else np.ascontiguousarray(allowed, np.bool_)
        given = p
        if self.compound:  # per unit: its body's
            p, widen, allow = p[self.owner], widen[self.owner], allow[self.owner]
        if self._chains is not None:
            self._join_fixed(p)
        rows, start, body, owner = self.tables[:4]
        while True:
            inputs = self._kernel_inputs
            count = find_candidates(
                p,
                base,
                widen,
                allow,
                self._unit_groups,
                self.apart,
                rows,
                start,
                body,
                owner,
                self.compound,
                self._candidates,
                inputs,
            )
            if count < 0:
                b = int(owner[-1 - count])
                raise ValueError(f"poses must be finite; poses[{b}] = {given[b].tolist()}")
            if count <= len(self._candidates):
                break
            self._allocate(2 * count)
        if count == 0:
            return EMPTY
        gap = np.empty(count)
        body1, body2, geometry, members, case_start = inputs
        at = case_start.tolist()
        done = 0
        for case, kernel in self._kernels:
            if at[case + 1] > at[case]:
                kernel(p, body1, body2, geometry, members[at[case] : at[case + 1]], gap)
                done += at[case + 1] - at[case]
        if done != count:  # a case possible_cases did not foresee: a bug, not bad input
            raise RuntimeError(f"contacts of cases beyond {sorted(self.cases)} found")
        out = (
            np.empty(count, np.int64),
            np.empty(count, np.int64),
            np.empty(count, np.int64),
            np.empty((count, 7)),
            np.empty((count, 4), np.int64),
            np.empty((count, 2)),
            np.empty((count, 2)),
        )
        m = select(p, base, widen, body, self._candidates, count, body1, body2, gap, out)
        if m == 0:
            return EMPTY
        if m < count:
            gap, out = gap[:m], tuple(a[:m] for a in out)
        case, one, two, geometry, feature, point, normal = out
        if self.compound:
            one, two = owner[one], owner[two]
        return Contacts(case, one, two, geometry, feature, gap, point, normal)

    def _join_fixed(self, unit_poses: np.ndarray) -> None:
        """The reflex joins of two fixed bodies' edges (runtime.collide.junctions) at these
        poses, found again only where the fixed bodies' poses changed."""
        key = unit_poses[self._chains].tobytes()
        if key != self._joined:
            t = self.tables
            t.rows[:] = self._own_rows
            join_fixed_edges(t.rows, t.start, t.body, t.owner, unit_poses, t.body[:, RADIUS])
            self._joined = key

    def refresh_ovals(self, poses: np.ndarray, contacts: Contacts) -> Contacts:
        """``contacts`` with the osculating circle of every contact on an ellipse found again
        for ``poses`` (geometry rewritten; gap, point and normal stay those of the state the set
        was found for).  The same object if no contact is on an ellipse."""
        if not self.has_ovals or len(contacts) == 0:
            return contacts
        p = self._poses(poses)
        geometry = contacts.geometry.copy()
        t = self.tables
        ovals.refresh(
            p, contacts.body1, contacts.body2, contacts.feature, geometry, t.rows, t.body_start
        )
        return replace(contacts, geometry=geometry)

    def _poses(self, poses) -> np.ndarray:
        try:
            p = np.ascontiguousarray(poses, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"poses must be an (n, 3) array of numbers, got {poses!r}") from None
        if p.shape != (self.n, 3):
            raise ValueError(
                f"poses must have shape ({self.n}, 3) for {self.n} shapes, got {p.shape}"
            )
        if not np.all(np.isfinite(p)):
            bad = int(np.argwhere(~np.isfinite(p))[0][0])
            raise ValueError(f"poses must be finite; poses[{bad}] = {p[bad].tolist()}")
        return p

    def _margins(self, margins) -> np.ndarray:
        try:
            m = np.ascontiguousarray(margins, dtype=float)
        except (TypeError, ValueError):
            raise ValueError(f"margins must be an (n,) array of numbers, got {margins!r}") from None
        if m.shape != (self.n,):
            raise ValueError(f"margins must have shape ({self.n},), got {m.shape}")
        bad = _first_bad_margin(m)
        if bad >= 0:
            raise ValueError(f"margins must be finite and >= 0; margins[{bad}] = {float(m[bad])!r}")
        return m


@njit
def _first_bad_margin(m):
    """Index of the first margin that is not finite and >= 0, or -1 (one compiled pass: the
    engine's step asks at every contact search, where two NumPy reductions cost ~3 us)."""
    for k in range(m.size):
        if not (m[k] >= 0.0 and m[k] < math.inf):  # NaN fails both
            return k
    return -1


def _tolerance(tolerance) -> float:
    try:
        tol = float(tolerance)
    except (TypeError, ValueError):
        raise ValueError(f"tolerance must be a number, got {tolerance!r}") from None
    if not math.isfinite(tol):
        raise ValueError(f"tolerance must be finite, got {tolerance!r}")
    return tol
