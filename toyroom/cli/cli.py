"""The ``toyroom`` command line: its parser and ``main()``. The parser only registers the
commands, each of which is defined whole (options, checks, handler) in its own module of
:mod:`toyroom.cli.commands`; ``main()`` checks what every command shares (the world's name,
an ``--out`` folder), then the command's own, and hands over to its handler. Global flags may
come before or after the command name; node commands (``toyroom sim``...) are handed to the
node with their options."""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Sequence

from bridge.errors import BridgeError
from bridge.flags import HelpFormatter, configure_logging, log_level, out_folder_problem
from bridge.recording.atomic import OutputError, disk_full, output_error
from bridge.session import world_problem
from protocol import Error as ProtocolErrorBase

from .commands import COMMANDS, NODE_HELP, NODES, exec_node
from .subcommand import NodeCommand, Subcommand

__all__ = ["NODE_HELP", "NODES", "build_parser", "global_parser", "main"]

log = logging.getLogger("toyroom")


def global_parser() -> argparse.ArgumentParser:
    """The flags ``toyroom`` takes before or after any command name."""
    parser = argparse.ArgumentParser(add_help=False, allow_abbrev=False)
    parser.add_argument(
        "--log-level",
        type=log_level,
        metavar="LEVEL",
        help="DEBUG, INFO, WARNING or ERROR (default: INFO here, WARNING in the nodes a command starts)",
    )
    return parser


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``toyroom`` (node commands are listed, their options are the node's)."""
    parser = argparse.ArgumentParser(
        prog="toyroom",
        description="Theory-of-Mind robot brain, 2D engine and their Zenoh wire.",
        parents=[global_parser()],
        formatter_class=HelpFormatter,
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    shared = argparse.ArgumentParser(add_help=False)
    shared.add_argument("--log-level", type=log_level, default=argparse.SUPPRESS, help=argparse.SUPPRESS)
    for command in COMMANDS:
        if isinstance(command, NodeCommand):  # its options are the node's
            node_help = f"{command.help} (`toyroom {command.name} --help`)"
            commands.add_parser(command.name, help=node_help, add_help=False)
            continue
        command.options(
            commands.add_parser(
                command.name,
                help=command.help,
                description=command.help,
                parents=[shared],
                formatter_class=HelpFormatter,
            )
        )
    return parser


SUBCOMMANDS = {command.name: command for command in COMMANDS if isinstance(command, Subcommand)}
"""The commands ``toyroom`` runs itself (not a node's), by name."""


def argument_problem(args: argparse.Namespace) -> str | None:
    """What is wrong with arguments the parser let through (a world name that is none, an
    ``--out`` that is a file, then the command's own checks: a recording to write that is a
    folder or in a missing one, a time flag below its floor), in one line, or ``None``."""
    if getattr(args, "world", None) is not None and (problem := world_problem(args.world)) is not None:
        return problem
    command = SUBCOMMANDS[args.command]
    if command.out_folder and (problem := out_folder_problem(args.out)) is not None:
        return problem
    return command.problem(args)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``toyroom`` console script. Global flags (``--log-level``) may
    come before or after the command name."""
    argv = list(sys.argv[1:] if argv is None else argv)
    flags, rest = global_parser().parse_known_args(argv)
    if rest and rest[0] in NODES:
        levels = ["--log-level", flags.log_level] if flags.log_level else []
        return exec_node(rest[0], [*rest[1:], *levels])
    args = build_parser().parse_args(argv)
    configure_logging(args.log_level or "INFO")
    if (problem := argument_problem(args)) is not None:
        print(f"toyroom {args.command}: {problem}", file=sys.stderr)
        return 2
    try:
        return SUBCOMMANDS[args.command].handle(args)
    except (BridgeError, ProtocolErrorBase) as err:
        print(f"toyroom {args.command}: {err}", file=sys.stderr)
        return 2
    except OSError as err:  # a full disk writing the outputs: one line, nothing half written
        if not (isinstance(err, OutputError) or disk_full(err)):
            raise
        print(f"toyroom {args.command}: {output_error(err)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
