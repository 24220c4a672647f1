"""The grid of a parameter sweep: ``--vary`` specifications parsed, checked and combined.

    disc.position[0]=linspace(-0.5,0.5,1000)   1000 values from -0.5 to 0.5, ends included
    disc.restitution=0.2,0.5                   a list of values
    scene.gravity[1]=-9.81                     one value

The keys are those of runtime.simulate_ensemble (runtime.step.variations); a vector field is
varied one component at a time. Every combination of the values is one run, numbered with the
last ``--vary`` varying fastest. The grid is cut into chunks of consecutive runs, each run on a
worker as one ensemble.
"""

from __future__ import annotations

import itertools
import math
import re
from dataclasses import dataclass

import numpy as np

from runtime import settings
from runtime.step.variations import VariationError, parse_key, read_variations

_LINSPACE = re.compile(r"linspace\(([^,()]*),([^,()]*),([^,()]*)\)")


class GridError(ValueError):
    """A bad --vary (one line, naming it)."""


@dataclass(frozen=True)
class Grid:
    """``values`` (R, k): run r's value of each of the ``keys`` (the --vary ``specs``)."""

    specs: list[str]
    keys: list[str]
    values: np.ndarray

    @property
    def runs(self) -> int:
        return len(self.values)

    def chunks(self, size: int) -> list[tuple[int, int]]:
        """(start, stop) of each chunk of ``size`` consecutive runs."""
        return [(a, min(a + size, self.runs)) for a in range(0, self.runs, size)]

    def variations(self, start: int, stop: int) -> dict[str, np.ndarray]:
        """runtime.simulate_ensemble's variations of runs start..stop - 1."""
        return {key: self.values[start:stop, j].copy() for j, key in enumerate(self.keys)}


def default_chunk(runs: int) -> int:
    """Runs per chunk unless --chunk says: settings.SWEEP_CHUNKS chunks, at most
    settings.SWEEP_MAX_CHUNK runs each (independent of the workers, so a sweep resumed on
    another cluster cuts its grid the same way)."""
    return max(1, min(settings.SWEEP_MAX_CHUNK, math.ceil(runs / settings.SWEEP_CHUNKS)))


def parse_vary(spec: str) -> tuple[str, np.ndarray]:
    """(key, values) of one --vary KEY=VALUES."""
    key, sep, text = spec.partition("=")
    key, text = key.strip(), text.replace(" ", "")
    if not sep or not key or not text:
        raise GridError(
            f"--vary {spec!r}: expected KEY=VALUES, e.g. disc.position[0]=linspace(-0.5,0.5,11) "
            "or disc.restitution=0.2,0.5"
        )
    match = _LINSPACE.fullmatch(text)
    if match:
        start, stop = (_number(spec, v) for v in match.groups()[:2])
        count = match[3]
        if not (count.isdigit() and 1 <= int(count) <= settings.SWEEP_MAX_RUNS):
            raise GridError(
                f"--vary {spec!r}: linspace's count must be a whole number from 1 to "
                f"{settings.SWEEP_MAX_RUNS:g}, got {count!r}"
            )
        return key, np.linspace(start, stop, int(count))
    if "(" in text or ")" in text:
        raise GridError(
            f"--vary {spec!r}: values are a list 'a,b,c' or 'linspace(start,stop,count)'"
        )
    return key, np.array([_number(spec, v) for v in text.split(",")])


def _number(spec: str, text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise GridError(f"--vary {spec!r}: {text!r} is not a number") from None
    if not math.isfinite(value):
        raise GridError(f"--vary {spec!r}: {text!r} is not a finite number")
    return value


def make_grid(scene, specs: list[str]) -> Grid:
    """The checked grid of the --vary ``specs`` for ``scene``."""
    if not specs:
        raise GridError("give at least one --vary KEY=VALUES (e.g. disc.restitution=0.2,0.5)")
    keys, lists = [], []
    for spec in specs:
        key, values = parse_vary(spec)
        try:
            _, field, component, size = parse_key(scene, key)
            if size > 1 and component is None:
                raise VariationError(
                    f"{field} is a vector: vary one component at a time, e.g. {key}[0]=..."
                )
            if key in keys:
                raise VariationError(f"{key} is varied twice")
            read_variations(scene, {key: values})
        except VariationError as exc:
            raise GridError(f"--vary {spec!r}: {_short(exc)}") from None
        keys.append(key)
        lists.append(values)
    try:
        read_variations(scene, {k: v[:1] for k, v in zip(keys, lists, strict=True)})
    except VariationError as exc:  # e.g. position[0] and position given apart
        raise GridError(f"--vary: {_short(exc)}") from None
    runs = math.prod(len(v) for v in lists)
    if runs > settings.SWEEP_MAX_RUNS:
        raise GridError(
            f"--vary: {runs:,} runs in the grid, more than {settings.SWEEP_MAX_RUNS:,}; "
            "sweep fewer values"
        )
    values = np.array(list(itertools.product(*lists)), dtype=float).reshape(runs, len(keys))
    return Grid(list(specs), keys, values)


def _short(exc: Exception) -> str:
    """A variation error in --vary terms: its 'variations[key]' prefix dropped (the --vary
    names the key), 'variations[key][i] = x' said as 'value x'."""
    key = r"^variations\[(?:'[^']*'|\"[^\"]*\")\]"
    text = re.sub(key + r"\[\d+\] = ", "value ", str(exc))
    return re.sub(key + ":? ", "", text)
