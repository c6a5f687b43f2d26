"""Random episodes: scenario (and map) files made from a seed (:mod:`.episodes`), everyday or
built around one of the robot's tasks (:mod:`.tasks`)."""

from .episodes import KINDS, MAPS, MINDS, house_map, write_episode, write_house_episode
from .tasks import BELIEF_TASKS, TASKS

__all__ = [
    "BELIEF_TASKS",
    "KINDS",
    "MAPS",
    "MINDS",
    "TASKS",
    "house_map",
    "write_episode",
    "write_house_episode",
]
