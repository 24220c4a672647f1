"""One chunk of a sweep, as a Dask task: its runs as one ensemble (runtime.simulate_ensemble).

Why a module of its own: a Dask worker imports the task's function by name, so it must be
importable without the command-line parts (argument parsing, the output folder, the client).
"""

from __future__ import annotations

import numpy as np


def run_chunk(scene, variations: dict[str, np.ndarray], options: dict):
    """The Ensemble of ``scene`` with ``variations`` (runtime.simulate_ensemble's keyword
    ``options``: duration, dt, method, record_every, guards)."""
    from runtime.step.ensemble import simulate_ensemble

    return simulate_ensemble(scene, variations, **options)
