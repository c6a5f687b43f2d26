"""The meshcat live view of a world: the layout and camera (:mod:`.layout`), the map
(:mod:`.floorplan`), text and panels (:mod:`.text`, :mod:`.panel`), the drawing
(:mod:`.scene`), the viewer node (:mod:`.viewer`, ``python -m toyroom.view``) and headless
screenshots (:mod:`.screenshot`)."""

from .colours import BAR_COLOURS, HALO_COLOUR, ITEM_COLOURS, PERSON_COLOURS, REGION_COLOURS
from .layout import PANEL_FRACTION, WINDOW, Layout, aim, frame
from .scene import MIND_HZ, REFRESH_HZ, SceneView
from .screenshot import screenshot
from .viewer import Viewer, build_parser, main

__all__ = [
    "BAR_COLOURS",
    "HALO_COLOUR",
    "ITEM_COLOURS",
    "MIND_HZ",
    "PANEL_FRACTION",
    "PERSON_COLOURS",
    "REFRESH_HZ",
    "REGION_COLOURS",
    "WINDOW",
    "Layout",
    "SceneView",
    "Viewer",
    "aim",
    "build_parser",
    "frame",
    "main",
    "screenshot",
]
