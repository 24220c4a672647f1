"""A small 2-D rigid-body contact engine on top of the generated kernels.

    scene = runtime.load_scene("scenes/disc_in_bowl.toml")
    run = runtime.simulate(scene, duration=10.0, dt=1e-3, method="rk4")
    run.t, run.poses, run.velocities, run.energy, run.contact_forces
    ensemble = runtime.simulate_ensemble(scene, {"disc.angle": angles}, duration=1.0)  # N copies

Submodules are imported on first use, so `runtime.lcp` loads only the solver.

Layout: model/ (shapes, bodies, scenes), io/ (scene files), collide/ (broad and narrow phase),
solve/ (kernel rows, contact forces, impulses), step/ (the time step), app/ (CLI, plots).
"""

from __future__ import annotations

import importlib

_EXPORTS = {
    "Body": "runtime.model.scene",
    "Scene": "runtime.model.scene",
    "SceneError": "runtime.io.scene_file",
    "load_scene": "runtime.io.scene_file",
    "scene_from_dict": "runtime.io.scene_file",
    "SceneWarning": "runtime.io.scene_file",
    "Run": "runtime.step.simulation",
    "SimulationError": "runtime.step.world",
    "simulate": "runtime.step.simulation",
    "simulate_ensemble": "runtime.step.ensemble",
    "Ensemble": "runtime.step.ensemble",
    "World": "runtime.step.world",
    "Stabilisation": "runtime.solve.forces",
    "Guards": "runtime.step.guards",
}

# submodules reachable as attributes, e.g. `runtime.lcp.solve(A, b)` after `import runtime`
_MODULES = {"lcp": "runtime.solve.lcp", "shapes": "runtime.model.shapes"}

__all__ = sorted(_EXPORTS) + sorted(_MODULES)


def __getattr__(name: str):
    if name in _EXPORTS:
        return getattr(importlib.import_module(_EXPORTS[name]), name)
    if name in _MODULES:
        return importlib.import_module(_MODULES[name])
    raise AttributeError(f"module 'runtime' has no attribute {name!r}")
