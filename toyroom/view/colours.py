"""The live view's colours (``0xRRGGBB``), shared by the drawing, its labels and its legend.

Bodies, floors and bars are drawn unlit, so each shows on screen exactly in its colour here
(the tests find them by it)."""

from __future__ import annotations

from protocol import ItemShape

REGION_COLOURS = [0xE8D5B7, 0xB7D3E8, 0xC8E8B7, 0xE8B7D9, 0xF2E6A0, 0xD0D0D0, 0xB7E8E0, 0xE0C0A0]
"""Floors: one tint per region, in the scene's order."""
PERSON_COLOURS = [0x1F77B4, 0x2CA02C, 0x9467BD, 0x8C564B, 0x17BECF]
"""People, in the scene's order (their discs, their labels' borders, their panel headings)."""
BAR_COLOURS = [0x9ECAE1, 0xA1D99B, 0xCBC9E2, 0xD9B99B, 0x9EDAE5]
"""Belief bars: a light tint of their person's colour."""
ITEM_COLOURS: dict[str, int] = {
    ItemShape.BALL: 0xD62728,
    ItemShape.BOARD: 0xFF7F0E,
    ItemShape.MARBLE: 0xE377C2,
    ItemShape.BLOCK: 0xBCBD22,
}
"""Items by shape; a shape not listed is drawn as a block."""
ROBOT_COLOUR = 0x444444
HALO_COLOUR = 0xFF0000
"""The ring at a person's feet while a false belief is flagged."""
FALSE_TEXT = 0xC00000
"""Panel lines about a false belief (a darker red than the ring, to read on white)."""
DOOR_COLOUR = 0xFFFFFF
WALL_COLOUR = 0x555555
SPOT_COLOUR = 0x5A5A5A
PLAY_SPOT_COLOUR = 0x3C9A64
INK = 0x222222
"""Text."""
MUTED = 0x666666
"""Secondary text (section headings, the tick)."""


def person_colour(index: int) -> int:
    """The colour of the ``index``-th person of the scene (colours repeat after five)."""
    return PERSON_COLOURS[index % len(PERSON_COLOURS)]


def bar_colour(index: int) -> int:
    """The belief-bar tint of the ``index``-th person of the scene."""
    return BAR_COLOURS[index % len(BAR_COLOURS)]


def item_colour(shape: str) -> int:
    """An item's colour by its shape (any other shape, known or not, is a block's)."""
    return ITEM_COLOURS.get(shape, ITEM_COLOURS[ItemShape.BLOCK])


def rgb(colour: int) -> tuple[int, int, int]:
    """``0xRRGGBB`` as an ``(r, g, b)`` tuple of 0-255 ints."""
    return (colour >> 16) & 255, (colour >> 8) & 255, colour & 255
