"""``python -m bridge.play``: ``toyroom play``'s server."""

import sys

from .node import main

sys.exit(main())
