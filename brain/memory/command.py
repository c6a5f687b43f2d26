"""``python -m brain memory`` (``toyroom memory``): what a memory file holds, forgetting a
person, and an export and its import.

- ``show FILE [--person P] [--household H] [--latest]``: a table of every household, day and
  person (or those chosen; ``--latest``: each household's last day, what its next day starts
  from): when it was saved (UTC), each person's likeliest favourite and where they were last
  read to believe each item is, places and items named as the scene names them.
- ``forget FILE PERSON [--household NAME] [--wait S] [--everywhere DIR]``: remove every row
  about ``PERSON`` in one household (a person may ask a robot to forget them), their bytes too
  (``secure_delete`` and ``VACUUM``); says how many rows went. ``--household`` is needed when
  the person is in more than one; a name the file does not hold is an error naming who it
  does hold. A file a running brain holds is not refused: the brain is asked, forgets, saves
  nothing more of them, and answers (:mod:`.requests`; ``--wait`` seconds at most). It then
  names the copies the file does not hold (:mod:`.copies`), or removes those under ``DIR``
  with ``--everywhere DIR``, naming each.
- ``export FILE [--out JSON] [--person P [--household H]]``: everything, or what it holds
  about one person, as JSON (stdout without ``--out``); never over the memory file itself,
  nor over any other memory file.
- ``import FILE JSON``: an export (of the whole file) into a new or empty memory file.

``show`` and ``export`` open the file read-only: they never write to it. Every error is one
line on standard error, begun with the command's name (``toyroom memory:``), exit 2.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from rich.console import Console

from bridge.flags import add_log_level, command_parser
from bridge.recording.atomic import output_error, write_text

from ..errors import MemoryFileError, MemoryInUseError, MemoryRequestError
from . import copies, requests
from .showing import chosen, table
from .store import open_memory
from .transfer import dumps, export, import_export

WAIT_SECONDS = 60.0
"""How long ``forget`` waits for a running brain to answer (the default of ``--wait``)."""


def memory_parser() -> argparse.ArgumentParser:
    """The parser of ``python -m brain memory``: show, forget, export and import."""
    parser = command_parser(
        "python -m brain memory",
        "Read or change the brain's memory of households across days (--memory FILE of the brain).",
    )
    actions = parser.add_subparsers(dest="action", required=True, metavar="ACTION")
    show = actions.add_parser("show", help="every household, day and person the file remembers")
    show.add_argument("file", type=Path, help="the memory file (SQLite)")
    show.add_argument("--person", metavar="P", help="only this person (an id as the scene names them)")
    show.add_argument("--household", metavar="NAME", help="only this household")
    show.add_argument(
        "--latest", action="store_true", help="only each household's last day (what its next day starts from)"
    )
    forget = actions.add_parser("forget", help="remove every row about a person, and say how many")
    forget.add_argument("file", type=Path, help="the memory file (SQLite)")
    forget.add_argument("person", help="the person's id, as the scene names them")
    forget.add_argument(
        "--household",
        metavar="NAME",
        help="the household to forget them in (needed when the file holds the person in more than one)",
    )
    forget.add_argument(
        "--wait",
        type=float,
        default=WAIT_SECONDS,
        metavar="S",
        help="when a running brain holds the file: seconds to wait for it to forget "
        f"(default {WAIT_SECONDS:g})",
    )
    forget.add_argument(
        "--everywhere",
        type=Path,
        metavar="DIR",
        help="also remove the copies under DIR (runs' mind.csv, logs, recordings, mornings, exports "
        "naming the person and household), and say which; nothing outside DIR",
    )
    export = actions.add_parser("export", help="everything the file holds, as JSON")
    export.add_argument("file", type=Path, help="the memory file (SQLite)")
    export.add_argument("--out", type=Path, help="write the JSON here (default: standard output)")
    export.add_argument("--person", metavar="P", help="only what the file holds about this person")
    export.add_argument("--household", metavar="NAME", help="with --person: only in this household")
    imported = actions.add_parser("import", help="an export into a new or empty memory file")
    imported.add_argument("file", type=Path, help="the memory file to write (SQLite; new, or empty)")
    imported.add_argument("json", type=Path, help="what toyroom memory export wrote (of the whole file)")
    add_log_level(parser, "WARNING")
    return parser


def memory_main(args: argparse.Namespace) -> int:
    """Run ``args.action`` on ``args.file`` (exists, but for ``import``: the file is never
    created otherwise).

    Raises:
        MemoryFileError: the file is not a usable memory, or ``--out`` is not a place to
            write the export (named in the message), or what ``import`` reads is no export.
        MemoryRequestError: a person or household the file does not hold.
    """
    if args.file.is_dir():
        raise MemoryFileError(f"{args.file} is a folder, not a memory file")
    if args.action == "import":
        count = import_export(args.json, args.file)
        print(f"imported {count} days of households from {args.json} into {args.file}")
        return 0
    if not args.file.is_file():
        raise MemoryFileError(f"no memory file at {args.file}")
    if args.action == "forget":
        return forget_main(args)
    if args.action == "export" and args.out is not None:
        check_export_path(args.out, args.file)
    if args.action == "export" and args.household is not None and args.person is None:
        raise MemoryRequestError("export --household chooses among a person's households: give --person too")
    with open_memory(args.file, read_only=True) as memory:
        if args.action == "export":
            text = dumps(export(memory, args.person, args.household))
            if args.out is None:
                print(text)
                return 0
            try:
                write_text(args.out, text + "\n")
            except OSError as err:
                raise MemoryFileError(f"--out {args.out}: {output_error(err)}") from err
            print(f"wrote {args.out}")
        else:
            where = f"memory file {args.file}"
            saved = chosen(memory.saved(), args.person, args.household, args.latest, where)
            Console(width=160).print(table(saved, args.file, memory.names(), args.person))
    return 0


def forget_main(args: argparse.Namespace) -> int:
    """``forget``: in the file, or by the running brain that holds it; then the copies."""
    if args.everywhere is not None and not args.everywhere.is_dir():
        raise MemoryFileError(f"--everywhere {args.everywhere}: no such folder")
    if not args.wait >= 0:
        raise MemoryRequestError(f"--wait is a number of seconds >= 0, not {args.wait}")
    try:
        with open_memory(args.file) as memory:
            requests.carry_out(memory)  # any a brain stopped before answering
            home = memory.household_of(args.person, args.household)
            removed = memory.forget(args.person, home)
        by = ""
    except MemoryInUseError:
        answer = ask_holder(args.file, requests.ForgetRequest(args.person, args.household), args.wait)
        if answer.error:
            raise MemoryRequestError(answer.error) from None
        home, removed = answer.household or "", answer.removed
        by = (
            f" by the running brain (at tick {answer.tick}), which saves nothing more of them"
            if answer.tick is not None
            else ""
        )
    print(f"forgot {args.person} in household {home}: {removed} rows removed from {args.file}{by}")
    if args.everywhere is None:
        print(copies.ELSEWHERE)
        return 0
    found, unsure = copies.find_copies(args.everywhere, args.person, home)
    removed_copies = copies.remove(found, args.everywhere)
    for gone in removed_copies:
        print(f"removed {gone.path} ({gone.kind})")
    print(
        f"removed {len(removed_copies)} copies of {args.person} in household {home} under {args.everywhere}"
    )
    for path in unsure:
        print(
            f"left {path}: it names {args.person} but not household {home} (another household's?): check it"
        )
    for path in copies.memories(args.everywhere, args.file):
        print(forget_in(path, args.person, home))
    return 0


def forget_in(path: Path, person: str, household: str) -> str:
    """Forget ``person`` of ``household`` in another memory file found by ``--everywhere``
    (read first: a file that is no toyroom memory, or does not hold them, is not written);
    what became of it, in one line."""
    try:
        with open_memory(path, read_only=True, wait=0) as memory:
            held = person in memory.people_by_household().get(household, [])
        if not held:
            return f"left {path}: a memory file without {person} in household {household}"
        with open_memory(path, wait=0) as memory:
            removed = memory.forget(person, household)
    except MemoryInUseError:
        again = f"toyroom memory forget {path} {person} --household {household}"
        return f"left {path}: a memory file in use ({again})"
    except MemoryFileError as err:
        return f"left {path}: {err}"
    return f"forgot {person} in {path} (memory file): {removed} rows removed"


def ask_holder(memory: Path, request: requests.ForgetRequest, wait: float) -> requests.ForgetAnswer:
    """Ask whoever holds ``memory`` to carry out ``request``; its answer (carried out here
    when the holder lets the file go first).

    Raises:
        MemoryFileError: no answer within ``wait`` seconds (the request is withdrawn:
            nothing was forgotten).
    """
    asked = requests.ask(memory, request)
    deadline = time.monotonic() + wait
    while (answer := requests.answer_of(asked)) is None:
        if time.monotonic() >= deadline:
            if (answer := requests.withdraw(asked)) is not None:  # carried out meanwhile
                return answer
            raise MemoryFileError(
                f"memory file {memory} is in use by another process that did not forget "
                f"{request.person!r} within {wait:g} s (a brain looks at every tick: a paused one, or "
                "not a brain?): nothing was forgotten; stop it, or try again with a longer --wait"
            )
        try:  # without waiting on the lock: a wait would hold up the holder's own saves
            with open_memory(memory, wait=0) as store:  # the holder let it go: carried out here
                requests.carry_out(store)
        except MemoryInUseError:
            time.sleep(0.1)
    return answer


SQLITE_HEADER = b"SQLite format 3\x00"


def check_export_path(out: Path, memory: Path) -> None:
    """Refuse an ``export --out`` that is the memory file itself, another memory (SQLite)
    file, a folder, or in a folder that does not exist.

    Raises:
        MemoryFileError: naming ``out`` and why.
    """
    if out.resolve() == memory.resolve() or _same(out, memory):
        raise MemoryFileError(
            f"--out {out} is the memory file itself: the export would overwrite the memory "
            "(write it elsewhere)"
        )
    if out.is_dir():
        raise MemoryFileError(f"--out {out} is a folder: name the JSON file to write in it")
    if not out.parent.is_dir():
        raise MemoryFileError(f"--out {out}: no folder {out.parent} to write it in")
    if out.is_file():
        with out.open("rb") as f:
            if f.read(len(SQLITE_HEADER)) == SQLITE_HEADER:
                raise MemoryFileError(
                    f"--out {out} is a SQLite file (a memory?): an export never overwrites one"
                )


def _same(a: Path, b: Path) -> bool:
    try:
        return a.samefile(b)
    except OSError:
        return False
