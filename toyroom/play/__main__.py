"""``python -m toyroom.play``: ``toyroom play``'s server."""

import sys

from .node import main

sys.exit(main())
