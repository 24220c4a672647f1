"""`python -m derive`: the same as `regenerate-equations`."""

import sys

from derive.cli import main

sys.exit(main())
