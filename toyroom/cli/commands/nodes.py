"""The commands that run a node package as its own process (``toyroom sim`` is ``python -m
sim2d``, ``toyroom generate`` is ``python -m sim2d generate``), their options the node's own:
:data:`NODE_COMMANDS`, and :func:`exec_node`, which hands ``toyroom``'s process over to one.
Nodes are started as processes; this module never imports ``sim2d`` or ``brain``."""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence

from bridge.flags import PROG_ENV
from bridge.processes import node_environment

from ..subcommand import NodeCommand

NODE_COMMANDS = (
    NodeCommand("sim", "run the sim2d engine node (pymunk) until interrupted", "sim2d"),
    NodeCommand("brain", "run the brain node (inference and robot) against any engine of the world", "brain"),
    NodeCommand(
        "view", "the meshcat live view of a world (prints its URL; --screenshot FILE.png)", "toyroom.view"
    ),
    NodeCommand(
        "gateway",
        "carry a world over a WebSocket for engines without Zenoh (Unity, C#): "
        "--world W [--listen ws://127.0.0.1:7448] [--token FILE]",
        "toyroom.gateway",
    ),
    NodeCommand(
        "play",
        "serve a page where participants play one person of a scenario in their browser, each in a "
        "world of their own, recorded to MCAP: --scenario S --as A1 [--participants N] [--out DIR]",
        "toyroom.play",
    ),
    NodeCommand(
        "generate",
        "write a random episode (and its map): --map M --seed S --out DIR, or --rooms R --items K",
        "sim2d",
        ("generate",),
    ),
    NodeCommand(
        "export-scenario",
        "write a scenario as one JSON document for engines without TOML (the C# engine): "
        "--scenario NAME [--out FILE]",
        "sim2d",
        ("export",),
    ),
    NodeCommand(
        "fit",
        "fit the model's parameters to recorded runs (RECORDINGS... --params beta,hazard --out DIR), "
        "cross-validated by episode, and compare models by held-out log-likelihood",
        "toyroom.fitting",
    ),
    NodeCommand(
        "memory",
        "the brain's memory of households across days: show FILE | forget FILE PERSON | "
        "export FILE [--out JSON] | import FILE JSON",
        "brain",
        ("memory",),
    ),
    NodeCommand(
        "morning",
        "write a household's next morning from a finished run: RUN [--out FILE.json]",
        "toyroom.cli.commands.morning",
    ),
    NodeCommand(
        "rate",
        "serve a judgments page: participants watch recordings and rate beliefs and desires "
        "(RECORDINGS... --questions FILE.toml [--out FILE.csv] [--participants N])",
        "toyroom.rating",
    ),
)
"""The node commands, in the order ``toyroom --help`` lists them."""

NODES = {command.name: command for command in NODE_COMMANDS}
"""The node commands by name."""
NODE_HELP = {command.name: command.help for command in NODE_COMMANDS}
"""What ``toyroom --help`` says of each node command (its own help is the node's)."""


def exec_node(command: str, argv: Sequence[str], prog: str | None = None) -> int:
    """Replace this process with the node of ``command`` (signals go straight to it); its
    help and errors name ``prog`` (default: ``toyroom COMMAND``)."""
    node = NODES[command]
    env = node_environment(child=False)  # single-threaded BLAS: fit's worker processes use every core
    env[PROG_ENV] = prog or f"toyroom {command}"
    os.execve(sys.executable, [sys.executable, "-m", node.package, *node.leading, *argv], env)
    return 0  # pragma: no cover - execv does not return
