"""The answers file: one CSV row per participant, question and slider, in the format
``toyroom fit --judgments`` reads (:data:`COLUMNS`), appended and flushed to disk as each
answer comes in, so a closed tab or a stopped server loses nothing; read back on start, so
a participant resumes at their next unanswered question."""

from __future__ import annotations

import csv
import os
import threading
from collections.abc import Mapping
from pathlib import Path

from .questions import Question, QuestionsError

COLUMNS = ("episode", "tick", "person", "quantity", "target", "value", "estimate", "participant", "question")
"""``toyroom fit --judgments``'s columns (``episode`` to ``value``), the optional ``estimate``
(``online``, or ``smoothed`` for a retrospective question), and who answered which question
(columns the fit does not read)."""


class AnswerBook:
    """The answers CSV of a study: what each participant has answered, and new answers
    appended (thread-safe).

    Args:
        path: the CSV; created with the header when missing, else checked and read.

    Raises:
        QuestionsError: a file that is not an answers file (another header), naming it.
    """

    def __init__(self, path: Path) -> None:
        self.path = path
        self._lock = threading.Lock()
        self.answered: dict[str, set[str]] = {}
        if path.exists() and path.stat().st_size > 0:
            self._read()
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            with path.open("w", newline="", encoding="utf-8") as handle:
                csv.writer(handle).writerow(COLUMNS)

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
        """Append one row per slider of ``question`` (``values``: by target, in 0-1) and
        flush them to disk; False (and nothing written) when it was answered already."""
        rows = [
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
            with self.path.open("a", newline="", encoding="utf-8") as handle:
                csv.writer(handle).writerows(rows)
                handle.flush()
                os.fsync(handle.fileno())
            self.answered.setdefault(participant, set()).add(question.id)
            return True
