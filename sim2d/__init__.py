"""sim2d: the pymunk engine that stands in for the paper's Unity scene: maps and scenarios
as TOML, physics, scripted and autonomous people, the robot's body, and the engine node."""

from .engine import Engine
from .errors import ScenarioError, Sim2dError
from .generation.episodes import write_episode, write_house_episode
from .node import EngineNode
from .scenario.maps import GameMap, load_map
from .scenario.scenario import Scenario, load_scenario, scenario_names

__all__ = [
    "load_map",
    "load_scenario",
    "scenario_names",
    "write_episode",
    "write_house_episode",
    "Engine",
    "EngineNode",
    "GameMap",
    "Scenario",
    "ScenarioError",
    "Sim2dError",
]
