"""``python -m runtime SCENE.toml ...``: the ``simulate`` command (runtime/app/cli.py).

Only the standard library is imported before the command's own Ctrl-C handling starts, so an
interrupt during start-up prints one line, not a traceback.
"""

import sys

try:
    from runtime.app.cli import main
except KeyboardInterrupt:
    print("python -m runtime: interrupted", file=sys.stderr)
    sys.exit(130)

sys.exit(main(prog="python -m runtime"))
