"""Scenarios and maps as data: read from TOML files (the bundled ones live in
``sim2d/scenarios/``) and checked section by section, every table strict (:mod:`.tables`).

A map (:mod:`.maps`) is rooms, doors, item spots, visibility and homes; a scenario
(:mod:`.scenario`) puts items and agents on one, with a scripted person's route
(:mod:`.script`), an autonomous person's first jobs in a task episode (:mod:`.jobs`) and how
autonomous people behave (:mod:`.autonomy`).
"""

from .autonomy import Autonomy
from .jobs import Jobs
from .maps import SCENARIO_DIR, GameMap, load_map
from .scenario import AgentSetup, ItemSetup, Scenario, load_scenario, scenario_names
from .script import Step

__all__ = [
    "SCENARIO_DIR",
    "load_map",
    "load_scenario",
    "scenario_names",
    "AgentSetup",
    "Autonomy",
    "GameMap",
    "ItemSetup",
    "Jobs",
    "Scenario",
    "Step",
]
