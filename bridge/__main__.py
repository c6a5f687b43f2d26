"""``python -m bridge`` runs the ``toyroom`` command line."""

import sys

from .cli import main

sys.exit(main())
