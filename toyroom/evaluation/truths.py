"""The evaluator's subscription to ``engine/truth``, decoding each tick's truth once per change.

An engine publishes every tick's truth (the people's true minds and where each item is), and
on most ticks nothing of it changes but the tick: decoding all of it again was about a
quarter of the evaluator's CPU. A JSON truth whose bytes from its ``"agents"`` on are the
previous truth's, and whose other fields before them are too (the episode and tick aside),
is that truth with the new episode and tick (:class:`TruthDecoder`); any other payload is
decoded, and checked, whole (:func:`protocol.decode`), so the truths are the same objects'
values as decoding each in full gives.
"""

from __future__ import annotations

import logging
import re
from collections.abc import Callable

import msgspec
import zenoh

from bridge.bridge import Bridge
from bridge.pubsub import Received, decode_payload
from protocol import Encoding, ProtocolError, Truth, decode

log = logging.getLogger("toyroom.eval")

_AGENTS = b',"agents":'
_NUMBERS = re.compile(rb'"(?:episode|tick)":\d+')


class _TruthHead(msgspec.Struct):
    """What comes before a truth's ``agents``: its episode and tick are read."""

    episode: int
    tick: int


_head_decoder = msgspec.json.Decoder(_TruthHead)


class TruthDecoder:
    """Decodes JSON ``truth`` payloads in order, reusing the previous one's people and items
    when their bytes are the same (the episode and tick are then read alone)."""

    def __init__(self) -> None:
        self._previous: tuple[bytes, bytes, Truth] | None = None
        """The previous payload's head without its numbers, its bytes from ``agents`` on, and its truth."""

    def decode(self, data: bytes) -> Truth:
        """The truth of ``data``, equal to ``protocol.decode(data, Truth)``.

        Raises:
            ProtocolError: ``data`` is not a valid ``truth`` message.
        """
        at = data.find(_AGENTS)
        if at > 0 and self._previous is not None:
            shape, tail, truth = self._previous
            head = data[:at]
            if data[at:] == tail and _NUMBERS.sub(b"", head) == shape:
                try:
                    numbers = _head_decoder.decode(head + b"}")
                except msgspec.DecodeError:  # a malformed number: the whole decode says what is wrong
                    numbers = _TruthHead(episode=-1, tick=-1)
                if numbers.episode >= 0 and numbers.tick >= 0:
                    return msgspec.structs.replace(truth, episode=numbers.episode, tick=numbers.tick)
        truth = decode(data, Truth)
        if at > 0:
            self._previous = (_NUMBERS.sub(b"", data[:at]), data[at:], truth)
        return truth


class TruthSubscriber:
    """Calls ``callback(truth, received)`` for every good ``truth`` on ``bridge``'s truth key
    (from a Zenoh thread, as :class:`bridge.pubsub.Subscriber` does); a bad payload is
    dropped with a warning. Close it (or leave the bridge) to stop."""

    def __init__(self, bridge: Bridge, callback: Callable[[Truth, Received], None]) -> None:
        self.key = bridge.keys.truth
        self.dropped = 0
        self._callback = callback
        self._decoder = TruthDecoder()
        self._subscriber = bridge.session.declare_subscriber(self.key, self._on_sample)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        key = str(sample.key_expr)
        encoding = Encoding.from_mime(str(sample.encoding) if sample.encoding is not None else None)
        try:
            if encoding is Encoding.JSON:
                truth = self._decoder.decode(sample.payload.to_bytes())
            else:
                truth, _ = decode_payload(sample.payload, sample.encoding, key, Truth)  # type: ignore[assignment]
        except ProtocolError as err:
            self.dropped += 1
            log.warning("dropped a truth on %s: %s", key, err)
            return
        try:
            self._callback(truth, Received(key, encoding))
        except Exception:
            log.exception("the truth handler of key '%s' failed", key)

    def close(self) -> None:
        """Undeclare the subscriber; safe to call twice."""
        try:
            self._subscriber.undeclare()
        except Exception:
            pass


def subscribe_truths(bridge: Bridge, callback: Callable[[Truth, Received], None]) -> TruthSubscriber:
    """A :class:`TruthSubscriber` on ``bridge``, closed when the bridge is (as its own
    subscribers are)."""
    subscriber = TruthSubscriber(bridge, callback)
    bridge._track(subscriber)  # the bridge closes what it tracks, before its session
    return subscriber
