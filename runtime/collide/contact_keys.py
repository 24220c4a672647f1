"""Contact identity from one step to the next: one Python int per contact.

Why: the step looks every contact of a frame up in the contacts resting before (hysteresis), in
those resting at the last step's end, and in the warm-start memory of the force solve. With the
key as a tuple of six ints (Contacts.keys: body 1, body 2, kind 1, index 1, kind 2, index 2),
building the tuples and hashing them cost ~1 us a contact and step: for 10,000 contacts more
than all the compiled physics of the step. Packed in mixed radix into one integer by NumPy, a
key is built, hashed and compared as a plain int; it unpacks again where the bodies or features
are needed. A scene too large for 63 bits (n^2 (3 W)^2 >= 2^63, W: a bound of the feature
indices) keeps the tuples, which behave the same everywhere.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from runtime.compiled import CHECK_CALLS

KINDS = 3  # VERTEX, EDGE, END (runtime.collide.contact_set)


class ContactKeys:
    """The keys of one scene's contacts (``n`` bodies, feature indices below ``width``)."""

    def __init__(self, n: int, width: int) -> None:
        self.n, self.width = int(n), max(int(width), 1)
        self.radix = KINDS * self.width  # values of one feature (kind, index)
        self.packed = (self.n * self.radix) ** 2 < 2**63

    @classmethod
    def of(cls, shapes: Sequence) -> ContactKeys:
        """The keys of a scene of ``shapes``: indices into each shape's vertices or edges."""
        width = max((max(len(s.vertices), len(s.edges)) for s in shapes), default=0)
        return cls(len(shapes), width + 1)

    def of_contacts(self, contacts) -> list:
        """The key of each contact, in order (ints, or tuples where they do not fit)."""
        if not self.packed:
            return list(map(tuple, contacts.keys().tolist()))
        feature = contacts.feature
        if CHECK_CALLS and len(feature) and not (  # the finder's own bug: checked in the tests
            0 <= feature[:, 1::2].min() and feature[:, 1::2].max() < self.width
            and 0 <= feature[:, ::2].min() and feature[:, ::2].max() < KINDS
        ):  # fmt: skip
            raise RuntimeError(f"contact features {feature.tolist()} outside the keys' range "
                               f"(indices below {self.width}): a bug of the contact finder")  # fmt: skip
        one = feature[:, 0] * self.width + feature[:, 1]
        two = feature[:, 2] * self.width + feature[:, 3]
        pair = contacts.body1.astype(np.int64) * self.n + contacts.body2
        return ((pair * self.radix + one) * self.radix + two).tolist()

    def parts(self, key) -> tuple[int, int, int, int, int, int]:
        """(body 1, body 2, kind 1, index 1, kind 2, index 2) of a key."""
        if not self.packed:
            return tuple(key)
        rest, two = divmod(key, self.radix)
        pair, one = divmod(rest, self.radix)
        b1, b2 = divmod(pair, self.n)
        return b1, b2, *divmod(one, self.width), *divmod(two, self.width)

    def bodies(self, key) -> tuple[int, int]:
        """(body 1, body 2) of a key."""
        if not self.packed:
            return key[0], key[1]
        return divmod(key // (self.radix * self.radix), self.n)

    def make(self, parts: Sequence[int]):
        """The key of (body 1, body 2, kind 1, index 1, kind 2, index 2)."""
        if not self.packed:
            return tuple(int(p) for p in parts)
        b1, b2, k1, i1, k2, i2 = (int(p) for p in parts)
        return ((b1 * self.n + b2) * self.radix + k1 * self.width + i1) * self.radix + (
            k2 * self.width + i2
        )
