"""The answers file: one CSV row per participant, question and slider, in the format
``toyroom fit --judgments`` reads (:data:`COLUMNS`), appended and flushed to disk as each
answer comes in, so a closed tab or a stopped server loses nothing; read back on start, so
a participant resumes at their next unanswered question.

Each answer is written whole or not at all (:func:`append_whole`): its rows go in one append,
then ``fsync``; a write that fails partway (a full disk, a file-size limit) is truncated back
to the file's size before it, so no partial row is left for the next answer to be glued to,
and the error is raised for the server to report the answer as not saved."""

from __future__ import annotations

import csv
import io
import logging
import os
import threading
from collections.abc import Mapping
from pathlib import Path

from .questions import Question, QuestionsError

log = logging.getLogger("toyroom.rating")

COLUMNS = ("episode", "tick", "person", "quantity", "target", "value", "estimate", "participant", "question")
"""``toyroom fit --judgments``'s columns (``episode`` to ``value``), the optional ``estimate``
(``online``, or ``smoothed`` for a retrospective question), and who answered which question
(columns the fit does not read)."""


def csv_bytes(rows: list[tuple[object, ...]]) -> bytes:
    """``rows`` as CSV lines (UTF-8, each ending in CRLF as the ``csv`` module writes them)."""
    text = io.StringIO(newline="")
    csv.writer(text).writerows(rows)
    return text.getvalue().encode("utf-8")


def append_whole(path: Path, data: bytes) -> None:
    """Append ``data`` to ``path`` and ``fsync`` it, whole or not at all.

    Raises:
        OSError: the write or the ``fsync`` failed (``ENOSPC``, ``EFBIG``, ``EIO``...); the
            file was truncated back to its size before the call.
    """
    fd = os.open(path, os.O_WRONLY | os.O_APPEND)
    try:
        before = os.fstat(fd).st_size
        try:
            view = memoryview(data)
            while view:
                written = os.write(fd, view)
                if written <= 0:
                    raise OSError(28, os.strerror(28))  # ENOSPC: a write that writes nothing
                view = view[written:]
            os.fsync(fd)
        except OSError:
            _roll_back(fd, path, before)
            raise
    finally:
        os.close(fd)


def _roll_back(fd: int, path: Path, size: int) -> None:
    """Truncate ``path`` (open as ``fd``) back to ``size`` bytes after a failed append."""
    try:
        os.ftruncate(fd, size)
        os.fsync(fd)
    except OSError as err:
        log.error("%s: could not take back a partly written answer (%s)", path, err.strerror)


def check_answers_path(path: Path) -> None:
    """Refuse an answers path that cannot keep answers: one that exists and is no regular file
    (a device such as ``/dev/full`` or ``/dev/null``, a folder, a pipe).

    Raises:
        QuestionsError: naming the path and what it is.
    """
    if path.exists() and not path.is_file():
        kind = "a folder" if path.is_dir() else "a device, pipe or socket"
        raise QuestionsError(f"{path}: cannot keep the answers: it is {kind}, not a regular file")


class AnswerBook:
    """The answers CSV of a study: what each participant has answered, and new answers
    appended (thread-safe).

    Args:
        path: the CSV; created with the header when missing, else checked and read (a partial
            last row, left by a write cut off before this version, is dropped with a warning).

    Raises:
        QuestionsError: a path that is no regular file, a file that cannot be made or read, or
            one that is not an answers file (another header), naming it.
    """

    def __init__(self, path: Path) -> None:
        check_answers_path(path)
        self.path = path
        self._lock = threading.Lock()
        self.answered: dict[str, set[str]] = {}
        try:
            if path.exists() and path.stat().st_size > 0:
                self._drop_partial_row()
                self._read()
            else:
                path.parent.mkdir(parents=True, exist_ok=True)
                path.touch()
                append_whole(path, csv_bytes([COLUMNS]))
        except OSError as err:
            raise QuestionsError(
                f"{path}: cannot make or read the answers file ({err.strerror or err})"
            ) from None

    def _drop_partial_row(self) -> None:
        """Truncate a last row without its line end (a write cut off by a full disk in an
        older version), so the next answer starts a line of its own."""
        data = self.path.read_bytes()
        end = data.rfind(b"\n") + 1
        if data.endswith(b"\n") or end == 0:
            return
        with self.path.open("r+b") as handle:
            handle.truncate(end)
            os.fsync(handle.fileno())
        log.warning("%s: dropped a partial last row (never saved whole): %r", self.path, data[end:][:200])

    def _read(self) -> None:
        try:
            with self.path.open(newline="", encoding="utf-8") as handle:
                reader = csv.reader(handle)
                header = tuple(next(reader, ()))
                if header != COLUMNS:
                    raise QuestionsError(
                        f"{self.path}: not an answers file of toyroom rate (expected the header "
                        f"{','.join(COLUMNS)}, got {','.join(header) or 'nothing'})"
                    )
                for row in reader:
                    if len(row) == len(COLUMNS):
                        self.answered.setdefault(row[7], set()).add(row[8])
        except (OSError, UnicodeDecodeError, csv.Error) as err:
            raise QuestionsError(f"{self.path}: cannot read the answers ({err})") from None

    def done(self, participant: str) -> set[str]:
        """The ids of the questions ``participant`` has answered."""
        with self._lock:
            return set(self.answered.get(participant, ()))

    def add(self, participant: str, question: Question, values: Mapping[str, float]) -> bool:
        """Append one row per slider of ``question`` (``values``: by target, in 0-1) in one
        write and ``fsync`` them; False (and nothing written) when it was answered already.

        Raises:
            OSError: the rows could not be written (:func:`append_whole`): none were kept, and
                the question is still unanswered.
        """
        rows: list[tuple[object, ...]] = [
            (
                question.episode,
                question.tick,
                question.person,
                question.quantity,
                target,
                f"{values[target]:.4f}",
                question.estimate,
                participant,
                question.id,
            )
            for target in question.targets
        ]
        with self._lock:
            if question.id in self.answered.get(participant, ()):
                return False
            append_whole(self.path, csv_bytes(rows))
            self.answered.setdefault(participant, set()).add(question.id)
            return True
