"""Where things go in the frame, and the camera that frames them.

The view is laid out for a reference window (:data:`WINDOW`, the screenshot's 1000 x 750
pixels): the map on the left, as large as fits, and a column of text panels (what the
brain infers of each person, the legend) on the right, :data:`PANEL_FRACTION` of the width.
Everything is drawn on the floor plane (z = 0) of the scene's own metres, so a top-down
camera shows it as laid out: :func:`aim` points one straight down at the frame's centre
(a perspective camera with a narrow field of view, or an orthographic one). Sizes in
reference pixels (``px``) turn into metres through :attr:`Layout.px_per_m`. In a window of
another shape the frame's height still fills the window; its sides are cut or padded.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import meshcat
import meshcat.geometry as g

from protocol import Scene

WINDOW = (1000, 750)
"""The reference window (width, height) in pixels: the screenshot's size."""
PANEL_FRACTION = 0.26
"""The share of the frame's width kept for the panels, right of the map."""
MARGIN_PX = 6.0
"""Space around the map and the panels (reference pixels)."""
TOP_BAR_PX = 24.0
"""meshcat's 'Open Controls' bar covers the top right of the page: the panels start below."""
FIELD_OF_VIEW = 8.0
"""The perspective camera's vertical field of view (degrees): narrow (the camera about 7
frame heights away), so that walls and bodies standing up from the floor barely lean
outwards, even on a small map."""
PANEL_Z = 0.4
"""Height (metres) of the panels: above the walls, which a perspective camera shows leaning
out a little at the map's edge."""


@dataclass(frozen=True)
class Rect:
    """A rectangle in reference pixels, from the frame's top left corner (y down)."""

    left: float
    top: float
    width: float
    height: float


@dataclass(frozen=True)
class Layout:
    """The frame of one scene: the map's and the panels' places, and the scale."""

    px_per_m: float
    """Reference pixels per scene metre."""
    left_m: float
    """The scene x (metres) of the frame's left edge."""
    top_m: float
    """The scene y (metres) of the frame's top edge."""
    map: Rect
    panel: Rect

    @property
    def width_m(self) -> float:
        """The frame's width (metres)."""
        return WINDOW[0] / self.px_per_m

    @property
    def height_m(self) -> float:
        """The frame's height (metres)."""
        return WINDOW[1] / self.px_per_m

    @property
    def centre(self) -> tuple[float, float]:
        """The frame's centre in scene metres (x, y)."""
        return self.left_m + self.width_m / 2, self.top_m - self.height_m / 2

    def metres(self, px: float) -> float:
        """A length in reference pixels as scene metres."""
        return px / self.px_per_m

    def point(self, u: float, v: float) -> tuple[float, float]:
        """The scene point (metres) at reference pixel ``(u, v)`` (from the top left)."""
        return self.left_m + u / self.px_per_m, self.top_m - v / self.px_per_m


def frame(scene: Scene) -> Layout:
    """Lay out ``scene``'s map (its whole grid, ``columns x rows`` cells) and the panels in
    the reference window: the map scaled to fill its share, centred in it."""
    width_px, height_px = WINDOW
    panel_left = width_px * (1.0 - PANEL_FRACTION)
    room_w, room_h = panel_left - 2 * MARGIN_PX, height_px - 2 * MARGIN_PX
    map_w_m, map_h_m = scene.columns * scene.cell_size, scene.rows * scene.cell_size
    scale = min(room_w / map_w_m, room_h / map_h_m)
    drawn = Rect(
        MARGIN_PX + (room_w - map_w_m * scale) / 2,
        MARGIN_PX + (room_h - map_h_m * scale) / 2,
        map_w_m * scale,
        map_h_m * scale,
    )
    panel = Rect(
        panel_left,
        TOP_BAR_PX + MARGIN_PX,
        width_px - panel_left - MARGIN_PX,
        height_px - TOP_BAR_PX - 2 * MARGIN_PX,
    )
    return Layout(
        px_per_m=scale,
        left_m=scene.origin.x - drawn.left / scale,
        top_m=scene.origin.y + map_h_m + drawn.top / scale,
        map=drawn,
        panel=panel,
    )


def aim(vis: meshcat.Visualizer, layout: Layout, ortho: bool = False) -> None:
    """Replace meshcat's camera by one looking straight down at the frame's centre (the
    drawing is moved so that this centre is the origin), north (+y) up, the frame's height
    filling the window: a perspective camera (:data:`FIELD_OF_VIEW`), or with ``ortho`` an
    orthographic one. Orbit, pan and zoom with the mouse still work."""
    half_h, half_w = layout.height_m / 2, layout.width_m / 2
    distance = half_h / math.tan(math.radians(FIELD_OF_VIEW) / 2)
    camera: g.OrthographicCamera | g.PerspectiveCamera
    if ortho:
        # meshcat's page keeps `left` and sets `right` from the window's shape
        camera = g.OrthographicCamera(-half_w, half_w, half_h, -half_h, distance / 100, distance * 10)
    else:
        camera = g.PerspectiveCamera(
            fov=FIELD_OF_VIEW, aspect=WINDOW[0] / WINDOW[1], near=distance / 100, far=distance * 10
        )
    vis["/Cameras/default/rotated"].set_object(camera)
    # The camera's frame is rotated (its y is the scene's z): this is `distance` above the
    # origin, a hair south of it so that the orbit controls keep north up.
    vis["/Cameras/default/rotated/<object>"].set_property("position", [0.0, distance, distance * 1e-4])
