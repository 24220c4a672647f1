"""``python -m runtime SCENE.toml ...``: the ``simulate`` command (runtime/app/cli.py).

Only the standard library is imported before the command's own Ctrl-C handling starts, so an
interrupt during start-up prints one line, not a traceback.
"""

import os
import sys

try:
    from runtime.app.interrupts import redeliver

    sys.unraisablehook = redeliver  # before the command's modules load (runtime.app.interrupts)
    from runtime.app.cli import main
except KeyboardInterrupt:
    print("python -m runtime: interrupted", file=sys.stderr, flush=True)
    # at once: a half-imported library's shutdown hooks could meet the interrupt again and end
    # the process by the signal (-2, seen once in CI-like runs) instead of the status 130
    os._exit(130)

sys.exit(main(prog="python -m runtime"))
