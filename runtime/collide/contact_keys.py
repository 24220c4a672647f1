"""Contact identity from one step to the next: one int per contact, looked up as arrays.

Why: the step looks every contact of a frame up in the contacts resting before (hysteresis), in
those resting at the last step's end, and in the warm-start memory of the force solve. With the
key as a tuple of six ints (Contacts.keys: body 1, body 2, kind 1, index 1, kind 2, index 2),
building the tuples and hashing them cost ~1 us a contact and step: for 10,000 contacts more
than all the compiled physics of the step. Packed in mixed radix into one integer by NumPy, a
key is built and compared as an int64; it unpacks again where the bodies or features are
needed. The sets of keys the step remembers are sorted arrays, looked up by binary search
(:func:`member`, :class:`Guesses`): Python sets and dicts of ints still cost ~0.3 us a contact
and step, 10,000 disc-in-a-bowl copies a third of their step. A scene too large for 63 bits
(n^2 (3 W)^2 >= 2^63, W: a bound of the feature indices) keeps the tuples, in object arrays
that NumPy sorts and searches the same way.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from runtime.compiled import CHECK_CALLS, njit

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

    def of_contacts(self, contacts) -> np.ndarray:
        """(m,) the key of each contact, in order (int64, or tuples where they do not fit)."""
        if not self.packed:
            return objects(map(tuple, contacts.keys().tolist()))
        feature = contacts.feature
        if CHECK_CALLS and len(feature) and not (  # the finder's own bug: checked in the tests
            0 <= feature[:, 1::2].min() and feature[:, 1::2].max() < self.width
            and 0 <= feature[:, ::2].min() and feature[:, ::2].max() < KINDS
        ):  # fmt: skip
            raise RuntimeError(f"contact features {feature.tolist()} outside the keys' range "
                               f"(indices below {self.width}): a bug of the contact finder")  # fmt: skip
        return _packed(contacts.body1, contacts.body2, feature, self.n, self.width)

    def bodies_of(self, keys: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(body 1, body 2) of each of ``keys``, as arrays."""
        if not self.packed:
            pairs = np.array([key[:2] for key in keys.tolist()], np.int64).reshape(-1, 2)
            return pairs[:, 0], pairs[:, 1]
        return np.divmod(keys // (self.radix * self.radix), self.n)

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


def objects(items) -> np.ndarray:
    """A 1-d object array of ``items`` (tuples stay elements, not rows)."""
    items = list(items)
    out = np.empty(len(items), dtype=object)
    for k, item in enumerate(items):
        out[k] = item
    return out


def key_set(keys: np.ndarray) -> np.ndarray:
    """The set of ``keys``, as the sorted array of its distinct members (np.unique, but a
    plain sort: its hash table costs more than the sort for keys that are mostly distinct)."""
    if keys.dtype == np.int64:
        return _distinct(keys)
    ordered = np.sort(keys)
    if len(ordered) > 1:
        ordered = ordered[np.r_[True, ordered[1:] != ordered[:-1]]]
    return ordered


def find(keys: np.ndarray, table: np.ndarray, sorter: np.ndarray | None = None) -> np.ndarray:
    """(m,) where each of ``keys`` is in ``table`` (sorted, or sorted by ``sorter``; distinct
    members), -1 where it is not."""
    if sorter is None and keys.dtype == np.int64 and table.dtype == np.int64:
        return _find_sorted(keys, table)  # a compiled loop: for a few keys, NumPy's calls cost more
    if len(table) == 0 or len(keys) == 0:
        return np.full(len(keys), -1, np.int64)
    at = np.minimum(np.searchsorted(table, keys, sorter=sorter), len(table) - 1)
    if sorter is not None:
        at = sorter[at]
    return np.where(table[at] == keys, at, -1)


def member(keys: np.ndarray, keyset: np.ndarray) -> np.ndarray:
    """Whether each of ``keys`` is in ``keyset`` (a :func:`key_set`), as a bool array."""
    if keys.dtype == np.int64 and keyset.dtype == np.int64:
        return _looked_up(keys, keyset, _FOUND)
    return find(keys, keyset) >= 0


_FOUND = np.ones(0, np.bool_)  # _looked_up's values for membership: none (True when found)


@njit
def _looked_up(keys, table, values):
    """Per key: values[where it is in the sorted ``table``] (True if ``values`` is empty),
    0 (False) where it is not there -- member and Guesses.get in one compiled loop."""
    at = _find_sorted(keys, table)
    out = np.zeros(keys.size, values.dtype)
    for k in range(keys.size):
        if at[k] >= 0:
            out[k] = values[at[k]] if values.size else True
    return out


@njit
def _packed(body1, body2, feature, n, width):
    """The packed key of each contact (one compiled loop: NumPy's five array operations cost
    more for the few contacts of a small scene)."""
    radix = KINDS * width
    out = np.empty(body1.size, np.int64)
    for k in range(body1.size):
        one = feature[k, 0] * width + feature[k, 1]
        two = feature[k, 2] * width + feature[k, 3]
        out[k] = ((body1[k] * n + body2[k]) * radix + one) * radix + two
    return out


@njit
def _distinct(keys):
    """key_set of int64 keys, compiled (a few keys: NumPy's calls cost more than the sort)."""
    ordered = np.sort(keys)
    size = min(ordered.size, 1)
    for k in range(1, ordered.size):
        if ordered[k] != ordered[size - 1]:
            ordered[size] = ordered[k]
            size += 1
    return ordered[:size].copy()


@njit
def _find_sorted(keys, table):
    """find for int64 keys in a sorted table: a binary search per key."""
    out = np.empty(keys.size, np.int64)
    n = table.size
    for k in range(keys.size):
        key, lo, hi = keys[k], 0, n
        while lo < hi:
            mid = (lo + hi) >> 1
            if table[mid] < key:
                lo = mid + 1
            else:
                hi = mid
        out[k] = lo if lo < n and table[lo] == key else -1
    return out


@njit
def _merged(table, clamped, keys, values):
    """(table, clamped) with ``values`` for ``keys`` (int64, distinct): known keys changed in
    place, new ones merged in order (new arrays only then)."""
    at = _find_sorted(keys, table)
    new = 0
    for k in range(keys.size):
        if at[k] >= 0:
            clamped[at[k]] = values[k]
        else:
            new += 1
    if new == 0:
        return table, clamped
    order = np.argsort(keys)
    out_keys, out_values = (
        np.empty(table.size + new, np.int64),
        np.empty(table.size + new, clamped.dtype),
    )
    i = o = 0
    for k in order:
        if at[k] >= 0:
            continue
        while i < table.size and table[i] < keys[k]:
            out_keys[o], out_values[o] = table[i], clamped[i]
            i, o = i + 1, o + 1
        out_keys[o], out_values[o] = keys[k], values[k]
        o += 1
    out_keys[o:], out_values[o:] = table[i:], clamped[i:]
    return out_keys, out_values


class Guesses:
    """Contact key -> whether its force was clamped (positive) at its last solve: the warm-start
    guesses of the force solves (runtime.solve.forces), as sorted parallel arrays. ``loaded``,
    when given, is a second such map: whether the contact carried a force (a large island's
    loaded set, runtime.solve.lcp_loaded); copies carry it along. With another ``dtype`` the
    values are of that type (0 for a contact never solved): the friction LCP's basis flags."""

    def __init__(
        self,
        keys: np.ndarray | None = None,
        clamped: np.ndarray | None = None,
        loaded: Guesses | None = None,
        dtype=bool,
    ):
        keys = np.zeros(0, np.int64) if keys is None else keys
        clamped = np.zeros(len(keys), dtype) if clamped is None else np.asarray(clamped, dtype)
        order = np.argsort(keys, kind="stable")
        self.keys, self.clamped = keys[order], clamped[order]
        self.loaded, self.dtype = loaded, dtype

    def __len__(self) -> int:
        return len(self.keys)

    def copy(self) -> Guesses:
        loaded = None if self.loaded is None else self.loaded.copy()
        return Guesses(self.keys.copy(), self.clamped.copy(), loaded, self.dtype)

    def get(self, keys: np.ndarray) -> np.ndarray:
        """(m,) the guess of each of ``keys``: False (0) for a contact never solved."""
        if keys.dtype == np.int64 and self.keys.dtype == np.int64 and len(self.keys):
            return _looked_up(keys, self.keys, self.clamped)
        at = find(keys, self.keys)
        known = at >= 0
        out = np.zeros(len(keys), self.dtype)
        out[known] = self.clamped[at[known]]
        return out

    def update(self, keys: np.ndarray, clamped: np.ndarray) -> None:
        """Remember ``clamped`` for ``keys`` (distinct), replacing what was known of them."""
        clamped = np.asarray(clamped, self.dtype)
        if keys.dtype == np.int64 and self.keys.dtype == np.int64:
            self.keys, self.clamped = _merged(self.keys, self.clamped, keys, clamped)
            return
        if len(keys) == 0:  # tuples (a scene too large for packed keys): the same, by NumPy
            return
        order = np.argsort(keys, kind="stable")
        keys, clamped = keys[order], clamped[order]
        at = find(keys, self.keys)
        known = at >= 0
        self.clamped[at[known]] = clamped[known]
        new = ~known
        if np.any(new):
            where = np.searchsorted(self.keys, keys[new])
            if self.keys.dtype != keys.dtype:  # the first keys of an empty memory set the dtype
                self.keys = self.keys.astype(keys.dtype)
            self.keys = np.insert(self.keys, where, keys[new])
            self.clamped = np.insert(self.clamped, where, clamped[new])

    def items(self):
        """(key, clamped) pairs, as Python objects."""
        return zip(self.keys.tolist(), self.clamped.tolist(), strict=True)
