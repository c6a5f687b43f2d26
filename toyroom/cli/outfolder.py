"""Where ``toyroom run --out DIR`` writes, and how its outputs reach ``DIR``.

A run writes into a fresh sibling folder, ``DIR.running-PID``, which holds a ``FAILED`` note
from the start (so a run killed outright, by SIGKILL or a crash, leaves a marked folder). At
the end:

- finished: the note goes, and the folder takes the place of ``DIR``. An earlier run there is
  replaced whole, by one atomic rename when ``DIR`` holds nothing but a run's outputs; other
  things in ``DIR`` (sub-folders such as ``out/eval/`` or another run's ``out/paper-1/``) are
  left as they are, and only the earlier run's outputs make way.
- failed or interrupted: the folder, with its ``FAILED`` note, becomes ``DIR`` if ``DIR`` was
  missing or empty, else the sibling ``DIR.failed-YYYYMMDD-HHMMSS``; ``DIR`` keeps what it had.

While a run is on it holds a lock on ``DIR`` (``fcntl.flock`` on the sibling file ``DIR.lock``,
which names its process and goes when the run ends): a second run into the same ``DIR`` is
refused at its start, naming the first, instead of both finishing and one's results being lost.

A run's outputs are the names in :data:`RUN_OUTPUTS`; a ``DIR`` holds an earlier run when it
has one of :data:`RUN_MARKERS`. A ``DIR`` that is a file, or that holds files of a run's
names but no earlier run (a project folder with its own ``settings.toml``...), is refused
before anything starts.
"""

from __future__ import annotations

import ctypes
import fcntl
import fnmatch
import os
import shutil
import time
from collections.abc import Callable
from pathlib import Path

from bridge.errors import BridgeError
from bridge.flags import name_problem

FAILED = "FAILED"
"""The note in the folder of a run that did not finish: why, and how to recover the rest."""
RUN_MARKERS = ("engine.log", "trace.jsonl", FAILED)
"""A folder holding one of these holds an earlier run (every run writes ``engine.log`` first)."""
RUN_OUTPUTS = (
    *RUN_MARKERS,
    "events.csv",
    "mind.csv",
    "report.md",
    "*.png",
    "settings.toml",
    "*.log",
    "minds-*.jsonl",
    "inputs.jsonl",
    "scenarios",
)
"""What a run writes (``fnmatch`` patterns): the earlier run's entries that make way for a new one."""


def _is_output(name: str) -> bool:
    return any(fnmatch.fnmatchcase(name, pattern) for pattern in RUN_OUTPUTS)


def _fresh(path: Path) -> Path:
    """``path``, or ``path-2``, ``path-3``... whichever does not exist yet."""
    candidate, n = path, 1
    while candidate.exists() or candidate.is_symlink():
        n += 1
        candidate = path.with_name(f"{path.name}-{n}")
    return candidate


def _exchange(first: Path, second: Path) -> bool:
    """Swap two folders in one atomic step (Linux ``renameat2(RENAME_EXCHANGE)``); whether it
    could (not on other systems or file systems)."""
    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except (AttributeError, OSError):
        return False
    at_fdcwd, rename_exchange = -100, 2
    done = renameat2(at_fdcwd, os.fsencode(first), at_fdcwd, os.fsencode(second), rename_exchange)
    return bool(done == 0)


def _take_lock(target: Path) -> tuple[int, Path]:
    """Lock ``target`` for this process: an exclusive ``flock`` on ``target.lock`` (made if
    missing), which is made to hold this process's id; the open file and its path.

    Raises:
        BridgeError: another process holds the lock (naming it), or the file cannot be made.
    """
    path = target.with_name(f"{target.name}.lock")
    while True:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            fd = os.open(path, os.O_RDWR | os.O_CREAT, 0o644)
        except OSError as err:
            raise BridgeError(f"cannot make the lock file {path} for --out {target}: {err}") from None
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode(errors="replace").strip() or "whose id is not written yet"
            os.close(fd)
            raise BridgeError(
                f"--out {target} is being written by another toyroom run (process {holder}); "
                "wait for it to end or name another folder"
            ) from None
        try:
            if os.stat(path).st_ino == os.fstat(fd).st_ino:
                break  # else a run that ended removed it after this one opened it: again
        except FileNotFoundError:
            pass
        os.close(fd)
    os.ftruncate(fd, 0)
    os.write(fd, f"{os.getpid()}\n".encode())
    return fd, path


class RunFolder:
    """The results folder ``target`` of one run, and the fresh folder the run writes into
    (:attr:`staging`, made by :meth:`open`).

    Raises:
        BridgeError: ``target`` is a file, holds files of a run's names but no earlier run, or
            its name is not valid UTF-8.
    """

    def __init__(self, target: Path) -> None:
        if (problem := name_problem(target)) is not None:  # before the lock: nothing is left behind
            raise BridgeError(problem)
        self.target = target.resolve() if target.is_symlink() else target.absolute()
        if self.target.parent == self.target:
            raise BridgeError(f"--out {target} is a file system's root; name a folder for the results")
        if self.target.exists() and not self.target.is_dir():
            raise BridgeError(f"--out {target} is a file; name a folder for the results")
        entries = self._entries()
        if entries and not any(e.name in RUN_MARKERS for e in entries):
            clash = sorted(e.name for e in entries if _is_output(e.name))
            if clash:
                raise BridgeError(
                    f"--out {target} holds {', '.join(clash)} but no earlier run (no engine.log or "
                    "trace.jsonl): a run would replace them; name another folder"
                )
        self.staging = self.target.with_name(f"{self.target.name}.running-{os.getpid()}")
        self._lock: tuple[int, Path] | None = None

    def _entries(self) -> list[Path]:
        return sorted(self.target.iterdir()) if self.target.is_dir() else []

    def open(self, note: Callable[[Path], str]) -> Path:
        """Make the fresh folder, with ``note(folder)`` as its ``FAILED`` file until :meth:`finish`.

        Raises:
            BridgeError: another run is writing ``target`` (its process named), or the folder
                cannot be made.
        """
        if self._lock is None:
            self._lock = _take_lock(self.target)
        self.staging = _fresh(self.staging)
        try:
            self.staging.mkdir(parents=True)
            (self.staging / FAILED).write_text(note(self.staging), encoding="utf-8")
        except OSError as err:
            raise BridgeError(f"cannot make the results folder {self.staging}: {err}") from None
        return self.staging

    def finish(self) -> Path:
        """Put the finished run in place of ``target`` (see the module's docstring); ``target``."""
        (self.staging / FAILED).unlink(missing_ok=True)
        entries = self._entries()
        if not self.target.exists() or not entries:
            os.replace(self.staging, self.target)  # an empty folder is replaced in one step
        elif all(_is_output(e.name) for e in entries):
            if not _exchange(self.staging, self.target):
                aside = _fresh(self.target.with_name(f"{self.target.name}.replaced-{os.getpid()}"))
                os.rename(self.target, aside)
                os.rename(self.staging, self.target)
                self.staging = aside
            shutil.rmtree(self.staging, ignore_errors=True)  # the earlier run, now here
        else:
            self._merge(entries)
        return self.target

    def _merge(self, entries: list[Path]) -> None:
        """Move the earlier run's outputs out of ``target`` and the new run's in, leaving the
        rest of ``target`` as it is."""
        new = {e.name for e in self.staging.iterdir()}
        aside = _fresh(self.target.with_name(f"{self.target.name}.replaced-{os.getpid()}"))
        aside.mkdir()
        for entry in entries:
            if _is_output(entry.name) or entry.name in new:
                os.rename(entry, aside / entry.name)
        for name in sorted(new):
            os.rename(self.staging / name, self.target / name)
        self.staging.rmdir()
        shutil.rmtree(aside, ignore_errors=True)

    def release(self) -> None:
        """Give up the lock on ``target`` (its file goes); safe to call twice."""
        if self._lock is not None:
            fd, path = self._lock
            self._lock = None
            path.unlink(missing_ok=True)  # while still held: nobody locks the file going
            os.close(fd)

    def failed_destination(self) -> Path:
        """Where a failed run goes: ``target`` when missing or empty, else a fresh sibling
        ``target.failed-YYYYMMDD-HHMMSS``."""
        if not self._entries():
            return self.target
        stamp = time.strftime("%Y%m%d-%H%M%S")
        return _fresh(self.target.with_name(f"{self.target.name}.failed-{stamp}"))

    def place_failed(self, destination: Path) -> Path:
        """Move the failed run (its ``FAILED`` note written) to ``destination``
        (:meth:`failed_destination`); ``destination``."""
        os.replace(self.staging, destination)
        return destination
