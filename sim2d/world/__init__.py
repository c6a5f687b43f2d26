"""The simulated world: bodies in pymunk (:mod:`.physics`) between walls made from the map's
grid (:mod:`.walls`), moved along shortest paths of cells (:mod:`.paths`); who holds what and
the actions every agent performs (:mod:`.world`); the bodies as protocol states
(:mod:`.states`)."""

from .paths import path_to_any, shortest_path
from .physics import Physics
from .states import BodyStates
from .walls import wall_segments
from .world import PERSON_SPEED, Agent, Item, World

__all__ = [
    "PERSON_SPEED",
    "path_to_any",
    "shortest_path",
    "wall_segments",
    "Agent",
    "BodyStates",
    "Item",
    "Physics",
    "World",
]
