"""The ``toyroom`` application: the command line (:mod:`.cli`, :mod:`.commands`),
``toyroom run`` (:mod:`.run`) with its live table, and
``toyroom doctor``."""

from .cli import build_parser, main
from .doctor import run_doctor
from .run import RunConfig

__all__ = [
    "build_parser",
    "main",
    "run_doctor",
    "RunConfig",
]
