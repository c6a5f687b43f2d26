"""Typed query and queryable over protocol messages: one request, one answer.

Payloads travel as publish and subscribe's do (:mod:`bridge.pubsub`: encoded with
:mod:`protocol.codec`, the encoding in Zenoh's encoding field). A query's answer is decoded
with the type the querier expects; a peer's refusal arrives as an ``error`` reply and is
raised as :class:`~bridge.errors.RemoteError` (or :class:`~protocol.VersionMismatch`). A
queryable answers every failure, a malformed request or a handler that raises, with an
``error`` reply and keeps running.

A query may carry a request id (its Zenoh attachment, UTF-8 text): a queryable keeps its last
:data:`REMEMBERED_ANSWERS` answers by id and answers a query repeating an id with the answer
it gave, without calling its handler again. That is what lets a lock-step client whose link
went down under a ``step`` (an engine paused past its lease: the engine, continued, still
carries out the step it was sent, and its answer is lost with the link) ask again and get that
step's answer instead of a second step (:meth:`bridge.LockstepClient.again`).
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections import OrderedDict
from collections.abc import Callable
from typing import Any, Generic, TypeVar

import zenoh

from protocol import (
    Encoding,
    ErrorCode,
    ErrorReply,
    Message,
    ProtocolError,
    VersionMismatch,
    encode,
    tag_of,
)

from .errors import NoReply, Refused, RemoteError
from .pubsub import FOREVER, DropLog, decode_payload, zenoh_encoding

log = logging.getLogger("toyroom.bridge")

M = TypeVar("M", bound=Message)
Q = TypeVar("Q", bound=Message)

REMEMBERED_ANSWERS = 16
"""How many answers a :class:`Queryable` keeps by their queries' request ids."""


def query(
    session: zenoh.Session,
    key: str,
    request: Message | None,
    expected: type[M],
    *,
    timeout: float | None = 5.0,
    encoding: Encoding = Encoding.JSON,
    request_id: str | None = None,
) -> M:
    """Send a query and return the first answer, decoded as ``expected``.

    Args:
        session: the Zenoh session the query is sent on.
        key: the key expression queried.
        request: the query's payload (``None``: no payload).
        expected: the message type the answer is decoded as.
        timeout: seconds to wait for an answer; ``None`` waits forever (for debugging).
        request_id: sent as the query's attachment: a queryable that has answered this id
            answers with that answer again instead of handling the request twice.
        encoding: the wire encoding of the request and the answer.

    Raises:
        NoReply: nobody serves ``key``, or no answer came within ``timeout``.
        RemoteError: the peer refused the request; :class:`~protocol.VersionMismatch`
            when it refused it for speaking another major version.
        ProtocolError: the answer could not be decoded.
    """
    started = time.monotonic()
    kwargs: dict[str, Any] = {"timeout": FOREVER if timeout is None else timeout}
    if request is not None:
        kwargs["payload"] = encode(request, encoding)
        kwargs["encoding"] = zenoh_encoding(encoding)
    if request_id is not None:
        kwargs["attachment"] = request_id.encode()
    for reply in session.get(key, **kwargs):
        if reply.ok is not None:
            message, _ = decode_payload(reply.ok.payload, reply.ok.encoding, key, expected)
            return message  # type: ignore[return-value]
        err = reply.err
        try:
            refusal, _ = decode_payload(err.payload, err.encoding, key, ErrorReply)
        except ProtocolError:
            # not a peer's refusal but Zenoh's own error reply, e.g. its query timeout
            text = err.payload.to_bytes()[:200].decode("utf-8", "replace")
            raise NoReply(
                f"no answer on '{key}' within {timeout:g} s (zenoh: {text})"
                if timeout is not None
                else f"no answer on '{key}' (zenoh: {text})"
            ) from None
        assert isinstance(refusal, ErrorReply)
        if refusal.code is ErrorCode.VERSION_MISMATCH:
            ours = request.protocol if request is not None else refusal.protocol
            raise VersionMismatch(ours, refusal.protocol, key=key)
        raise RemoteError(key, refusal.code, refusal.message)
    waited = time.monotonic() - started
    if timeout is not None and waited >= timeout * 0.9:
        raise NoReply(f"no answer on '{key}' within {timeout:g} s")
    raise NoReply(f"nobody answers on '{key}' (is the engine running, on the same world?)")


class Queryable(Generic[Q]):
    """Answers queries on a key with ``handler(request, key) -> reply message``.

    Queries are handled one at a time, in arrival order, on a worker thread of this
    queryable (so a long handler never blocks Zenoh); with ``inline=True`` they are answered
    in Zenoh's callback thread instead, one at a time under a lock, which saves the hand-off
    between threads (about half of a lock-step tick's overhead: ``toyroom bench``), for
    handlers that are short, such as a lock-step engine's ``step``. The
    request payload is decoded as one of ``expected`` (``None`` accepts a query without
    payload, delivered as ``None``). Failures become ``error`` replies: a malformed request
    ``bad_request``, another major version ``version_mismatch``, a handler raising
    :class:`~bridge.errors.Refused` its code, any other exception ``internal``. The answers
    to the last :data:`REMEMBERED_ANSWERS` queries that carried a request id are kept, and a
    query repeating one of those ids gets the same answer again (the module docstring).
    """

    def __init__(
        self,
        session: zenoh.Session,
        key: str,
        handler: Callable[[Any, str], Message],
        *,
        expected: tuple[type[Message], ...] | None = None,
        allow_empty: bool = True,
        inline: bool = False,
    ) -> None:
        self.key = key
        self.expected = expected
        self.allow_empty = allow_empty
        self.handled = 0
        self._handler = handler
        self._queue: queue.Queue[zenoh.Query | None] = queue.Queue()
        self._drops = DropLog()
        self._answers: OrderedDict[str, tuple[bytes, Encoding]] = OrderedDict()
        """The last answers given to queries with a request id, by id (oldest first)."""
        self._closed = False
        self._worker: threading.Thread | None = None
        if not inline:
            self._worker = threading.Thread(target=self._run, name=f"queryable {key}", daemon=True)
            self._worker.start()
        self._inline_lock = threading.Lock()
        self._queryable = session.declare_queryable(key, self._answer_inline if inline else self._queue.put)

    def _answer_inline(self, query: zenoh.Query) -> None:
        with self._inline_lock:
            try:
                self._answer(query)
            except Exception:
                log.exception("answering a query on '%s' failed", self.key)

    def _run(self) -> None:
        while True:
            item = self._queue.get()
            if item is None:
                return
            try:
                self._answer(item)
            except Exception:
                log.exception("answering a query on '%s' failed", self.key)
            finally:
                del item

    def _refuse(self, query: zenoh.Query, code: ErrorCode, message: str, encoding: Encoding) -> None:
        reply = ErrorReply(code=code, message=message)
        query.reply_err(encode(reply, encoding), encoding=zenoh_encoding(encoding))

    def _answer(self, query: zenoh.Query) -> None:
        key = str(query.key_expr)
        attached = query.attachment
        request_id = None if attached is None else attached.to_bytes().decode("utf-8", "replace")
        if request_id is not None and request_id in self._answers:
            payload, kept = self._answers[request_id]
            log.warning("request '%s' on '%s' asked again: answered with its first answer", request_id, key)
            query.reply(query.key_expr, payload, encoding=zenoh_encoding(kept))
            return
        encoding = Encoding.from_mime(str(query.encoding) if query.encoding is not None else None)
        request: Message | None = None
        if query.payload is None or len(query.payload.to_bytes()) == 0:
            if not self.allow_empty:
                self._refuse(query, ErrorCode.BAD_REQUEST, f"a query on '{key}' needs a payload", encoding)
                return
        else:
            try:
                request, encoding = decode_payload(query.payload, query.encoding, key, None)
            except VersionMismatch as err:
                self._drops.report(err)
                self._refuse(query, ErrorCode.VERSION_MISMATCH, str(err), encoding)
                return
            except ProtocolError as err:
                self._drops.report(err)
                self._refuse(query, ErrorCode.BAD_REQUEST, str(err), encoding)
                return
            if self.expected is not None and not isinstance(request, self.expected):
                wanted = ", ".join(f"'{tag_of(t)}'" for t in self.expected)
                message = f"'{key}' accepts {wanted} requests, got a '{tag_of(type(request))}' message"
                log.warning("refused: %s", message)
                self._refuse(query, ErrorCode.BAD_REQUEST, message, encoding)
                return
        try:
            answer = self._handler(request, key)
        except Refused as err:
            self._refuse(query, err.code, err.message, encoding)
            return
        except Exception as err:
            log.exception("handler of '%s' failed", key)
            self._refuse(query, ErrorCode.INTERNAL, f"{type(err).__name__}: {err}", encoding)
            return
        self.handled += 1
        payload = encode(answer, encoding)
        if request_id is not None:
            self._answers[request_id] = (payload, encoding)
            while len(self._answers) > REMEMBERED_ANSWERS:
                self._answers.popitem(last=False)
        query.reply(query.key_expr, payload, encoding=zenoh_encoding(encoding))

    def close(self) -> None:
        """Undeclare the queryable and stop its worker; safe to call twice."""
        if self._closed:
            return
        self._closed = True
        try:
            self._queryable.undeclare()
        except Exception:
            pass
        if self._worker is not None:
            self._queue.put(None)
            if threading.current_thread() is not self._worker:
                self._worker.join(timeout=5.0)

    def __enter__(self) -> Queryable[Q]:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
