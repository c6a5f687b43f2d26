"""``python -m brain memory`` (``toyroom memory``): what a memory file holds, forgetting a
person, and an export.

- ``show FILE``: a table of every household, day and person: each person's likeliest
  favourite and where they were last read to believe each item is.
- ``forget FILE PERSON``: remove every row about ``PERSON`` (a person may ask a robot to
  forget them); says how many rows went.
- ``export FILE [--out JSON]``: everything, as JSON (stdout without ``--out``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from rich.console import Console
from rich.table import Table

from bridge.flags import add_log_level, command_parser

from ..errors import MemoryFileError
from .snapshot import Distribution, Snapshot
from .store import dumps, open_memory


def memory_parser() -> argparse.ArgumentParser:
    parser = command_parser(
        "python -m brain memory",
        "Read or change the brain's memory of households across days (--memory FILE of the brain).",
    )
    actions = parser.add_subparsers(dest="action", required=True, metavar="ACTION")
    show = actions.add_parser("show", help="every household, day and person the file remembers")
    show.add_argument("file", type=Path, help="the memory file (SQLite)")
    forget = actions.add_parser("forget", help="remove every row about a person, and say how many")
    forget.add_argument("file", type=Path, help="the memory file (SQLite)")
    forget.add_argument("person", help="the person's id, as the scene names them")
    export = actions.add_parser("export", help="everything the file holds, as JSON")
    export.add_argument("file", type=Path, help="the memory file (SQLite)")
    export.add_argument("--out", type=Path, help="write the JSON here (default: standard output)")
    add_log_level(parser, "WARNING")
    return parser


def memory_main(args: argparse.Namespace) -> int:
    """Run ``args.action`` on ``args.file`` (exists: the file is never created here).

    Raises:
        MemoryFileError: the file is not a usable memory (named in the message).
    """
    if not args.file.is_file():
        raise MemoryFileError(f"no memory file at {args.file}")
    with open_memory(args.file) as memory:
        if args.action == "forget":
            removed = memory.forget(args.person)
            print(f"forgot {args.person}: {removed} rows removed from {args.file}")
        elif args.action == "export":
            text = dumps(memory.export())
            if args.out is None:
                print(text)
            else:
                args.out.write_text(text + "\n", encoding="utf-8")
                print(f"wrote {args.out}")
        else:
            Console(width=120).print(table(memory.snapshots(), args.file))
    return 0


def table(snapshots: list[Snapshot], path: Path) -> Table:
    """What ``show`` prints: one row per household, day (end or checkpoint) and person."""
    out = Table(title=f"memory {path}")
    for column in ("household", "day", "tick", "person", "favourite", "believes"):
        out.add_column(column)
    for s in snapshots:
        day = f"{s.day}" if s.final else f"{s.day} (checkpoint)"
        for p in s.people:
            believes = ", ".join(f"{item} {_top(where)}" for item, where in sorted(p.beliefs.items()))
            out.add_row(s.household, day, str(s.tick), p.person, _top(p.preference), believes)
    return out


def _top(distribution: Distribution) -> str:
    """The likeliest entry and its probability: ``ball 0.93``."""
    if not distribution:
        return "-"
    best = max(sorted(distribution), key=lambda k: distribution[k])
    return f"{best} {distribution[best]:.2f}"
