"""The copies of a person that a memory file does not hold, and ``forget --everywhere DIR``.

What the brain reads of a person is written in more places than its memory: each run's
``mind.csv`` (and its figures and ``report.md``), the run logs (``minds-*.jsonl``,
``inputs.jsonl``), recordings (``trace.jsonl``, ``*.mcap``), the mornings ``toyroom eval
--days`` writes (``mornings/*/dayN.json``) and memory exports. :data:`ELSEWHERE` says where they
typically are; :func:`find_copies` finds, under one folder the user names, the files of those
kinds that name the person (their id as a whole word) and the household (in the file, or in a
file beside it: a run's ``mind.csv`` names no household, its trace does). Nothing outside that
folder is read or removed, nor any other kind of file (scenarios, settings, code).
"""

from __future__ import annotations

import mmap
import os
import re
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

ELSEWHERE = (
    "copies a memory file does not hold, not removed: each run's mind.csv, events.csv, report.md, "
    "figures and logs (toyroom run --out DIR, toyroom brain --out), run logs (--run-log: minds-*.jsonl, "
    "inputs.jsonl), recordings (trace.jsonl, --record *.mcap; toyroom eval: OUT/recordings/), what "
    "toyroom eval --days keeps per household (OUT/work/CONDITION/household-N/: mornings/CHAIN/dayN.json, "
    "memory/CHAIN.sqlite, logs/) and memory exports (*.json): remove them with --everywhere DIR "
    "(under DIR only), or by hand"
)
"""What ``forget`` says of the copies it cannot reach."""

KINDS = {
    "mind.csv": "mind.csv",
    "events.csv": "events.csv",
    "trace.jsonl": "recording",
    "inputs.jsonl": "run log",
}
"""Output files by exact name, and what they are."""
DERIVED = ("report.md", "beliefs.png", "preferences.png")
"""Drawn from a ``mind.csv`` beside them: removed with it."""


@dataclass(frozen=True)
class Copy:
    """A file under the folder that holds the person: its ``kind``."""

    path: Path
    kind: str


def kind_of(path: Path) -> str | None:
    """What output ``path`` is (``None``: none of the kinds ``--everywhere`` removes)."""
    name = path.name
    if name in KINDS:
        return KINDS[name]
    if name.startswith("minds-") and name.endswith(".jsonl"):
        return "run log"
    if path.suffix == ".mcap":
        return "recording"
    if path.suffix == ".log":
        return "log"
    if path.suffix == ".json" and path.parent.parent.name == "mornings":
        return "morning"
    if path.suffix == ".json" and _head(path).lstrip().startswith(b"{") and b'"snapshots"' in _head(path):
        return "memory export"
    return None


def find_copies(root: Path, person: str, household: str) -> tuple[list[Copy], list[Path]]:
    """The files under ``root`` (never outside it: links are not followed) of the kinds
    above that name ``person`` and ``household``, those drawn from them; and those that
    name ``person`` but no household (left alone: another household's, perhaps)."""
    root = root.resolve()
    who, home = _word(person), _word(household)
    found: list[Copy] = []
    unsure: list[Path] = []
    for path in _files(root):
        kind = kind_of(path)
        if kind is None or not _names(path, who):
            continue
        if _names(path, home) or any(_names(p, home) for p in _beside(path)):
            found.append(Copy(path, kind))
            if path.name == "mind.csv":
                found += [
                    Copy(path.parent / d, "drawn from mind.csv")
                    for d in DERIVED
                    if (path.parent / d).is_file()
                ]
        else:
            unsure.append(path)
    return found, unsure


def memories(root: Path, skip: Path) -> list[Path]:
    """The SQLite files under ``root`` (memory files of other runs, perhaps), but ``skip``."""
    found = []
    for path in _files(root.resolve()):
        if path.resolve() != skip.resolve() and _head(path).startswith(b"SQLite format 3\x00"):
            found.append(path)
    return found


def remove(copies: list[Copy], root: Path) -> list[Copy]:
    """Remove each of ``copies`` that is a file under ``root``; those removed."""
    root = root.resolve()
    gone = []
    for copy in copies:
        if copy.path.is_symlink() or not copy.path.resolve().is_relative_to(root):
            continue
        copy.path.unlink(missing_ok=True)
        gone.append(copy)
    return gone


def _files(root: Path) -> Iterator[Path]:
    for folder, dirs, files in os.walk(root, followlinks=False):
        dirs.sort()
        for name in sorted(files):
            path = Path(folder) / name
            if path.is_file() and not path.is_symlink():
                yield path


def _beside(path: Path) -> list[Path]:
    """The run's other files that may name its household (its trace, logs, settings)."""
    return [p for p in path.parent.iterdir() if p != path and kind_of(p) in ("recording", "run log")]


def _word(name: str) -> re.Pattern[bytes]:
    """``name`` as a whole word: not inside a longer id."""
    return re.compile(rb"(?<![\w.-])" + re.escape(name.encode()) + rb"(?![\w.-])")


def _names(path: Path, word: re.Pattern[bytes]) -> bool:
    try:
        with path.open("rb") as f:
            if path.stat().st_size == 0:
                return False
            with mmap.mmap(f.fileno(), 0, access=mmap.ACCESS_READ) as data:
                return word.search(data) is not None
    except (OSError, ValueError):
        return False


def _head(path: Path) -> bytes:
    try:
        with path.open("rb") as f:
            return f.read(4096)
    except OSError:
        return b""
