"""Contact keys (runtime.collide.contact_keys): one int per contact, the same identity as the
tuple of Contacts.keys -- equal exactly when the tuples are equal, and unpacked to them."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import runtime
from runtime.collide.contact_keys import ContactKeys
from runtime.collide.contact_set import Contacts


def contacts_of(rows: np.ndarray) -> Contacts:
    m = len(rows)
    return Contacts(
        case=np.zeros(m, np.int64),
        body1=rows[:, 0].copy(),
        body2=rows[:, 1].copy(),
        geometry=np.zeros((m, 7)),
        feature=rows[:, 2:].copy(),
        gap=np.zeros(m),
        point=np.zeros((m, 2)),
        normal=np.zeros((m, 2)),
    )


@pytest.mark.parametrize("n, width", [(3, 2), (20_001, 5), (1000, 4000), (10**6, 10**4)])
def test_keys_are_equal_exactly_when_the_tuples_are_and_unpack_to_them(n, width):
    rng = np.random.default_rng(n)
    m = 5000
    rows = np.column_stack([
        rng.integers(0, n, m), rng.integers(0, n, m),
        rng.integers(0, 3, m), rng.integers(0, width, m),
        rng.integers(0, 3, m), rng.integers(0, width, m),
    ])  # fmt: skip
    rows = np.concatenate([rows, rows[:100]])  # some keys twice
    rows[-1] = [n - 1, n - 1, 2, width - 1, 2, width - 1]  # the largest key
    coder = ContactKeys(n, width)
    keys = coder.of_contacts(contacts_of(rows)).tolist()
    tuples = list(map(tuple, rows.tolist()))
    assert len(set(keys)) == len(set(tuples))
    assert [coder.parts(k) for k in keys] == tuples
    assert [coder.bodies(k) for k in keys] == [t[:2] for t in tuples]
    assert [coder.make(t) for t in tuples] == keys
    assert coder.packed == ((n * 3 * width) ** 2 < 2**63)


def test_a_scene_too_large_for_63_bits_keeps_tuples():
    coder = ContactKeys(10**7, 10**4)
    assert not coder.packed
    rows = np.array([[5, 9_999_999, 1, 9_999, 0, 3]])
    assert coder.of_contacts(contacts_of(rows)).tolist() == [tuple(rows[0].tolist())]
    assert coder.parts((5, 9_999_999, 1, 9_999, 0, 3)) == (5, 9_999_999, 1, 9_999, 0, 3)
    assert coder.bodies((5, 9_999_999, 1, 9_999, 0, 3)) == (5, 9_999_999)


def test_a_feature_outside_the_range_is_a_named_bug():
    coder = ContactKeys(4, 3)
    with pytest.raises(RuntimeError, match="outside the keys' range"):
        coder.of_contacts(contacts_of(np.array([[0, 1, 0, 3, 1, 0]])))


def test_a_scenes_keys_cover_its_features():
    """The width comes from the shapes: every contact the finder reports packs."""
    scene = runtime.load_scene(Path(__file__).parents[2] / "scenes" / "disc_in_bowl.toml")
    coder = scene.contact_finder().keys
    contacts = scene.contacts()
    assert len(contacts) and coder.packed
    keys = coder.of_contacts(contacts).tolist()
    assert [coder.parts(k) for k in keys] == list(map(tuple, contacts.keys().tolist()))


def _as_keys(items, packed: bool) -> np.ndarray:
    from runtime.collide.contact_keys import objects

    return np.array(items, np.int64) if packed else objects(items)


@pytest.mark.parametrize("packed", [True, False])
def test_key_sets_and_guesses_behave_as_python_sets_and_dicts(packed):
    """The sorted-array sets (key_set, member, find) and the warm-start memory (Guesses) give
    what a Python set and dict give, over updates that add, replace and repeat keys -- packed
    int keys and the tuples of scenes too large for them alike."""
    from runtime.collide.contact_keys import Guesses, find, key_set, member

    rng = np.random.default_rng(7 if packed else 8)

    def key(value: int):
        return value if packed else (value % 7, value // 7, 0, value % 3, 1, 2)

    memory, oracle = Guesses(loaded=Guesses()), {}
    for _ in range(60):
        values = rng.choice(200, size=rng.integers(0, 40), replace=False).tolist()
        keys = _as_keys([key(v) for v in values], packed)
        clamped = rng.random(len(values)) < 0.5
        asked = _as_keys([key(v) for v in rng.integers(0, 220, 50).tolist()], packed)
        expected = [oracle.get(k, False) for k in asked.tolist()]
        assert memory.get(asked).tolist() == expected
        memory.update(keys, clamped)
        oracle.update(zip(keys.tolist(), clamped.tolist(), strict=True))
        assert dict(memory.items()) == oracle and len(memory) == len(oracle)
        held = key_set(np.concatenate([keys, keys[: len(keys) // 2]]))
        assert held.tolist() == sorted(set(keys.tolist()))
        assert member(asked, held).tolist() == [k in set(keys.tolist()) for k in asked.tolist()]
        at = find(asked, keys, np.argsort(keys))
        positions = {k: p for p, k in enumerate(keys.tolist())}
        assert at.tolist() == [positions.get(k, -1) for k in asked.tolist()]
        memory.loaded.update(keys, ~clamped)  # the second map (loaded sets), kept apart
        assert dict(memory.loaded.items()) == {k: not v for k, v in oracle.items()}
    copy = memory.copy()
    memory.update(_as_keys([key(0)], packed), np.array([not oracle.get(key(0), False)]))
    memory.loaded.update(_as_keys([key(0)], packed), np.array([oracle.get(key(0), False)]))
    assert dict(copy.items()) == oracle  # a copy is not changed by later updates
    assert dict(copy.loaded.items()) == {k: not v for k, v in oracle.items()}


def test_bodies_of_keys_match_their_parts():
    rng = np.random.default_rng(3)
    for n, width in [(50, 6), (10**7, 10**4)]:
        coder = ContactKeys(n, width)
        rows = np.column_stack([
            rng.integers(0, n, 300), rng.integers(0, n, 300),
            rng.integers(0, 3, 300), rng.integers(0, width, 300),
            rng.integers(0, 3, 300), rng.integers(0, width, 300),
        ])  # fmt: skip
        body1, body2 = coder.bodies_of(coder.of_contacts(contacts_of(rows)))
        np.testing.assert_array_equal(body1, rows[:, 0])
        np.testing.assert_array_equal(body2, rows[:, 1])
