"""Ctrl-C and SIGTERM that land in a finaliser, delivered again instead of printed.

Why: llvmlite frees its objects in finalisers while numba compiles (at start-up). An interrupt
that arrives there cannot propagate: Python prints it as "Exception ignored ... Traceback" and
goes on, so a Ctrl-C during start-up printed a traceback (and was half lost). Standard library
only: ``python -m runtime`` installs the hook before it imports anything else.
"""

from __future__ import annotations

import _thread
import signal
import sys
from typing import Any


class Terminated(KeyboardInterrupt):
    """SIGTERM, handled like Ctrl-C (clean-up runs) but with exit status 143."""


def redeliver(unraisable: Any, default: Any = sys.__unraisablehook__) -> None:
    """sys.unraisablehook: an interrupt raised in a finaliser is delivered to the main thread
    again, where the command turns it into one line -- from a helper thread, so that it arrives
    after this hook has returned (raised in the hook, it would be printed the same way).
    Anything else, or an interrupt at shutdown (no thread can start), goes to ``default``."""
    kind = unraisable.exc_type
    if kind is not None and issubclass(kind, KeyboardInterrupt):
        signum = signal.SIGTERM if issubclass(kind, Terminated) else signal.SIGINT
        try:
            _thread.start_new_thread(_thread.interrupt_main, (signum,))
            return
        except RuntimeError:
            pass
    default(unraisable)
