"""``python -m runtime SCENE.toml ...``: the ``simulate`` command (runtime/app/cli.py).

Only the standard library is imported before the command's own Ctrl-C handling starts, so an
interrupt during start-up prints one line, not a traceback.
"""

import _thread
import os
import sys


def _again(unraisable, default=sys.__unraisablehook__):
    """A Ctrl-C that lands in a finaliser while the command's modules load is delivered again
    (runtime.app.cli.redeliver, which takes over once they have loaded), not printed."""
    if unraisable.exc_type is not None and issubclass(unraisable.exc_type, KeyboardInterrupt):
        try:
            _thread.start_new_thread(_thread.interrupt_main, ())
            return
        except RuntimeError:  # at shutdown
            pass
    default(unraisable)


sys.unraisablehook = _again
try:
    from runtime.app.cli import main
except KeyboardInterrupt:
    print("python -m runtime: interrupted", file=sys.stderr, flush=True)
    # at once: a half-imported library's shutdown hooks could meet the interrupt again and end
    # the process by the signal (-2, seen once in CI-like runs) instead of the status 130
    os._exit(130)

sys.exit(main(prog="python -m runtime"))
