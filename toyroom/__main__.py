"""``python -m toyroom`` runs the ``toyroom`` command line."""

import sys

from .cli.cli import main

sys.exit(main())
