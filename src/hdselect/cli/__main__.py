"""``python -m hdselect.cli``: the command line."""

import sys

from hdselect.cli.main import main

sys.exit(main())
