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
