"""What every toyroom command line shares, for the ``toyroom`` CLI and the nodes alike:
the parser, its help format, ``--log-level`` and logging.

A node (``python -m sim2d``, ``python -m brain``, ``python -m bridge.view``) builds its parser
with :func:`command_parser`, so ``toyroom sim --help`` says ``usage: toyroom sim`` and every
option shows its default; the network flags live with the session
(:func:`bridge.session.add_network_args`).
"""

from __future__ import annotations

import argparse
import logging
import os

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
