"""``python -m toyroom.gateway``: the gateway node (``toyroom gateway``)."""

import sys

from .node import main

sys.exit(main())
