"""The flags every toyroom command shares, for the ``toyroom`` CLI and the nodes alike.

A node (``python -m sim2d``, ``python -m brain``, ``python -m bridge.view``) builds its parser
with :func:`command_parser`, so ``toyroom sim --help`` says ``usage: toyroom sim`` and every
option shows its default, and takes the network flags with :func:`add_network_args`.
"""

from __future__ import annotations

import argparse
import logging
import os
from pathlib import Path

from .session import SessionSettings

PROG_ENV = "TOYROOM_PROG"
"""Set by ``toyroom`` when it runs a node (``toyroom sim``), so the node's help names that command."""

LOG_LEVELS = ("DEBUG", "INFO", "WARNING", "ERROR")


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter, argparse.RawDescriptionHelpFormatter):
    """Help that shows each option's default (unless it has none) and keeps the line breaks
    of descriptions."""

    def _get_help_string(self, action: argparse.Action) -> str | None:
        if action.default is None or action.default is False or action.default == []:
            return action.help  # nothing worth showing: unset, a flag that is off, an empty list
        return super()._get_help_string(action)


def command_parser(prog: str, description: str) -> argparse.ArgumentParser:
    """A parser named ``prog``, or what ``toyroom`` asked for in :data:`PROG_ENV` (then
    removed, so no child process inherits it)."""
    return argparse.ArgumentParser(
        prog=os.environ.pop(PROG_ENV, prog), description=description, formatter_class=HelpFormatter
    )


def log_level(value: str) -> str:
    """``--log-level``'s type: a level name in any case."""
    if value.upper() not in LOG_LEVELS:
        raise argparse.ArgumentTypeError(f"expected one of {', '.join(LOG_LEVELS)}, not {value!r}")
    return value.upper()


def add_log_level(parser: argparse.ArgumentParser, default: str = "INFO") -> None:
    """Add ``--log-level``."""
    parser.add_argument(
        "--log-level",
        type=log_level,
        default=default,
        metavar="LEVEL",
        help=f"one of {', '.join(LOG_LEVELS)}",
    )


def configure_logging(level: str) -> None:
    """Log to stderr at ``level``, with time, level and logger name."""
    logging.basicConfig(level=level, format="%(asctime)s %(levelname)s %(name)s: %(message)s")


def add_network_args(parser: argparse.ArgumentParser, *, world: bool = True) -> None:
    """Add the flags that choose the world and override the Zenoh session."""
    group = parser.add_argument_group("network (default: loopback only, no multicast)")
    if world:
        group.add_argument("--world", default="default", help="world name: the key prefix toyroom/WORLD/")
    group.add_argument("--zenoh-config", type=Path, help="a Zenoh JSON5 config file to start from")
    group.add_argument(
        "--mode", choices=("peer", "client", "router"), help="Zenoh mode (default: peer, or the config's)"
    )
    group.add_argument(
        "--listen", action="append", metavar="ENDPOINT", help="listen endpoint, e.g. tcp/127.0.0.1:7447"
    )
    group.add_argument(
        "--connect", action="append", metavar="ENDPOINT", help="connect endpoint (a router or peer)"
    )


def settings_from_args(args: argparse.Namespace) -> SessionSettings:
    """The session settings the network flags ask for."""
    return SessionSettings(
        mode=args.mode,
        listen=tuple(args.listen) if args.listen else None,
        connect=tuple(args.connect) if args.connect else None,
        config_file=args.zenoh_config,
    )
