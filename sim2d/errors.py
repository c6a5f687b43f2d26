"""Errors raised by sim2d: one root, and a scenario/map error that names the file, the
entry and what is wrong."""

from __future__ import annotations

from pathlib import Path


class Sim2dError(Exception):
    """Root of every error raised by ``sim2d``."""


class ScenarioError(Sim2dError):
    """A map or scenario file is broken.

    Attributes:
        path: the file.
        entry: where in the file, e.g. ``doors[2] 'S1-E'`` or ``agents[0].script[3]``.
        problem: what is wrong, saying what was expected and what came instead.
    """

    def __init__(self, path: Path | str, entry: str, problem: str) -> None:
        self.path = Path(path)
        self.entry = entry
        self.problem = problem
        where = f" {entry}:" if entry else ""
        super().__init__(f"{self.path}:{where} {problem}")
