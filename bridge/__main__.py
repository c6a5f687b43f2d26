"""``python -m bridge`` runs the ``toyroom`` command line."""

import sys

from .app.cli import main

sys.exit(main())
