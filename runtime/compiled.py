"""Compiled code: numba's ``njit`` with an on-disk cache that cannot go stale.

Why: the engine's hot loops (narrow phase, kernel rows, contact forces, integrator stages) are
branches and small dense solves over a few numbers per contact, where NumPy's per-call cost is
most of the time and numba's compiled loops are not. numba caches compiled code on disk, but it
checks only the source file of the function it compiled: a kernel it calls that changed
(``regenerate-equations``, a mutation test, an edit) would leave stale machine code in use. So the
cache lives in a folder named after a hash of every source file of runtime/ and generated/ (and
the Python and numba versions): any change starts a fresh cache, and old ones are pruned.

``NUMBA_DISABLE_JIT=1`` runs the same functions as plain Python (slow; for debugging).
Set ``CURVED_EDGE_CACHE`` to put the caches somewhere else than ``~/.cache/curved-edge-physics``.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import sys
import warnings
from pathlib import Path

import numba
import numpy as np
from numba.core.errors import NumbaExperimentalFeatureWarning
from threadpoolctl import threadpool_limits

ROOT = Path(__file__).resolve().parent.parent
KEEP = 4  # cache folders kept (the newest), so switching between versions stays cheap


def _source_key() -> str:
    digest = hashlib.sha256(f"{sys.version}|{numba.__version__}".encode())
    for package in ("runtime", "generated"):
        for path in sorted((ROOT / package).rglob("*.py")):
            digest.update(str(path.relative_to(ROOT)).encode())
            digest.update(path.read_bytes())
    return digest.hexdigest()[:16]


def _cache_folder() -> Path:
    base = Path(
        os.environ.get("CURVED_EDGE_CACHE")
        or Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "curved-edge-physics"
    )
    folder = base / f"numba-{_source_key()}"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        old = sorted(
            (p for p in base.glob("numba-*") if p != folder),
            key=lambda p: p.stat().st_mtime,
            reverse=True,
        )
        for stale in old[KEEP - 1 :]:
            shutil.rmtree(stale, ignore_errors=True)
        os.utime(folder)
    except OSError:  # a read-only home: numba falls back to compiling without a cache
        pass
    return folder


CACHE_FOLDER = _cache_folder()
numba.config.CACHE_DIR = str(CACHE_FOLDER)

# One BLAS thread: the engine's matrices are small (an island's A, a few hundred rows at most),
# where threads only add synchronisation -- on a shared 2-core machine a 92-row product took
# 31 ms threaded against 0.15 ms on one thread (bench/README.md, Contact forces) -- and a
# fixed thread count keeps sums in one order, so reruns stay bit-for-bit equal.
import scipy.linalg  # noqa: E402, F401  (loads scipy's BLAS, which compiled code calls, first)

threadpool_limits(1, user_api="blas")


def cache_is_cold() -> bool:
    """True when no compiled code is cached yet for this source (the first run after an install or
    a change compiles the engine: a minute or more of CPU), so a front end can say why it waits."""
    try:
        return not any(CACHE_FOLDER.rglob("*.nbi"))
    except OSError:
        return True


def njit(*args, **kwargs):
    """``numba.njit`` with ``cache=True`` (on disk, in :data:`CACHE_FOLDER`) by default."""
    kwargs.setdefault("cache", True)
    return numba.njit(*args, **kwargs)


CHECK_CALLS = bool(os.environ.get("CURVED_EDGE_CHECK_CALLS"))  # tests turn it on (conftest)
_SCALARS = (bool, int, float, complex, np.generic)  # typed by their Python type alone


class Bound:
    """A compiled function called again and again with arguments of the same kinds.

    Why: numba resolves the types of every argument at every call from Python; for an argument
    that is itself a compiled function (how the engine passes the kernels of a scene's contact
    cases, so only those are imported) that costs ~4 us each, more than a small island's whole
    stage. The first call with arguments of new kinds goes through the dispatcher (compiling,
    or loading the cache); later calls -- from any Bound of the same function in this process,
    so a new World does not pay it again (~0.1 ms a function: a run of a few steps paid more
    for it than for its steps) -- go straight to the compiled entry point, which does not check
    types: the caller (runtime.step.stepper) builds every array with its dtype and layout, and
    with ``CURVED_EDGE_CHECK_CALLS`` set (the test suite does) every call is checked against
    the first, and a call with other kinds of arguments is a TypeError (a bug of the caller)."""

    _entries: dict = {}  # (dispatcher, kinds of the arguments) -> entry point, per process

    def __init__(self, dispatcher) -> None:
        self.dispatcher = dispatcher
        self.entry = None
        self.kinds: tuple = ()

    @staticmethod
    def _kinds(args: tuple) -> tuple:
        """What numba's type of each argument depends on: an array's dtype, dimensions, layout
        and writability, a tuple's members, a scalar's Python type (anything else: the object
        itself, as a compiled function passed as an argument is typed by its identity)."""
        return tuple(
            (a.dtype.num, a.ndim, a.flags.c_contiguous, a.flags.writeable)
            if hasattr(a, "flags")
            else Bound._kinds(a)
            if type(a) is tuple
            else type(a)
            if isinstance(a, _SCALARS)
            else ("object", id(a))
            for a in args
        )

    def __call__(self, *args):
        if self.entry is not None:
            if CHECK_CALLS and self._kinds(args) != self.kinds:
                raise TypeError(
                    f"{self.dispatcher.__name__} called with arguments of other kinds than at "
                    f"its first call: {self._kinds(args)} != {self.kinds}"
                )
            return self.entry(*args)
        kinds = self._kinds(args)
        entry = self._entries.get((self.dispatcher, kinds))
        if entry is not None:
            self.entry, self.kinds = entry, kinds
            return entry(*args)
        with warnings.catch_warnings():
            # compiled stages take the kernels of a scene's cases as function arguments
            # (runtime.solve.kernel_set): numba calls that experimental when it compiles them
            warnings.simplefilter("ignore", NumbaExperimentalFeatureWarning)
            result = self.dispatcher(*args)
        types = tuple(self.dispatcher.typeof_pyval(a) for a in args)
        overload = self.dispatcher.overloads.get(types)
        if overload is not None:
            self.entry, self.kinds = overload.entry_point, kinds
            self._entries[(self.dispatcher, kinds)] = self.entry
        return result


def leaf(function):
    """:func:`njit` without numba's reference counting, for small helpers that allocate no
    array.  Why: every call of a compiled function that is not inlined counts references of its
    array arguments with atomic operations, about 10 ns each here: 60-100 ns per call of a
    helper taking a few tables, more than the geometry it computes."""
    return njit(_nrt=False)(function)
