"""Every mutant of bench/mutants.py still applies: its text is where it says, once. A change
that moves the text would otherwise be found only when `make mutate` (35 min, not part of
`make test`) refuses to start."""

from __future__ import annotations

from pathlib import Path

import pytest

from bench.mutants import MUTANTS
from bench.mutate import mutated

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("mutant", MUTANTS, ids=lambda m: m.name)
def test_the_mutant_applies_and_changes_its_file(mutant):
    text = (ROOT / mutant.path).read_text()
    changed = mutated(mutant, text)
    assert changed != text
    assert len(changed) - len(text) == len(mutant.new) - len(mutant.old)
