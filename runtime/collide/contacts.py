"""Contact detection as functions of the bodies: ``find_contacts`` and ``possible_cases``.

Why: callers that hold shapes rather than a :class:`~runtime.collide.finder.ContactFinder`
(a scene being checked, a test, a pair of bodies) still want the contacts as
:class:`~runtime.collide.contact_set.Contacts`; a finder per set of bodies is kept here (the
last few used), so repeated calls cost what the finder's do.

Transitional: the engine of runtime/step still reads one :class:`Contact` object per contact
(``.case``, ``.geometry`` dict, ``.feature`` tuple, ...).  :func:`contact_objects` converts a
``Contacts`` into that list, :func:`find_contact_objects` is the old list-returning
``find_contacts`` and :func:`as_arrays` converts back; all go once runtime/step reads
``Contacts``.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from generated import GEOMETRY_COLUMNS
from runtime.collide.broadphase import candidate_pairs
from runtime.collide.contact_set import CASE_NAMES, KIND_NAMES, Contacts
from runtime.collide.finder import CASES, ContactFinder, check_bodies, possible_cases
from runtime.model.shapes import Shape

__all__ = [
    "CASES",
    "Contact",
    "as_arrays",
    "candidate_pairs",
    "contact_objects",
    "find_contact_objects",
    "find_contacts",
    "finder_for",
    "possible_cases",
]
KEEP = 64  # finders kept for find_contacts (the engine's impact search asks pair by pair)
_finders: OrderedDict = OrderedDict()


def finder_for(shapes: Sequence[Shape], fixed: Sequence[bool]) -> ContactFinder:
    """A contact finder for these bodies, reused while they are among the last KEEP asked for."""
    flags = check_bodies(shapes, fixed)
    key = (tuple(map(id, shapes)), flags.tobytes())
    found = _finders.get(key)
    if found is None:
        found = ContactFinder(shapes, flags)
        _finders[key] = (found, tuple(shapes))  # the shapes too: their ids stay theirs
        if len(_finders) > KEEP:
            _finders.popitem(last=False)
        return found
    _finders.move_to_end(key)
    return found[0]


def find_contacts(
    shapes: Sequence[Shape], poses: np.ndarray, fixed: Sequence[bool], tolerance: float
) -> Contacts:
    """All contacts with ``gap <= tolerance`` (penetrating ones included) between the bodies
    ``shapes`` (body coordinates, origin at the centre of mass) at ``poses`` ``(n, 3)`` of
    ``(x, y, th)``.  Ordered by pair ``(min index, max index)``, then by feature."""
    return finder_for(shapes, fixed).find(poses, tolerance)


@dataclass(frozen=True, slots=True)
class Contact:
    """Transitional: one contact as an object (see :func:`contact_objects`).  ``geometry``:
    the kernel's geometry keyword arguments; ``feature``: ``(feature of body 1, feature of
    body 2)``, each ``("vertex" | "edge" | "end", index)``."""

    case: str
    body1: int
    body2: int
    geometry: dict[str, float]
    gap: float
    feature: tuple
    point: tuple[float, float]
    normal: tuple[float, float]


def contact_objects(found: Contacts) -> list[Contact]:
    """Transitional: ``found`` as one :class:`Contact` per row, for runtime/step until it reads
    ``Contacts``."""
    out = []
    rows = zip(
        found.case.tolist(), found.body1.tolist(), found.body2.tolist(), found.geometry.tolist(),
        found.feature.tolist(), found.gap.tolist(), found.point.tolist(), found.normal.tolist(),
        strict=True,
    )  # fmt: skip
    for case, b1, b2, geometry, (k1, i1, k2, i2), gap, point, normal in rows:
        name = CASE_NAMES[case]
        values = {arg: geometry[column] for arg, column in GEOMETRY_COLUMNS[name].items()}
        feature = ((KIND_NAMES[k1], i1), (KIND_NAMES[k2], i2))
        out.append(Contact(name, b1, b2, values, gap, feature, tuple(point), tuple(normal)))
    return out


def find_contact_objects(
    shapes: Sequence[Shape], poses: np.ndarray, fixed: Sequence[bool], tolerance: float
) -> list[Contact]:
    """Transitional: :func:`find_contacts` as a list of :class:`Contact` objects."""
    return contact_objects(find_contacts(shapes, poses, fixed, tolerance))


def as_arrays(found: Sequence[Contact] | Contacts) -> Contacts:
    """Transitional: a list of :class:`Contact` objects (or a ``Contacts``) as ``Contacts``."""
    if isinstance(found, Contacts):
        return found
    m = len(found)
    if m == 0:
        return Contacts.empty()
    geometry, feature = np.zeros((m, 7)), np.zeros((m, 4), dtype=np.int64)
    case_id = {name: number for number, name in CASE_NAMES.items()}
    for k, c in enumerate(found):
        for name, value in c.geometry.items():
            geometry[k, GEOMETRY_COLUMNS[c.case][name]] = value
        (kind1, index1), (kind2, index2) = c.feature
        feature[k] = (KIND_NAMES.index(kind1), index1, KIND_NAMES.index(kind2), index2)
    return Contacts(
        np.array([case_id[c.case] for c in found], dtype=np.int64),
        np.array([c.body1 for c in found], dtype=np.int64),
        np.array([c.body2 for c in found], dtype=np.int64),
        geometry,
        feature,
        np.array([c.gap for c in found], dtype=float),
        np.array([c.point for c in found], dtype=float).reshape(m, 2),
        np.array([c.normal for c in found], dtype=float).reshape(m, 2),
    )
