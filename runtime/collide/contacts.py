"""Contact detection for the engine: broad phase by bounding circles, then the narrow phase.

Why: the engine needs, at each state, every pair of features with gap below a tolerance,
each as one of the four generated cases of docs/conventions.md (``vertex_edge``,
``vertex_circle``, ``circle_edge``, ``circle_circle``) with the kernel's geometry arguments in
body coordinates and the kernel's own gap, body 2 owning the normal.  Which body is body 2 is
fixed by the case (a vertex is body 1, a concave arc body 2, a circle on a straight edge is
body 1); for two convex curves the fixed body is body 2 if there is one (so the engine can use
the ``*_static2`` kernels), otherwise the lower index is body 1.

The broad phase is a vectorised sweep over bounding circles (about each body's centre of mass,
inflated by the tolerance) along the wider axis of the scene, so pairs that cannot touch never
reach the per-pair Python narrow phase (runtime/narrowphase.py).  Pairs of fixed bodies are
skipped.  :func:`possible_cases` tells the engine which kernel modules a scene can need.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from itertools import product

import numpy as np

from generated import CASE_ID, GEOMETRY_COLUMNS
from runtime.collide import narrowphase
from runtime.collide.contact_set import KIND_NAMES, Contacts
from runtime.model.shapes import Shape

CASES = ("vertex_edge", "vertex_circle", "circle_edge", "circle_circle")


@dataclass(frozen=True, slots=True)
class Contact:
    """One contact.  ``geometry``: the kernel's geometry keyword arguments (``px1 py1`` or
    ``cx1 cy1 r1`` for body 1; ``ex2 ey2 nx2 ny2`` or ``cx2 cy2 r2`` for body 2), in each
    body's coordinates.  ``gap``: the kernel's gap for them.  ``feature``: ``(feature of body 1,
    feature of body 2)``, each ``("vertex", k)`` (index into ``Shape.vertices``), ``("edge", k)``
    (index into ``Shape.edges``) or ``("end", k)`` (where edge k runs smoothly into the next),
    stable from step to step.  ``point``: world point of body 1's feature nearest body 2 (the
    vertex itself for a vertex).  ``normal``: world unit normal, from body 2 toward body 1."""

    case: str
    body1: int
    body2: int
    geometry: dict[str, float]
    gap: float
    feature: tuple
    point: tuple[float, float]
    normal: tuple[float, float]


def candidate_pairs(
    centres: np.ndarray, radii: np.ndarray, fixed: np.ndarray, margin: float = 0.0
) -> tuple[np.ndarray, np.ndarray]:
    """Index arrays ``(I, J)``, ``I < J``, sorted, of the pairs whose circles (``centres``,
    ``radii``) are at most ``margin`` apart, skipping pairs of two fixed bodies."""
    n = len(radii)
    empty = np.zeros(0, dtype=np.intp)
    if n < 2:
        return empty, empty
    r = np.asarray(radii, dtype=float) + 0.5 * max(margin, 0.0)
    axis = int(np.ptp(centres[:, 1]) > np.ptp(centres[:, 0]))
    lo = centres[:, axis] - r
    order = np.argsort(lo, kind="stable")
    lo_sorted, hi_sorted = lo[order], (centres[:, axis] + r)[order]
    ends = np.searchsorted(lo_sorted, hi_sorted, side="right")
    counts = np.maximum(ends - np.arange(n) - 1, 0)
    a = np.repeat(np.arange(n), counts)
    b = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts) + a + 1
    i, j = order[a], order[b]
    d = centres[i] - centres[j]
    keep = (np.einsum("ij,ij->i", d, d) <= (r[i] + r[j]) ** 2) & ~(fixed[i] & fixed[j])
    i, j = np.minimum(i[keep], j[keep]), np.maximum(i[keep], j[keep])
    sort = np.lexsort((j, i))
    return i[sort], j[sort]


def _check(shapes, poses, fixed, tolerance=0.0) -> tuple[np.ndarray, np.ndarray, float]:
    n = len(shapes)
    for k, s in enumerate(shapes):
        if not isinstance(s, Shape):
            raise ValueError(
                f"shapes[{k}] must be a runtime.model.shapes.Shape, got {type(s).__name__}"
            )
    flags = np.asarray(fixed, dtype=bool).reshape(-1)
    if flags.shape != (n,):
        raise ValueError(f"fixed must have one flag per shape ({n}), got {len(flags)}")
    if poses is None:
        return np.zeros((n, 3)), flags, 0.0
    try:
        p = np.asarray(poses, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"poses must be an (n, 3) array of numbers, got {poses!r}") from None
    if p.shape != (n, 3):
        raise ValueError(f"poses must have shape ({n}, 3) for {n} shapes, got {p.shape}")
    if not np.all(np.isfinite(p)):
        bad = int(np.argwhere(~np.isfinite(p))[0][0])
        raise ValueError(f"poses must be finite; poses[{bad}] = {p[bad].tolist()}")
    tol = float(tolerance)
    if not math.isfinite(tol):
        raise ValueError(f"tolerance must be finite, got {tolerance!r}")
    return p, flags, tol


def find_contacts(
    shapes: Sequence[Shape], poses: np.ndarray, fixed: Sequence[bool], tolerance: float
) -> list[Contact]:
    """All contacts with ``gap <= tolerance`` (penetrating ones included) between the bodies
    ``shapes`` (body coordinates, origin at the centre of mass) at ``poses`` ``(n, 3)`` of
    ``(x, y, th)``.  Ordered by pair ``(min index, max index)``, then by feature."""
    p, flags, tol = _check(shapes, poses, fixed, tolerance)
    tables = [narrowphase.table(s) for s in shapes]
    radii = np.array([s.bounding_radius for s in shapes], dtype=float)
    first, second = candidate_pairs(p[:, :2], radii, flags, tol)
    discs = np.array([_is_disc(t) for t in tables], dtype=bool)
    both = discs[first] & discs[second]
    found = _disc_contacts(first[both], second[both], p, tables, flags, tol)
    rows, fix, closed = p.tolist(), flags.tolist(), [t.closed for t in tables]
    turned: list = [None] * len(shapes)
    for i, j in zip(first[~both].tolist(), second[~both].tolist(), strict=True):
        for k in (i, j):
            if turned[k] is None:
                turned[k] = narrowphase.rotated(tables[k], rows[k][2])
        xj, yj = rows[j][0], rows[j][1]
        pair = narrowphase.Pair(i, j, tables[i], tables[j], turned[i], turned[j],
                                rows[i][0] - xj, rows[i][1] - yj, fix[i], fix[j], tol)  # fmt: skip
        candidates = pair.candidates()
        if candidates:
            eps = 1e-9 * (radii[i] + radii[j])
            for case, b1, b2, geom, gap, feature, (px, py), normal in narrowphase.filtered(
                candidates, closed, eps
            ):
                found.append(Contact(case, b1, b2, geom, gap, feature, (px + xj, py + yj), normal))
    found.sort(key=lambda c: (c.body1, c.body2) if c.body1 < c.body2 else (c.body2, c.body1))
    return found


def _is_disc(t: narrowphase.Table) -> bool:
    """A shape whose only feature is one full convex circle (the vectorised fast path)."""
    plain = not (t.corners or t.ends or t.segments or t.ellipses) and len(t.arcs) == 1
    return plain and t.arcs[0][3] > 0 and t.arcs[0][5] >= 2 * math.pi


def _disc_contacts(first, second, p, tables, flags, tol) -> list[Contact]:
    """circle_circle contacts between pairs of discs, vectorised (a pile of discs)."""
    if len(first) == 0:
        return []
    arcs = [t.arcs[0] if t.arcs else (None, 0.0, 0.0, 0.0) for t in tables]
    centre = np.array([(a[1], a[2]) for a in arcs])
    radius = np.array([a[3] for a in arcs])
    swap = flags[first] & ~flags[second]  # a fixed disc is body 2
    b1, b2 = np.where(swap, second, first), np.where(swap, first, second)
    c, s = np.cos(p[:, 2]), np.sin(p[:, 2])
    turned = np.stack([c * centre[:, 0] - s * centre[:, 1], s * centre[:, 0] + c * centre[:, 1]], 1)
    v = p[b1, :2] - p[b2, :2] + turned[b1] - turned[b2]
    dist = np.hypot(v[:, 0], v[:, 1])
    r1, r2 = radius[b1], radius[b2]
    gap = -r1 - r2 + dist
    keep = (gap <= tol) & (dist > 0) & ((gap >= 0) | (-gap <= np.minimum(r1, r2)))
    normal = v[keep] / dist[keep, None]
    point = p[b1[keep], :2] + turned[b1[keep]] - r1[keep, None] * normal
    out = []
    for k1, k2, g, (px, py), (nx, ny) in zip(
        b1[keep].tolist(),
        b2[keep].tolist(),
        gap[keep].tolist(),
        point.tolist(),
        normal.tolist(),
        strict=True,
    ):
        a1, a2 = arcs[k1], arcs[k2]
        geom = {**a1[6], **a2[7]}
        out.append(Contact("circle_circle", k1, k2, geom, g, (a1[0], a2[0]), (px, py), (nx, ny)))
    return out


def _signature(shape: Shape) -> tuple[bool, bool, bool, bool, bool]:
    """(has corners, smooth arc ends, straight edges, convex curves, concave arcs)."""
    t = narrowphase.table(shape)
    convex = any(a[3] > 0 for a in t.arcs) or bool(t.ellipses)
    concave = any(a[3] < 0 for a in t.arcs)
    return bool(t.corners), bool(t.ends), bool(t.segments), convex, concave


def _cases(x: tuple, y: tuple) -> set[str]:
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
    types each pair of bodies (not both fixed) brings: the kernel modules the engine needs."""
    _, flags, _ = _check(shapes, None, fixed)
    groups: dict = {}
    for s, f in zip(shapes, flags.tolist(), strict=True):
        key = (_signature(s), f)
        groups[key] = groups.get(key, 0) + 1
    found: set[str] = set()
    for (a, fa), (b, fb) in product(groups, repeat=2):
        if (fa and fb) or ((a, fa) == (b, fb) and groups[(a, fa)] < 2):
            continue
        found |= _cases(a, b) | _cases(b, a)
    return found


def as_arrays(found: Sequence[Contact]) -> Contacts:
    """The contacts as one :class:`~runtime.collide.contact_set.Contacts` (arrays)."""
    m = len(found)
    if m == 0:
        return Contacts.empty()
    geometry = np.zeros((m, 7))
    feature = np.zeros((m, 4), dtype=np.int64)
    kinds = {name: k for k, name in enumerate(KIND_NAMES)}
    for k, c in enumerate(found):
        columns = GEOMETRY_COLUMNS[c.case]
        for name, value in c.geometry.items():
            geometry[k, columns[name]] = value
        (kind1, index1), (kind2, index2) = c.feature
        feature[k] = (kinds[kind1], index1, kinds[kind2], index2)
    return Contacts(
        np.array([CASE_ID[c.case] for c in found], dtype=np.int64),
        np.array([c.body1 for c in found], dtype=np.int64),
        np.array([c.body2 for c in found], dtype=np.int64),
        geometry,
        feature,
        np.array([c.gap for c in found], dtype=float),
        np.array([c.point for c in found], dtype=float).reshape(m, 2),
        np.array([c.normal for c in found], dtype=float).reshape(m, 2),
    )
