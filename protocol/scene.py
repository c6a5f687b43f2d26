"""The scene description an engine sends in its handshake.

The scene is general: any set of regions made of grid cells, one-cell doors that join two
regions, item locations ("spots": a storage shelf, a play spot, a basket, a box), agents and
items, and *visibility given per walkable cell* as the set of item locations visible from it.
Room groups (the paper's "from P1 or S1 you see P1 and S1") are one way to fill the
visibility table; line of sight on an open map, or a one-room Sally-Anne map with two
containers, are others, with no change to the protocol.

The walkable cells are the union of the regions' cells and the door cells. A door cell
belongs to no region; what it sees is its own visibility entry (sim2d's maps give it the
spots located in the two regions it joins).
"""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec

from .geometry import Cell, Vec2
from .message import Id
from .vocabulary import described, known

Metres = Annotated[float, msgspec.Meta(gt=0.0)]


class RegionKind(enum.StrEnum):
    """What a region is for (an open vocabulary: :mod:`protocol.vocabulary`).

    Only ``outside`` means anything to the brain: a person who walks into it has chosen
    to leave (the planner's "out" goal), and no waiting is read there. ``playground``,
    ``storage``, ``entrance`` and ``room`` are labels for people and viewers (play spots
    are ``Location.play``, sight is the visibility table); the brain reads a kind it does
    not know as ``room``.
    """

    PLAYGROUND = "playground"
    STORAGE = "storage"
    ENTRANCE = "entrance"
    OUTSIDE = "outside"
    ROOM = "room"


RegionKindName = Annotated[str, described(RegionKind, "region kind")]


class Region(msgspec.Struct, frozen=True):
    """A room or area: an id, what kind it is, and the walkable cells it covers."""

    id: Id
    kind: RegionKindName
    """A :class:`RegionKind` member when known, else the string as sent."""
    cells: tuple[Cell, ...]
    name: str = ""
    """Human-readable name, e.g. ``"Playground 1"``."""

    def __post_init__(self) -> None:
        msgspec.structs.force_setattr(self, "kind", known(RegionKind, self.kind))


class Door(msgspec.Struct, frozen=True):
    """A one-cell door joining two regions; the cell touches a cell of each (4-neighbour)."""

    id: Id
    cell: Cell
    joins: tuple[Id, Id]


class Location(msgspec.Struct, frozen=True):
    """An item location (a spot where items rest), inside one region.

    ``play`` marks a play spot: a person holding an item may play with it there. ``use``
    marks a place where a person uses an item resting there without carrying it (eating at
    a stall): the ``use`` event. ``capacity``: at most this many items rest there at once
    (``None``: any number); the brain rules out worlds that break it.
    """

    id: Id
    region: Id
    cell: Cell
    play: bool = False
    use: bool = False
    capacity: Annotated[int, msgspec.Meta(ge=1)] | None = None


class Visibility(msgspec.Struct, frozen=True):
    """The item locations a person standing on ``cell`` sees (and so sees items at, or missing from)."""

    cell: Cell
    locations: tuple[Id, ...]


class AgentKind(enum.Enum):
    """People are observed by the brain; robots are driven by it."""

    PERSON = "person"
    ROBOT = "robot"


class AgentSpec(msgspec.Struct, frozen=True):
    """An agent of the scene.

    ``home`` is the cell the agent starts on (the robot returns there when idle).
    ``acts`` matters for robots only: ``True`` when the robot may act (the brain sends it
    commands), ``False`` when it only observes.
    """

    id: Id
    kind: AgentKind
    home: Cell
    name: str = ""
    radius: Metres = 0.25
    """Body radius in metres."""
    acts: bool = True


class ItemShape(enum.StrEnum):
    """How viewers draw an item (an open vocabulary: a viewer draws a shape it does not
    know as a block)."""

    BALL = "ball"
    BOARD = "board"
    MARBLE = "marble"
    BLOCK = "block"


ItemShapeName = Annotated[str, described(ItemShape, "item shape")]


class ItemSpec(msgspec.Struct, frozen=True):
    """A movable item (a toy).

    ``absent``: the item is not in the scene (no state lists it), though people may want
    it and believe it is somewhere; the brain then counts "absent" as one more place an
    item can be (never seen, never taken).

    ``portable``: whether a person can take and carry it (protocol 1.4; ``True`` when not
    sent). ``False`` declares the item fixed (a parked food truck, a stall): it only ever
    rests where it is (or is absent), so no world the brain considers has it carried, no
    one takes it, and beliefs about it are over resting places only. There is no implicit
    default from ``use`` locations: the scene does not say where an item rests (the state
    does), and an item used in place may still be portable.
    """

    id: Id
    shape: ItemShapeName = ItemShape.BLOCK
    """An :class:`ItemShape` member when known, else the string as sent."""
    name: str = ""
    absent: bool = False
    portable: bool = True

    def __post_init__(self) -> None:
        msgspec.structs.force_setattr(self, "shape", known(ItemShape, self.shape))


class Household(msgspec.Struct, frozen=True):
    """The household an episode is a day of (protocol 1.5): the same map, people and items
    lived over days, each day starting where the last ended. A brain with a memory file
    starts each person's estimate from what it learned of them on the days before
    (``id`` names the household in that memory); ``day`` counts from 1."""

    id: Id
    day: Annotated[int, msgspec.Meta(ge=1)] = 1


class Scene(msgspec.Struct, frozen=True):
    """Everything a brain or viewer needs to know about the world that does not change.

    Units: ``cell_size`` and ``origin`` in metres; the grid is ``columns`` x ``rows`` cells.
    ``household`` (optional, protocol 1.5): the household and day this episode is, if it is
    one (:class:`Household`); absent, an episode of its own.
    """

    name: str
    cell_size: Metres
    origin: Vec2
    columns: Annotated[int, msgspec.Meta(ge=1)]
    rows: Annotated[int, msgspec.Meta(ge=1)]
    regions: tuple[Region, ...]
    doors: tuple[Door, ...]
    locations: tuple[Location, ...]
    visibility: tuple[Visibility, ...]
    agents: tuple[AgentSpec, ...]
    items: tuple[ItemSpec, ...]
    household: Household | None = None

    def walkable(self) -> frozenset[tuple[int, int]]:
        """The walkable cells as ``(col, row)`` tuples: region cells and door cells."""
        cells = {(c.col, c.row) for region in self.regions for c in region.cells}
        cells.update((d.cell.col, d.cell.row) for d in self.doors)
        return frozenset(cells)

    def cell_centre(self, cell: Cell) -> Vec2:
        """The centre of ``cell`` in world metres."""
        return Vec2(
            self.origin.x + (cell.col + 0.5) * self.cell_size,
            self.origin.y + (cell.row + 0.5) * self.cell_size,
        )
