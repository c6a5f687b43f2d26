"""What a ``toyroom`` command is to the top-level parser: a :class:`Subcommand` (its name, its
one line of help, its options and its handler) or a :class:`NodeCommand` (a node package run as
its own process, the options its own). Each is defined in the command's module under
:mod:`toyroom.cli.commands`; the parser (:mod:`toyroom.cli.cli`) only registers them."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from dataclasses import dataclass


def no_problem(args: argparse.Namespace) -> None:
    """What a command without checks of its own finds wrong with its arguments: nothing."""
    del args
    return None


@dataclass(frozen=True)
class Subcommand:
    """A command ``toyroom`` runs in its own process.

    Attributes:
        name: the command's name (``toyroom NAME``).
        help: its one line in ``toyroom --help``, also its own help's description.
        options: adds its arguments to its parser.
        handle: does the command with its parsed arguments; the exit code.
        problem: what is wrong with arguments the parser let through (a flag below its floor, a
            file to write that is a folder), in one line, or ``None``; checked before
            :attr:`handle`, after the world name and ``--out``.
        out_folder: whether its ``--out`` is a folder (made when missing; a file is refused).
    """

    name: str
    help: str
    options: Callable[[argparse.ArgumentParser], None]
    handle: Callable[[argparse.Namespace], int]
    problem: Callable[[argparse.Namespace], str | None] = no_problem
    out_folder: bool = False


@dataclass(frozen=True)
class NodeCommand:
    """A command that replaces ``toyroom`` with a node package's process (``toyroom sim`` is
    ``python -m sim2d``), its options the node's own.

    Attributes:
        name: the command's name (``toyroom NAME``).
        help: its line in ``toyroom --help`` (which adds where its own help is).
        package: the module ``python -m`` runs.
        leading: the arguments before the command's own (``generate`` for ``python -m sim2d
            generate``).
    """

    name: str
    help: str
    package: str
    leading: tuple[str, ...] = ()
