"""toyroom's brain: a Bayesian Theory of Mind of each person (:mod:`brain.model`), tracked
tick by tick (:mod:`brain.tracking`), a robot that acts on it (:mod:`brain.robot`), the files
it writes (:mod:`brain.outputs`), and the node that runs it all on the wire (:mod:`brain.node`)."""

from protocol import Observer

from .errors import BrainError, EngineLost
from .node import BRAIN_NAME, BrainNode
from .outputs import ShadowMinds, write_outputs
from .robot import RobotBrain, RobotTree
from .settings import ModelSettings, RobotSettings
from .tracking import MindTracker

__all__ = [
    "BRAIN_NAME",
    "write_outputs",
    "BrainError",
    "BrainNode",
    "EngineLost",
    "MindTracker",
    "ModelSettings",
    "Observer",
    "RobotBrain",
    "RobotSettings",
    "RobotTree",
    "ShadowMinds",
]
