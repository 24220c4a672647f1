"""A small 2-D rigid-body contact engine on top of the generated kernels.

    scene = runtime.load_scene("scenes/disc_in_bowl.toml")
    run = runtime.simulate(scene, duration=10.0, dt=1e-3, method="rk4")
    run.t, run.poses, run.velocities, run.energy, run.contact_forces

Submodules are imported on first use, so `from runtime import lcp` loads only the solver.
"""

from __future__ import annotations

import importlib

_EXPORTS = {
    "Body": "runtime.scene",
    "Scene": "runtime.scene",
    "SceneError": "runtime.scene",
    "load_scene": "runtime.scene",
    "scene_from_dict": "runtime.scene",
    "Run": "runtime.simulation",
    "SimulationError": "runtime.simulation",
    "simulate": "runtime.simulation",
    "Stabilisation": "runtime.dynamics",
    "Guards": "runtime.guards",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    raise AttributeError(f"module 'runtime' has no attribute {name!r}")
