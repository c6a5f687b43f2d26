"""What every toyroom command line shares, for the ``toyroom`` CLI and the nodes alike:
the parser, its help format, ``--log-level`` and logging.

A node (``python -m sim2d``, ``python -m brain``, ``python -m toyroom.view``) builds its parser
with :func:`command_parser`, so ``toyroom sim --help`` says ``usage: toyroom sim`` and every
option shows its default; the network flags live with the session
(:func:`bridge.session.add_network_args`).
"""

from __future__ import annotations

import argparse
import errno
import logging
import os
import stat
from collections.abc import Sequence
from pathlib import Path
from typing import BinaryIO

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


def _whole_number(text: str, least: int) -> int:
    """``text`` as a whole number >= ``least``, or argparse's error naming what was given."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= {least}, got {text!r}") from None
    if value < least:
        raise argparse.ArgumentTypeError(f"expected a whole number >= {least}, got {value}")
    return value


def positive_int(text: str) -> int:
    """An argparse type: a whole number >= 1 (the error names what was given)."""
    return _whole_number(text, 1)


def two_or_more(text: str) -> int:
    """An argparse type: a whole number >= 2 (the error names what was given)."""
    return _whole_number(text, 2)


def non_negative_int(text: str) -> int:
    """An argparse type: a whole number >= 0 (the error names what was given)."""
    return _whole_number(text, 0)


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


def add_settings_args(parser: argparse.ArgumentParser) -> None:
    """The brain's ``--settings FILE.toml`` and repeatable ``--set NAME=VALUE`` (the brain
    checks them; ``toyroom`` commands hand them on with :func:`settings_argv`)."""
    parser.add_argument(
        "--settings",
        type=Path,
        metavar="FILE.toml",
        help="the brain's model and robot settings ([model], [robot])",
    )
    parser.add_argument(
        "--set",
        dest="overrides",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="one brain setting, e.g. beta=3 or belief_model=graded (repeatable; after --settings)",
    )


def settings_argv(settings: Path | None, overrides: Sequence[str]) -> list[str]:
    """The brain's command-line options for a settings file and ``NAME=VALUE`` overrides
    (the file's path made absolute: the brain may run elsewhere)."""
    argv = ["--settings", str(settings.resolve())] if settings is not None else []
    return argv + [arg for text in overrides for arg in ("--set", text)]


def name_problem(path: Path, flag: str = "--out") -> str | None:
    """Why ``flag`` ``path`` cannot name an output: its name is not valid UTF-8 (the outputs
    name their files in text: notes, reports, commands to run), or ``None``."""
    try:
        os.fsencode(path).decode("utf-8")
    except UnicodeDecodeError:
        shown = os.fsencode(path).decode("utf-8", "backslashreplace")
        named = f"{flag} {shown}" if flag else shown
        return f"{named}: the name is not valid UTF-8; name an output in UTF-8"
    return None


def out_folder_problem(path: Path, flag: str = "--out") -> str | None:
    """Why ``flag`` ``path`` cannot be a folder (its name is not UTF-8, or it, or a folder
    above it, is a file), or ``None`` (it is a folder, or can be made)."""
    if (problem := name_problem(path, flag)) is not None:
        return problem
    for part in (path, *path.parents):
        if part.exists():
            if part.is_dir():
                return None
            where = "" if part == path else f" ({part} is a file)"
            return f"{flag} {path}: expected a folder, got a file{where}"
    return None


def out_file_problem(path: Path, flag: str = "--out", make_folder: bool = True) -> str | None:
    """Why ``flag`` ``path`` (a positional argument: ``flag`` empty) cannot be written as a
    file (its name is not UTF-8, it is a folder, a folder above it is a file, or, unless the
    command makes it (``make_folder``), its folder is missing), or ``None``."""
    if (problem := name_problem(path, flag)) is not None:
        return problem
    named = f"{flag} {path}" if flag else str(path)
    if path.is_dir():
        return f"{named}: expected a file, got a folder"
    folder = path.parent
    for part in (folder, *folder.parents):
        if part.is_dir():
            break
        if part.exists():
            return f"{named}: {part} is a file, not a folder"
    if not make_folder and not folder.is_dir():
        return f"{named}: the folder {folder} does not exist"
    return None


_KINDS = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISSOCK, "a socket"),
)


def open_regular(path: Path) -> BinaryIO:
    """``path`` opened for reading in binary, when it is a regular file. Anything else is
    refused at once, without blocking: a FIFO would block the open until a writer came (and
    a process blocked there does not stop on SIGTERM), a device may never end.

    Raises:
        OSError: it cannot be opened, or is not a regular file (``strerror``: what it is,
            e.g. ``a FIFO, not a regular file``)."""
    fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_CLOEXEC)
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            kind = next((name for test, name in _KINDS if test(mode)), "a special file")
            raise OSError(errno.EINVAL, f"{kind}, not a regular file", str(path))
        os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise
