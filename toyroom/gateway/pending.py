"""The queries a gateway client serves, held until the client replies.

Zenoh hands the link a query on a key the client serves; the link numbers it (a ``qid``),
sends it to the client as a :class:`~protocol.frames.Query` frame and holds it here until
the client's :class:`~protocol.frames.Reply`. A client holds at most :data:`MAX_PENDING`:
beyond that the oldest is refused (``internal``). A held query let go unanswered (its key
unserved, or the client gone) is dropped, so its querier learns at once that nobody answers
(as when a Zenoh engine dies) instead of waiting out its timeout; a client dropped for a
frame above the gateway's limit has them refused instead, saying so.
"""

from __future__ import annotations

import itertools
import threading

import zenoh

from protocol import Encoding, ErrorCode, ErrorReply, encode

MAX_PENDING = 256
"""Unanswered queries a client may hold; the oldest is refused beyond that."""


class PendingQueries:
    """One client's held queries, by qid, each with the encoding it came in and the ``serve``
    id of the key it came on; safe to use from Zenoh's threads and the client's at once."""

    def __init__(self) -> None:
        self._pending: dict[int, tuple[zenoh.Query, Encoding, int]] = {}
        self._lock = threading.Lock()
        self._qids = itertools.count(1)

    def hold(self, query: zenoh.Query, encoding: Encoding, serve: int) -> int:
        """Hold ``query`` under a new qid (returned), refusing the oldest beyond :data:`MAX_PENDING`."""
        qid = next(self._qids)
        with self._lock:
            self._pending[qid] = (query, encoding, serve)
            oldest = next(iter(self._pending)) if len(self._pending) > MAX_PENDING else None
        if oldest is not None:
            self.refuse(oldest, f"the client left {MAX_PENDING} queries unanswered")
        return qid

    def take(self, qid: int) -> tuple[zenoh.Query, Encoding] | None:
        """The held query ``qid`` and its encoding, no longer held (``None``: not held)."""
        with self._lock:
            pending = self._pending.pop(qid, None)
        return None if pending is None else (pending[0], pending[1])

    def release(self, qid: int) -> None:
        """Let go of a held query unanswered: its querier learns at once that nobody answers
        (as when a Zenoh engine dies), instead of waiting out its timeout."""
        with self._lock:
            pending = self._pending.pop(qid, None)
        if pending is not None:
            try:
                pending[0].drop()
            except Exception:
                pass

    def refuse(self, qid: int, why: str) -> None:
        """Refuse a held query (``internal``), e.g. one of too many held."""
        with self._lock:
            pending = self._pending.pop(qid, None)
        if pending is None:
            return
        query, encoding, _ = pending
        refusal = ErrorReply(code=ErrorCode.INTERNAL, message=why)
        try:
            query.reply_err(encode(refusal, encoding), encoding=zenoh.Encoding(encoding.value))
        except Exception:
            pass

    def release_served(self, serve: int) -> None:
        """Let go of every query held on the served key ``serve`` (it is unserved)."""
        with self._lock:
            held = [qid for qid, (_, _, on) in self._pending.items() if on == serve]
        for qid in held:
            self.release(qid)

    def refuse_all(self, why: str) -> None:
        """Refuse every held query (``internal``, saying ``why``): the client is gone for a
        reason its queriers must read, not just "nobody answers"."""
        with self._lock:
            held = list(self._pending)
        for qid in held:
            self.refuse(qid, why)

    def release_all(self) -> None:
        """Let go of every held query (the client is gone)."""
        with self._lock:
            held = list(self._pending)
        for qid in held:
            self.release(qid)
