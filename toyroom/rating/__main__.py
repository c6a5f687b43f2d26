"""``python -m toyroom.rating``: the rating server (``toyroom rate``)."""

import sys

from .node import main

sys.exit(main())
