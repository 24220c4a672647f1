"""Comparing two engines on one error measure: Pareto fronts, error at equal cost, cost at
equal error (bench/report.py).

Why apart from the report: the comparison is the report's claim, so it is one small piece that
can be read (and checked) on its own; it knows nothing of engines, only (wall time, error) points.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

FLOOR = 1e-16  # errors below this are rounding: plotted and compared as "<= 1e-16"
TARGET = 1e-2  # the project's target: at equal wall time our error <= 1/100 of the peer's
GRID = 41  # points of the log grid over a common range when looking for the worst ratio


@dataclass
class Point:
    """One run of one configuration of one engine: its cost and its errors."""

    engine: str
    method: str  # the line of the diagram it belongs to
    setting: str  # the swept parameter: "dt=0.01", "rtol=1e-06", ...
    wall_time: float
    errors: dict[str, float]
    steps: int


@dataclass(frozen=True)
class Front:
    """The runs no other run of the same engine beats in both cost and error, by cost."""

    cost: np.ndarray
    error: np.ndarray

    @classmethod
    def of(cls, points: list[Point], metric: str) -> Front:
        pairs = sorted(
            (p.wall_time, max(p.errors[metric], FLOOR))
            for p in points
            if math.isfinite(p.errors[metric])
        )
        cost, error = [], []
        for c, e in pairs:
            if not error or e < error[-1]:
                cost.append(c)
                error.append(e)
        return cls(np.array(cost), np.array(error))

    def error_at(self, cost: float) -> float:
        """Log-log interpolated error at a wall time inside the front's range."""
        return float(np.exp(np.interp(np.log(cost), np.log(self.cost), np.log(self.error))))

    def cost_at(self, error: float) -> float:
        """Log-log interpolated wall time to reach an error inside the front's range."""
        return float(np.exp(np.interp(-np.log(error), -np.log(self.error), np.log(self.cost))))


@dataclass
class Comparison:
    """Ours/peer on one error measure: ratios < 1 are in our favour."""

    metric: str
    cost_range: tuple[float, float] | None  # wall times both engines measured
    error_range: tuple[float, float] | None  # errors both engines reached
    error_ratio_mid: float = math.nan  # error ours/peer at the middle of cost_range
    error_ratio_worst: float = math.nan  # the largest such ratio over cost_range
    error_ratio_best: float = math.nan
    ours_at_floor: bool = False  # our error is rounding there: the ratio is an upper bound
    cost_ratio_mid: float = math.nan  # wall time ours/peer at the middle of error_range
    cost_ratio_hardest: float = math.nan  # ... at the peer's best error
    cost_hardest_is_bound: bool = False  # our cheapest run beats it: an upper bound
    target_from: float = math.nan  # wall time from which error ours/peer <= TARGET
    extra: dict[str, float] = field(default_factory=dict)

    @property
    def target_met(self) -> bool | None:
        if self.cost_range is None:
            return None
        return self.error_ratio_worst <= TARGET


def _overlap(a: tuple[float, float], b: tuple[float, float]) -> tuple[float, float] | None:
    lo, hi = max(a[0], b[0]), min(a[1], b[1])
    return (lo, hi) if lo <= hi else None


def _holds_from(costs: np.ndarray, ratios: np.ndarray) -> float:
    """The smallest wall time from which the error ratio stays <= TARGET (inf: nowhere)."""
    failing = np.flatnonzero(ratios > TARGET)
    if failing.size == 0:
        return float(costs[0])
    return float(costs[failing[-1] + 1]) if failing[-1] + 1 < len(costs) else math.inf


def compare(ours: list[Point], theirs: list[Point], metric: str) -> Comparison:
    """Error at equal cost and cost at equal error (ours/theirs), read off both fronts where
    both engines measured."""
    fo, ft = Front.of(ours, metric), Front.of(theirs, metric)
    cost_range = _overlap((fo.cost[0], fo.cost[-1]), (ft.cost[0], ft.cost[-1]))
    error_range = _overlap((fo.error[-1], fo.error[0]), (ft.error[-1], ft.error[0]))
    result = Comparison(metric, cost_range, error_range)
    if cost_range is not None:
        grid = np.geomspace(*cost_range, GRID)
        ratios = np.array([fo.error_at(c) / ft.error_at(c) for c in grid])
        mid = math.sqrt(cost_range[0] * cost_range[1])
        result.error_ratio_mid = fo.error_at(mid) / ft.error_at(mid)
        result.error_ratio_worst = float(ratios.max())
        result.error_ratio_best = float(ratios.min())
        result.ours_at_floor = fo.error_at(mid) <= FLOOR * 1.0001
        result.extra["cost_mid"] = mid
        result.target_from = _holds_from(grid, ratios)
    if error_range is not None:
        mid = math.sqrt(error_range[0] * error_range[1])
        result.cost_ratio_mid = fo.cost_at(mid) / ft.cost_at(mid)
        result.extra["error_mid"] = mid
    hardest = ft.error[-1]  # the smallest error the peer reached
    result.extra["error_hardest"] = hardest
    if hardest >= fo.error[0]:  # our cheapest run is already better: a bound
        result.cost_ratio_hardest = fo.cost[0] / ft.cost_at(hardest)
        result.cost_hardest_is_bound = True
    elif hardest >= fo.error[-1]:
        result.cost_ratio_hardest = fo.cost_at(hardest) / ft.cost_at(hardest)
    return result
