"""runtime.compiled.Bound: the compiled entry point of a function, found once per process and
kinds of arguments, then called without numba's typing -- so the key must tell apart every
argument that numba types differently (an entry point does not check what it is given)."""

from __future__ import annotations

import numpy as np

from runtime.compiled import Bound, njit


@njit(cache=False)
def _weighted(values, pair):
    return values.sum() * pair[0] + pair[1]


def test_a_second_bound_of_the_function_starts_from_the_first_ones_entry(monkeypatch):
    values = np.arange(4.0)
    first = Bound(_weighted)
    assert first(values, (2.0, 1.0)) == 13.0
    second = Bound(_weighted)

    def typed_again(*args):
        raise AssertionError("the dispatcher was asked again")

    monkeypatch.setattr(type(_weighted), "__call__", typed_again)  # any dispatcher call fails
    assert second(values, (3.0, 0.5)) == 18.5  # the shared entry, without the dispatcher
    assert second.entry is first.entry


def test_arguments_that_numba_types_apart_have_their_own_entries():
    values = np.arange(4.0)
    frozen = values.copy()
    frozen.flags.writeable = False
    kinds = Bound._kinds
    assert kinds((values, (2, 1.0))) != kinds((values, (2.0, 1.0)))  # a tuple's member
    assert kinds((values,)) != kinds((frozen,))  # a read-only array
    assert kinds((values,)) != kinds((np.arange(4),))  # another dtype
    assert kinds((values,)) != kinds((np.zeros((4, 2))[:, 0],))  # not contiguous
    assert kinds((_weighted,)) != kinds((njit(cache=False)(lambda x: x),))  # two functions
    bound = Bound(_weighted)
    assert bound(values, (2, 1.0)) == 13.0
    assert Bound(_weighted)(values, (2.0, 1.5)) == 13.5
    assert Bound(_weighted)(frozen, (1, 0.0)) == 6.0
    entries = [e for (d, _), e in Bound._entries.items() if d is _weighted]
    assert len(entries) == 3  # int member, float member, read-only array: three entries
