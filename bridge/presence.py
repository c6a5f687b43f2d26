"""Liveliness: tokens that say a node is up, and a watcher that reports peers appearing
and disappearing.

A node declares a token ``toyroom/<world>/@alive/<role>/<name>`` for as long as it runs.
Zenoh withdraws the token when the node's session closes, or when its link's lease runs
out after a crash (0.8 s with the default settings), so a watcher learns of a lost peer
within about a second either way.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import zenoh

log = logging.getLogger("toyroom.bridge")


@dataclass(frozen=True)
class Peer:
    """A node seen through its liveliness token."""

    role: str
    name: str
    key: str


@dataclass(frozen=True)
class PresenceEvent:
    """A peer appeared (``alive=True``) or disappeared (``alive=False``) at ``at``
    (``time.monotonic()`` seconds)."""

    peer: Peer
    alive: bool
    at: float


def _peer_of(key: str) -> Peer:
    parts = key.split("/")
    # toyroom/<world>/@alive/<role>/<name>
    role = parts[3] if len(parts) > 3 else ""
    name = "/".join(parts[4:]) if len(parts) > 4 else ""
    return Peer(role=role, name=name, key=key)


class Token:
    """A liveliness token; undeclared on :meth:`close` or when the session ends."""

    def __init__(self, session: zenoh.Session, key: str) -> None:
        self.key = key
        self._token = session.liveliness().declare_token(key)
        self._closed = False

    def close(self) -> None:
        """Withdraw the token; safe to call twice."""
        if not self._closed:
            self._closed = True
            try:
                self._token.undeclare()
            except Exception:
                pass

    def __enter__(self) -> Token:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class PresenceWatcher:
    """Tracks which peers matching a liveliness key expression are alive.

    Args:
        session: the Zenoh session.
        key: a liveliness key expression, e.g. ``toyroom/demo/@alive/engine/*``.
        on_change: called (on a Zenoh thread) with each :class:`PresenceEvent`.
    """

    def __init__(
        self,
        session: zenoh.Session,
        key: str,
        on_change: Callable[[PresenceEvent], None] | None = None,
    ) -> None:
        self.key = key
        self.events: list[PresenceEvent] = []
        self._alive: dict[str, Peer] = {}
        self._on_change = on_change
        self._cond = threading.Condition()
        self._closed = False
        self._subscriber = session.liveliness().declare_subscriber(key, self._on_sample, history=True)

    def _on_sample(self, sample: zenoh.Sample) -> None:
        peer = _peer_of(str(sample.key_expr))
        alive = sample.kind == zenoh.SampleKind.PUT
        event = PresenceEvent(peer=peer, alive=alive, at=time.monotonic())
        with self._cond:
            if alive:
                self._alive[peer.key] = peer
            else:
                self._alive.pop(peer.key, None)
            self.events.append(event)
            self._cond.notify_all()
        log.info("%s %s/%s", "appeared:" if alive else "disappeared:", peer.role, peer.name)
        if self._on_change is not None:
            try:
                self._on_change(event)
            except Exception:
                log.exception("presence callback failed")

    @property
    def alive(self) -> list[Peer]:
        """The peers alive now."""
        with self._cond:
            return list(self._alive.values())

    def wait(self, predicate: Callable[[list[Peer]], bool], timeout: float | None) -> bool:
        """Block until ``predicate(alive peers)`` holds; ``False`` when ``timeout`` s pass first."""
        with self._cond:
            return self._cond.wait_for(lambda: predicate(list(self._alive.values())), timeout)

    def wait_alive(self, name: str | None = None, timeout: float | None = 5.0) -> bool:
        """Wait until a peer (named ``name``, or any) is alive."""
        return self.wait(lambda peers: any(name in (None, p.name) for p in peers), timeout)

    def wait_gone(self, name: str, timeout: float | None = 5.0) -> bool:
        """Wait until no peer named ``name`` is alive."""
        return self.wait(lambda peers: all(p.name != name for p in peers), timeout)

    def close(self) -> None:
        """Stop watching; safe to call twice."""
        if not self._closed:
            self._closed = True
            try:
                self._subscriber.undeclare()
            except Exception:
                pass

    def __enter__(self) -> PresenceWatcher:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
