"""The ``toyroom`` application's command line: the parser and ``main()`` (:mod:`.cli`), which
only register and dispatch the commands, and one module per command (:mod:`.commands`: its
options, checks and handler; ``toyroom run`` with its live table and its folder, ``toyroom
eval``, ``toyroom doctor``...), beside what several commands share (:mod:`.options`,
:mod:`.floors`, :mod:`.recordings`)."""

from .cli import build_parser, main
from .commands.doctor import run_doctor
from .commands.run import RunConfig

__all__ = [
    "build_parser",
    "main",
    "run_doctor",
    "RunConfig",
]
