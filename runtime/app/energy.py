"""Where a run's energy went: lost at inelastic impacts, or numerical drift.

Why: with restitution below 1 the mechanical energy falls at every impact by design, so
"energy drift -308 J" read like an error when it was the impacts.  The loss at impacts is the
jump in kinetic energy across each located impact; what is left of the change, E(t) - E(0) plus
the energy lost at impacts up to t, is the integrator's numerical drift.

The per-step losses come from the engine (``run.impact_losses``: the energy lost at impacts
between the previous recorded step and this one, >= 0, 0 at the first).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["EnergyBudget", "energy_budget"]


@dataclass(frozen=True)
class EnergyBudget:
    """Per recorded step: the change ``E(t) - E(0)``, the energy ``lost`` at impacts up to t and
    the number of located ``impacts``."""

    change: np.ndarray
    lost: np.ndarray
    impacts: int

    @property
    def drift(self) -> np.ndarray:
        """The change not explained by impacts: E(t) - E(0) + lost(t)."""
        return self.change + self.lost


def energy_budget(run: Any) -> EnergyBudget:
    """The budget of ``run`` (its ``energy`` and ``impact_losses``)."""
    energy = np.asarray(run.energy, dtype=float)
    change = energy - energy[0] if len(energy) else np.zeros(0)
    lost = np.cumsum(np.asarray(run.impact_losses, dtype=float))
    return EnergyBudget(change, lost, len(run.impact_times))
