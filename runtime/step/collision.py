"""The contact finder as the step sees it: swept contacts of some bodies, one pair's contacts,
and oval contacts found again at a new state.

Why: the step asks three questions of the narrow phase (runtime.collide): which contacts can
close within the next h (each body's reach widened by how far it can move, runtime.collide.
sweep), which contacts one pair has at a trial state (to confirm an impact), and where an oval's
contact point has moved to (its osculating circle is the contact's geometry). This module is the
one place that asks them.
"""

from __future__ import annotations

import numpy as np

from runtime.collide import contacts as _contacts
from runtime.collide.contact_set import EDGE, Contacts
from runtime.model.shapes import Ellipse


class Collision:
    """The contact questions of one scene's step (see the module docstring)."""

    def __init__(self, scene) -> None:
        self.scene = scene
        self.shapes = scene.shapes
        self.fixed = np.asarray(scene.fixed, dtype=bool)
        self.tolerance = scene.contact_tolerance
        self.ovals = {
            (b, e)
            for b, shape in enumerate(self.shapes)
            for e, edge in enumerate(shape.edges)
            if isinstance(edge, Ellipse)
        }

    def swept(self, poses: np.ndarray, margin: np.ndarray, active: np.ndarray | None) -> Contacts:
        """Contacts whose gap is at most the contact tolerance plus the margins of their two
        bodies, among the ``active`` bodies (a bool mask; None: all) and the fixed ones."""
        widest = float(np.max(margin, initial=0.0))
        found = _contacts.as_arrays(self.scene.find_contacts(poses, self.tolerance + 2.0 * widest))
        keep = found.gap <= self.tolerance + margin[found.body1] + margin[found.body2]
        if active is not None:
            allowed = active | self.fixed
            keep &= allowed[found.body1] & allowed[found.body2]
        return found if keep.all() else found.take(keep)

    def pair(self, i: int, j: int, poses: np.ndarray, tolerance: float) -> Contacts:
        """The contacts between bodies i and j only (scene body indices)."""
        found = _contacts.find_contacts(
            [self.shapes[i], self.shapes[j]],
            poses[[i, j]],
            [bool(self.fixed[i]), bool(self.fixed[j])],
            tolerance,
        )
        arrays = _contacts.as_arrays(found)
        index = np.array([i, j])
        return Contacts(
            arrays.case,
            index[arrays.body1],
            index[arrays.body2],
            arrays.geometry,
            arrays.feature,
            arrays.gap,
            arrays.point,
            arrays.normal,
        )

    def refresh_ovals(self, contacts: Contacts, poses: np.ndarray) -> Contacts:
        """``contacts`` with the geometry of those on an oval found again at ``poses``."""
        if not self.ovals or len(contacts) == 0:
            return contacts
        on_oval = [
            (int(contacts.feature[k, 0]) == EDGE and (int(contacts.body1[k]), int(contacts.feature[k, 1])) in self.ovals)
            or (int(contacts.feature[k, 2]) == EDGE and (int(contacts.body2[k]), int(contacts.feature[k, 3])) in self.ovals)
            for k in range(len(contacts))
        ]  # fmt: skip
        if not any(on_oval):
            return contacts
        geometry = contacts.geometry.copy()
        keys = contacts.keys()
        radii = np.array([s.bounding_radius for s in self.shapes])
        for k in np.flatnonzero(on_oval):
            i, j = sorted((int(contacts.body1[k]), int(contacts.body2[k])))
            fresh = self.pair(i, j, poses, self.tolerance + float(max(radii[i], radii[j])))
            match = np.flatnonzero(np.all(fresh.keys() == keys[k], axis=1))
            if match.size:
                geometry[k] = fresh.geometry[match[0]]
        return Contacts(
            contacts.case,
            contacts.body1,
            contacts.body2,
            geometry,
            contacts.feature,
            contacts.gap,
            contacts.point,
            contacts.normal,
        )
