"""Contact detection as functions of the bodies: ``find_contacts`` and ``possible_cases``.

Why: callers that hold shapes rather than a :class:`~runtime.collide.finder.ContactFinder`
(a scene being checked, a test, a pair of bodies) still want the contacts as
:class:`~runtime.collide.contact_set.Contacts`; a finder per set of bodies is kept here (the
last few used), so repeated calls cost what the finder's do.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Sequence

import numpy as np

from runtime.collide.broadphase import candidate_pairs
from runtime.collide.contact_set import Contacts
from runtime.collide.finder import CASES, ContactFinder, check_bodies, check_groups, possible_cases
from runtime.model.shapes import Shape

__all__ = ["CASES", "candidate_pairs", "find_contacts", "finder_for", "possible_cases"]
KEEP = 64  # finders kept for find_contacts (the engine's impact search asks pair by pair)
_finders: OrderedDict = OrderedDict()


def finder_for(
    shapes: Sequence[Shape],
    fixed: Sequence[bool],
    groups: Sequence[int] | None = None,
    apart: Sequence[tuple[int, int]] = (),
) -> ContactFinder:
    """A contact finder for these bodies (and collision groups and pairs kept ``apart``, see
    :class:`~runtime.collide.finder.ContactFinder`), reused while they are among the last KEEP
    asked for."""
    flags = check_bodies(shapes, fixed)
    grouped = None if groups is None else check_groups(groups, len(flags))
    apart = tuple(apart)
    key = (
        tuple(map(id, shapes)),
        flags.tobytes(),
        None if grouped is None else grouped.tobytes(),
        apart,
    )
    found = _finders.get(key)
    if found is None:
        found = ContactFinder(shapes, flags, grouped, apart)
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
