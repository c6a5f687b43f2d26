"""The robot's behaviour tree (py_trees), its branches in the paper's priority order.

1. inform: a person heads for an item that is not where they believe: tell them where it is;
2. swap: a person's preferred item is held by someone else: tell them it is occupied, ask
   the holder to swap; on yes, bring each item to the other person; on no, tell the person
   where the other item is;
3. put back: an item was moved while the person who left it was away: bring it back to
   where that person believes it is;
4. go home.

Each action is a command on the wire whose statuses are awaited, with a timeout; a failed
command or a refusal fails its branch, and the next tick the tree chooses again (a task is
tried ``attempts`` times at most, so the tree never sticks). A task, once begun, is carried
through before another begins; going home gives way at once. The branches are built in
:mod:`.branches`, from the behaviours of :mod:`.behaviours`; the tree reads and writes one
:class:`~.context.RobotContext` on its own blackboard namespace, so two brains in one
process never share state.
"""

from __future__ import annotations

import uuid

import py_trees
from py_trees.common import Access

from protocol import GridCell

from ..settings import RobotSettings
from .branches import build_tree
from .commands import CommandBook
from .context import RobotContext
from .situation import Situation


class RobotTree:
    """A tree, its blackboard namespace and context: what the brain ticks once per step."""

    def __init__(self, robot: str, home: GridCell, settings: RobotSettings | None = None) -> None:
        self.namespace = f"/brain_{uuid.uuid4().hex[:8]}"
        self.context = RobotContext(
            robot=robot, home=home, settings=settings or RobotSettings(), book=CommandBook(robot)
        )
        self.writer = py_trees.blackboard.Client(name="brain", namespace=self.namespace)
        self.writer.register_key(key="context", access=Access.WRITE)
        self.writer.context = self.context
        self.root = build_tree(self.namespace, self.context.settings.policy)
        self.root.setup_with_descendants()

    def tick(self, snapshot: Situation) -> None:
        """Tick once with the world as it is now."""
        self.context.snapshot = snapshot
        self.root.tick_once()

    def render(self) -> str:
        """The tree as text (``toyroom brain --print-tree``)."""
        return py_trees.display.unicode_tree(self.root)
