"""``python -m toyroom.view``: the viewer node (``toyroom view``)."""

import sys

from .viewer import main

sys.exit(main())
