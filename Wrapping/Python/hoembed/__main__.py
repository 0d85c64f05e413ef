"""``python -m hoembed``: the command-line program (see hoembed.cli)."""

import sys

from .cli import main

sys.exit(main())
