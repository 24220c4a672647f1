"""The compiled row kernels of a scene's contact cases, as arguments for compiled stages.

Why: a compiled stage (runtime.step.compiled_stages) evaluates the rows of contacts of every
case a scene has; it takes the four cases' batch loops as arguments, so only the kernels of the
cases the scene can produce are imported (model only what a scene needs) and a case it cannot
produce is a stub that is never called. numba compiles the stage once for each combination
of cases and keeps it in its cache.
"""

from __future__ import annotations

from collections.abc import Iterable

import generated
from runtime.compiled import njit
from runtime.solve.rows import load_compiled_cases


@njit
def no_rows(poses, velocities, body1, body2, geometry, static2, members, jacobian_out, bias_out):
    """The rows of a case the scene cannot produce: never asked for (members is empty)."""
    return


def row_kernels(cases: Iterable[str]) -> tuple:
    """(batch_rows of case id 0, 1, 2, 3): the generated loop of each case of ``cases``, the
    stub for the others."""
    modules = load_compiled_cases(cases)
    return tuple(
        modules[case].batch_rows if case in modules else no_rows
        for case in sorted(generated.CASE_ID.values())
    )
