"""Every compiled stage is cached on disk (runtime/compiled.py), so a run after the first on a
machine loads the engine instead of compiling it.

Why: the compiled stages (runtime/step/compiled_stages.py, compiled_frame.py) once took the
scene's row kernels as function arguments, whose numba types are the kernels' dispatcher
objects, different in every process: no process found another's cache entry (each run compiled
the stages afresh, ~20 s of CPU), and re-saving the index re-pickled entries whose dispatchers
the process no longer had (`ReferenceError: underlying object has vanished` from `simulate`).
They now call the generated loops as globals (runtime/solve/kernel_set.py).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from runtime.collide import broadphase
from runtime.step import compiled_frame, compiled_stages

ROOT = Path(__file__).resolve().parents[2]


def test_the_compiled_stages_are_cached_on_disk():
    stages = (compiled_stages.step, compiled_stages.accelerations, compiled_frame.settle_frame)
    for stage in (*stages, broadphase.sweep):
        assert type(stage._cache).__name__ == "FunctionCache", stage


def test_a_second_process_loads_the_stages_instead_of_compiling_them():
    """Two fresh processes in a row on the machine's cache: whatever the first had to compile
    it saved, and the second finds the stages the disc-in-bowl run calls (the step, which contains the
    accelerations, and the frame) in the cache (numba's
    own record of cache hits and misses; before, every process missed)."""
    code = (
        "import runtime\n"
        "from runtime.step import compiled_frame, compiled_stages\n"
        "s = runtime.load_scene('scenes/disc_in_bowl.toml')\n"
        "runtime.simulate(s, duration=0.01, dt=1e-3)\n"
        "for f in (compiled_stages.step, compiled_frame.settle_frame):\n"
        "    print(len(f.stats.cache_hits), len(f.stats.cache_misses))\n"
    )  # fmt: skip
    for _ in range(2):
        done = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                              text=True, check=True, timeout=900)  # fmt: skip
    counts = [tuple(int(x) for x in line.split()) for line in done.stdout.splitlines()]
    assert counts == [(1, 0), (1, 0)]  # the step and the frame, each loaded, none compiled
