"""Test-suite setup: make the project packages and the test helpers importable.

`make test` installs the project (editable), but a bare `pytest` in a checkout should work too, so
the repository root (for ``derive``, ``generated``, ``runtime``) and ``tests/`` (for the shared
helpers ``oracle`` and ``strategies``) go on sys.path.
"""

import os
import sys
from pathlib import Path

# every call of a compiled stage is checked against the kinds of its first arguments
# (runtime.compiled.Bound), here and in the subprocesses tests start
os.environ["CURVED_EDGE_CHECK_CALLS"] = "1"

_TESTS = Path(__file__).resolve().parent
for _path in (_TESTS.parent, _TESTS):
    if str(_path) not in sys.path:
        sys.path.insert(0, str(_path))


def _no_local_constants() -> None:
    """Hypothesis (>= 6.131) mixes the literal constants of every project module imported so
    far into what it draws, so a derandomized test drew other examples depending on which
    modules the other tests of its process had imported: under pytest-xdist, adding a test
    file or a constant to runtime/settings.py changed the examples of
    tests/runtime/test_lcp_property.py, and one of them failed in `make test` only (a warm
    restart of an ill-scaled problem, b ~ 8e9). Without them every property test draws the same
    examples in any process, alone or in the suite."""
    try:
        from hypothesis.internal.conjecture import providers
        from hypothesis.internal.constants_ast import Constants
    except ImportError:  # another Hypothesis: nothing of the kind to turn off
        return
    if hasattr(providers, "_get_local_constants"):
        empty = Constants()
        providers._get_local_constants = lambda: empty


_no_local_constants()
