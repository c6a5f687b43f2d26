"""The ``toyroom`` commands, one module each: its options, the checks of them the parser
cannot make, its handler and what it does (``toyroom eval`` is :mod:`.eval`, ``toyroom run``
:mod:`.run`). :data:`COMMANDS` lists them in the order ``toyroom --help`` does; the node
commands (``toyroom sim``, ``toyroom memory``...) hand their options to a node process
(:mod:`.nodes`; ``toyroom morning``'s node is :mod:`.morning`)."""

from __future__ import annotations

from ..subcommand import NodeCommand, Subcommand
from .bench import COMMAND as BENCH
from .conform import COMMAND as CONFORM
from .doctor import COMMAND as DOCTOR
from .eval import COMMAND as EVAL
from .infer import COMMAND as INFER
from .nodes import NODE_COMMANDS, NODE_HELP, NODES, exec_node
from .record import COMMAND as RECORD
from .replay import COMMAND as REPLAY
from .router import COMMAND as ROUTER
from .run import COMMAND as RUN
from .schema import COMMAND as SCHEMA

COMMANDS: tuple[Subcommand | NodeCommand, ...] = (
    SCHEMA,
    ROUTER,
    *NODE_COMMANDS,
    RUN,
    REPLAY,
    RECORD,
    INFER,
    BENCH,
    EVAL,
    CONFORM,
    DOCTOR,
)
"""Every ``toyroom`` command, in the order ``toyroom --help`` lists them."""

__all__ = ["COMMANDS", "NODE_COMMANDS", "NODE_HELP", "NODES", "exec_node"]
