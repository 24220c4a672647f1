"""Which compiled code is cached on disk (runtime/compiled.py), and which must not be.

Why: numba keys a cache entry by its argument types. The compiled stages (runtime/step/
compiled_stages.py) take the scene's row kernels as function arguments, whose types are the
kernels' dispatcher objects, different in every process: no process found another's entry,
each appended one more, and re-saving the index re-pickled entries whose dispatchers the
process no longer had -- `simulate` then stopped with "ReferenceError: underlying object has
vanished" on a valid scene, depending on what ran before and on the garbage collector.
"""

from __future__ import annotations

from runtime.collide import broadphase
from runtime.step import compiled_stages


def test_stages_taking_kernels_as_arguments_are_not_cached_on_disk():
    for stage in (compiled_stages.step, compiled_stages.accelerations):
        assert type(stage._cache).__name__ == "NullCache", stage


def test_plain_compiled_functions_are():
    assert type(broadphase.sweep._cache).__name__ == "FunctionCache"
