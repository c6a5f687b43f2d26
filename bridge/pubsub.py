"""Typed publish and subscribe over protocol messages (queries: :mod:`bridge.queries`).

Every payload is encoded with :mod:`protocol.codec`, and the encoding travels in Zenoh's
encoding field. Receivers decode with the type they expect: a payload that fails to decode
(malformed, unknown type, another major version) is logged with its key and the reason,
counted, and dropped; the receiver keeps running. A handler that raises is logged the same
way and never kills the node.
"""

from __future__ import annotations

import enum
import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Generic, TypeVar

import zenoh

from protocol import Encoding, Message, ProtocolError, VersionMismatch, decode, encode, tag_of

log = logging.getLogger("toyroom.bridge")

M = TypeVar("M", bound=Message)

FOREVER = 10 * 365 * 24 * 3600.0
"""What a disabled timeout means to Zenoh: ten years, in seconds."""


class Congestion(enum.Enum):
    """What a publisher does when the network cannot keep up.

    ``DROP`` suits state streams (a newer state replaces a dropped one); ``BLOCK`` suits
    commands, statuses and events, which must all arrive.
    """

    DROP = "drop"
    BLOCK = "block"

    def to_zenoh(self) -> zenoh.CongestionControl:
        return zenoh.CongestionControl.DROP if self is Congestion.DROP else zenoh.CongestionControl.BLOCK


@dataclass(frozen=True)
class Received:
    """Where a decoded message came from: its key and its encoding."""

    key: str
    encoding: Encoding


def zenoh_encoding(encoding: Encoding) -> zenoh.Encoding:
    """The Zenoh encoding object that signals ``encoding``."""
    return zenoh.Encoding(encoding.value)


def decode_payload(
    payload: zenoh.ZBytes,
    zenoh_enc: zenoh.Encoding | None,
    key: str,
    expected: type[M] | None,
) -> tuple[Message, Encoding]:
    """Decode a Zenoh payload; raise :class:`ProtocolError` naming the key on failure."""
    encoding = Encoding.from_mime(str(zenoh_enc) if zenoh_enc is not None else None)
    try:
        return decode(payload.to_bytes(), expected, encoding), encoding
    except ProtocolError as err:
        raise err.on_key(key) from None


class DropLog:
    """Logs dropped payloads: every malformed one, but each version mismatch only once per
    key and version (a peer of another major version would otherwise flood the log)."""

    def __init__(self) -> None:
        self._warned: set[tuple[str, str]] = set()
        self._lock = threading.Lock()

    def report(self, err: ProtocolError) -> None:
        if isinstance(err, VersionMismatch):
            marker = (err.key or "", err.theirs)
            with self._lock:
                first = marker not in self._warned
                self._warned.add(marker)
            if not first:
                log.debug("dropped: %s", err)
                return
            log.warning("dropped (further ones from this version are not logged): %s", err)
            return
        log.warning("dropped: %s", err)


class Publisher(Generic[M]):
    """Publishes messages on one key. Use as a context manager, or call :meth:`close`."""

    def __init__(
        self,
        session: zenoh.Session,
        key: str,
        *,
        encoding: Encoding = Encoding.JSON,
        congestion: Congestion = Congestion.BLOCK,
        express: bool = False,
    ) -> None:
        self.key = key
        self.encoding = encoding
        self._publisher = session.declare_publisher(
            key,
            encoding=zenoh_encoding(encoding),
            congestion_control=congestion.to_zenoh(),
            express=express,
        )
        self._matched = threading.Event()
        self._matching = self._publisher.declare_matching_listener(self._on_matching)
        if self._publisher.matching_status.matching:  # type: ignore[attr-defined]
            self._matched.set()
        self._closed = False

    def _on_matching(self, status: zenoh.MatchingStatus) -> None:
        if status.matching:
            self._matched.set()
        else:
            self._matched.clear()

    def wait_matched(self, timeout: float | None = 5.0) -> bool:
        """Wait until at least one subscriber matches this publisher's key; ``False`` on timeout.

        Zenoh delivers a put only to subscribers it already knows of, so a sender that must
        not lose its first message waits for this.
        """
        return self._matched.wait(timeout)

    def put(self, message: M) -> None:
        """Encode and publish ``message``."""
        self._publisher.put(encode(message, self.encoding))

    def close(self) -> None:
        """Undeclare the publisher; safe to call twice."""
        if not self._closed:
            self._closed = True
            try:
                self._matching.undeclare()
                self._publisher.undeclare()
            except Exception:  # the session may already be closed
                pass

    def __enter__(self) -> Publisher[M]:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class Subscriber(Generic[M]):
    """Receives messages of type ``expected`` on a key expression and calls ``callback``.

    The callback runs on a Zenoh thread: keep it short (hand work to a queue). Counters
    :attr:`received` and :attr:`dropped` say how many payloads were delivered and dropped.
    """

    def __init__(
        self,
        session: zenoh.Session,
        key: str,
        callback: Callable[[M, Received], None],
        *,
        expected: type[M] | None = None,
    ) -> None:
        self.key = key
        self.expected = expected
        self.received = 0
        self.dropped = 0
        self._callback = callback
        self._drops = DropLog()
        self._closed = False
        self._subscriber = session.declare_subscriber(key, self._on_sample)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        key = str(sample.key_expr)
        try:
            message, encoding = decode_payload(sample.payload, sample.encoding, key, self.expected)
        except ProtocolError as err:
            self.dropped += 1
            self._drops.report(err)
            return
        self.received += 1
        try:
            self._callback(message, Received(key, encoding))  # type: ignore[arg-type]
        except Exception:
            log.exception("handler of key '%s' failed on a '%s' message", key, tag_of(type(message)))

    def close(self) -> None:
        """Undeclare the subscriber; safe to call twice."""
        if not self._closed:
            self._closed = True
            try:
                self._subscriber.undeclare()
            except Exception:
                pass

    def __enter__(self) -> Subscriber[M]:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
