"""The robot: what the world calls for (:mod:`.situation`), the behaviour tree that turns
it into commands (:mod:`.tree`, :mod:`.branches`, :mod:`.behaviours`), the commands it has
sent (:mod:`.commands`), and the controller the brain node ticks (:mod:`.controller`)."""

from .commands import CommandBook
from .context import RobotContext, Skip, Step
from .controller import RobotBrain
from .situation import Inform, Occupied, PutBack, Situation, Task
from .tree import RobotTree

__all__ = [
    "CommandBook",
    "Inform",
    "Occupied",
    "PutBack",
    "RobotBrain",
    "RobotContext",
    "RobotTree",
    "Skip",
    "Situation",
    "Step",
    "Task",
]
