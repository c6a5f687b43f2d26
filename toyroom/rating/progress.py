"""Where each participant of a rating study is, as the server saw it: whether they agreed to
take part (the consent on their page), and which question their page shows now. An answer is
taken only from a participant who agreed, to the question their page shows (issue 64: answers
POSTed without the page, before consent or out of order, were saved).

Kept in memory: after a restart, a participant with a saved answer counts as having agreed
(they could not have answered otherwise), one without agrees again, and every page loads its
question again before its answer is taken."""

from __future__ import annotations

import threading


class Progress:
    """Each participant's consent and shown question (thread-safe)."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._agreed: set[str] = set()
        self._shown: dict[str, str | None] = {}

    def agree(self, participant: str) -> None:
        """Record that ``participant`` agreed to take part."""
        with self._lock:
            self._agreed.add(participant)

    def agreed(self, participant: str) -> bool:
        """Whether ``participant`` agreed (since this server started)."""
        with self._lock:
            return participant in self._agreed

    def show(self, participant: str, question: str | None) -> None:
        """Record that ``participant``'s page now shows ``question`` (``None``: the last page)."""
        with self._lock:
            self._shown[participant] = question

    def shown(self, participant: str) -> str | None:
        """The question ``participant``'s page shows (``None``: none loaded since the start)."""
        with self._lock:
            return self._shown.get(participant)
