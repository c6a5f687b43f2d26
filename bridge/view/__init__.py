"""The meshcat live view of a world: the drawing (:mod:`.scene`), the viewer node
(:mod:`.viewer`, ``python -m bridge.view``) and headless screenshots (:mod:`.screenshot`)."""

from .scene import BAR_COLOURS, HALO_COLOUR, ITEM_COLOURS, PERSON_COLOURS, SceneView
from .screenshot import screenshot
from .viewer import Viewer, build_parser, main

__all__ = [
    "BAR_COLOURS",
    "HALO_COLOUR",
    "ITEM_COLOURS",
    "PERSON_COLOURS",
    "SceneView",
    "Viewer",
    "build_parser",
    "main",
    "screenshot",
]
