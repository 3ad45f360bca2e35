"""``python -m hdselect``: the command line, as ``hdselect`` (and ``python -m hdselect.cli``)."""

import sys

from hdselect.cli.main import main

sys.exit(main())
