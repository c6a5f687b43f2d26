"""Text for the live view: lines of coloured spans (and colour swatches) drawn into PNG
images with Pillow, shown on flat planes lying on the floor, facing the top-down camera.

Sizes are in reference pixels (see :mod:`.layout`); images are drawn at :data:`SUPERSAMPLE`
times that, so text stays sharp when the window is larger than the reference or the camera
zooms in.
"""

from __future__ import annotations

import io
from collections.abc import Sequence
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import meshcat.geometry as g
from matplotlib import font_manager
from PIL import Image, ImageDraw, ImageFont

from .colours import INK, rgb

SUPERSAMPLE = 2
"""Image pixels per reference pixel."""
LINE_SPACING = 1.3
"""A line's height as a multiple of its font size."""
SMALLEST_FONT_PX = 10.0
"""Text is never shrunk below this (reference pixels); lines longer than fit are cut."""


@dataclass(frozen=True)
class Span:
    """A run of text in one colour (``0xRRGGBB``), bold or not."""

    text: str
    colour: int = INK
    bold: bool = False


@dataclass(frozen=True)
class Swatch:
    """A colour sample drawn in line with the text, one font size wide: a filled
    ``square`` or ``disc``, a ``ring``, or a short flat ``bar``."""

    colour: int
    shape: str = "square"


Part = Span | Swatch
Line = tuple[Part, ...]


@lru_cache(maxsize=64)
def font(size: int, bold: bool = False) -> ImageFont.FreeTypeFont:
    """DejaVu Sans (shipped with matplotlib) at ``size`` image pixels."""
    path = font_manager.findfont(
        font_manager.FontProperties(family="DejaVu Sans", weight="bold" if bold else "normal")
    )
    return ImageFont.truetype(path, size)


def _part_width(part: Part, size: int) -> float:
    """The width of ``part`` in image pixels at font ``size``."""
    if isinstance(part, Swatch):
        return size * 1.4
    return float(font(size, part.bold).getlength(part.text))


def line_width(line: Line, size: int) -> float:
    """The width of ``line`` in image pixels at font ``size``."""
    return sum(_part_width(part, size) for part in line)


def fit_font(lines: Sequence[Line], width_px: float, height_px: float, largest: float) -> float:
    """The largest font size (reference pixels, at most ``largest``, at least
    :data:`SMALLEST_FONT_PX`) at which ``lines`` fit ``width_px`` x ``height_px``."""
    probe = 40
    widest = max((line_width(line, probe) for line in lines), default=0.0)
    by_width = width_px * probe / widest if widest else largest
    by_height = height_px / (max(len(lines), 1) * LINE_SPACING)
    return max(SMALLEST_FONT_PX, min(largest, by_width, by_height))


def _swatch(draw: ImageDraw.ImageDraw, swatch: Swatch, x: float, y: float, size: int) -> None:
    """Draw ``swatch`` with its left edge at ``x``, centred on the line whose top is ``y``."""
    side = size * 0.8
    top = y + (size * LINE_SPACING - side) / 2
    box = (x + size * 0.1, top, x + size * 0.1 + side, top + side)
    colour = rgb(swatch.colour)
    if swatch.shape == "disc":
        draw.ellipse(box, fill=colour, outline=rgb(INK), width=max(1, size // 14))
    elif swatch.shape == "ring":
        draw.ellipse(box, outline=colour, width=max(2, size // 5))
    elif swatch.shape == "bar":
        draw.rectangle((box[0], top + side * 0.3, box[2] + size * 0.3, top + side * 0.7), fill=colour)
    else:
        draw.rectangle(box, fill=colour, outline=rgb(INK), width=max(1, size // 14))


def _cut(line: Line, size: int, room: float) -> Line:
    """``line`` shortened to ``room`` image pixels, its last text ending in an ellipsis."""
    kept: list[Part] = []
    used = 0.0
    for part in line:
        width = _part_width(part, size)
        if used + width <= room:
            kept.append(part)
            used += width
            continue
        if isinstance(part, Span):
            text = part.text
            while text and used + font(size, part.bold).getlength(text + "…") > room:
                text = text[:-1]
            kept.append(Span(text + "…", part.colour, part.bold))
        break
    return tuple(kept)


def draw_lines(
    lines: Sequence[Line],
    width_px: float,
    height_px: float,
    font_px: float,
    background: tuple[int, int, int, int] = (255, 255, 255, 235),
    border: int | None = None,
    padding_px: float = 6.0,
) -> bytes:
    """A PNG, ``width_px`` x ``height_px`` reference pixels, of ``lines`` left-aligned from
    the top at ``font_px``, on ``background`` (RGBA) with an optional ``border`` colour."""
    scale = SUPERSAMPLE
    image = Image.new("RGBA", (round(width_px * scale), round(height_px * scale)), background)
    draw = ImageDraw.Draw(image)
    size = max(1, round(font_px * scale))
    pad = padding_px * scale
    if border is not None:
        draw.rectangle((0, 0, image.width - 1, image.height - 1), outline=rgb(border), width=2 * scale)
    y = pad
    for line in lines:
        x = pad
        for part in _cut(line, size, image.width - 2 * pad):
            if isinstance(part, Swatch):
                _swatch(draw, part, x, y, size)
            else:
                offset = (size * LINE_SPACING - size) / 2
                draw.text((x, y + offset), part.text, fill=rgb(part.colour), font=font(size, part.bold))
            x += _part_width(part, size)
        y += size * LINE_SPACING
    return _png(image)


def draw_label(
    text: str,
    font_px: float,
    ink: int = INK,
    background: tuple[int, int, int, int] = (255, 255, 255, 235),
    border: int | None = None,
    max_width_px: float | None = None,
) -> tuple[bytes, float, float]:
    """A one-line label: its PNG and its size (width, height) in reference pixels; the font
    shrinks so that it is at most ``max_width_px`` wide."""
    pad = font_px * 0.3
    natural = font(40, True).getlength(text) / 40  # width per font pixel
    size = font_px
    if max_width_px is not None:
        size = min(font_px, max(SMALLEST_FONT_PX, (max_width_px - 2 * pad) / max(natural, 1e-6)))
    width, height = natural * size + 2 * pad + 2, size * LINE_SPACING + 2 * pad
    png = draw_lines([(Span(text, ink, bold=True),)], width, height, size, background, border, pad)
    return png, width, height


def _png(image: Image.Image) -> bytes:
    buffer = io.BytesIO()
    image.save(buffer, format="PNG", optimize=False, compress_level=3)
    return buffer.getvalue()


class Plane(g.Geometry):
    """A flat rectangle ``width`` x ``height`` (metres) in the x-y plane, facing +z (three.js's
    ``PlaneGeometry``, which meshcat's Python side does not name)."""

    def __init__(self, width: float, height: float) -> None:
        super().__init__()
        self.width, self.height = width, height

    def lower(self, object_data: Any) -> dict[str, Any]:
        return {"uuid": self.uuid, "type": "PlaneGeometry", "width": self.width, "height": self.height}


FRONT_SIDE = 0
"""three.js's ``FrontSide``: a plane is drawn from above only (never its mirror image)."""


def plane(png: bytes, width_m: float, height_m: float) -> tuple[Plane, g.MeshBasicMaterial]:
    """A flat, unlit rectangle ``width_m`` x ``height_m`` (metres) facing up, showing ``png``
    (transparent where the image is), for ``node.set_object(*plane(...))``."""
    texture = g.ImageTexture(image=g.PngImage(png))
    return Plane(width_m, height_m), g.MeshBasicMaterial(map=texture, transparent=True, side=FRONT_SIDE)
