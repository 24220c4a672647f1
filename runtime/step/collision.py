"""The contact finder as the step sees it: swept contacts of some bodies, one pair's contacts,
and oval contacts found again at a new state.

Why: the step asks three questions of the narrow phase (runtime.collide.finder): which contacts
can close within the next h (each body's reach widened by how far it can move, runtime.collide.
sweep), which contacts one pair has at a trial state (to confirm an impact), and where an oval's
contact point has moved to (its osculating circle is the contact's geometry). This module is the
one place that asks them.
"""

from __future__ import annotations

import numpy as np

from runtime.collide.contact_set import Contacts


class Collision:
    """The contact questions of one scene's step (see the module docstring)."""

    def __init__(self, scene) -> None:
        self.finder = scene.contact_finder()
        self.fixed = np.asarray(scene.fixed, dtype=bool)
        self.tolerance = scene.contact_tolerance
        self._pair = np.zeros(len(self.fixed), dtype=bool)

    def swept(self, poses: np.ndarray, margin: np.ndarray, active: np.ndarray | None) -> Contacts:
        """Contacts whose gap is at most the contact tolerance plus the margins of their two
        bodies, among the ``active`` bodies (a bool mask; None: all) and the fixed ones."""
        allowed = None if active is None else active | self.fixed
        return self.finder.find(poses, self.tolerance, margin, allowed)

    def keys(self, contacts: Contacts) -> np.ndarray:
        """The identity of each contact across steps (runtime.collide.contact_keys)."""
        return self.finder.keys.of_contacts(contacts)

    def pair(self, i: int, j: int, poses: np.ndarray, tolerance: float) -> Contacts:
        """The contacts between bodies i and j only (scene body indices)."""
        allowed = self._pair
        allowed[:] = False
        allowed[i] = allowed[j] = True
        return self.finder.find(poses, tolerance, None, allowed)

    def refresh_ovals(self, contacts: Contacts, poses: np.ndarray) -> Contacts:
        """``contacts`` with the geometry of those on an oval found again at ``poses``."""
        return self.finder.refresh_ovals(poses, contacts)
