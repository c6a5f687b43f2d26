"""A :class:`Bridge`: one Zenoh session on a world's network, with typed helpers.

>>> with Bridge("demo") as bridge:                                  # doctest: +SKIP
...     bridge.subscribe(bridge.keys.state, on_state, expected=State)
...     info = bridge.query(bridge.keys.info, Hello(client="me"), EngineInfo)

Everything it creates (publishers, subscribers, queryables, tokens, watchers) is closed
with it, in reverse order; :meth:`Bridge.close` is safe to call twice.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from typing import Any, Protocol, TypeVar

import zenoh

from protocol import Encoding, Keys, Message

from .presence import PresenceEvent, PresenceWatcher, Token
from .pubsub import Congestion, Publisher, Received, Subscriber
from .queries import Queryable, query
from .session import SessionSettings, open_session

log = logging.getLogger("toyroom.bridge")

M = TypeVar("M", bound=Message)


class _Closable(Protocol):
    def close(self) -> None: ...


class Bridge:
    """A Zenoh session bound to one world, speaking protocol messages.

    Args:
        world: the world name (keys ``toyroom/<world>/...``, default port derived from it).
        settings: how to open the session (default: loopback peer, see :mod:`bridge.session`).
        encoding: the encoding this node sends (JSON, or MessagePack for speed); receiving
            accepts both.
        session: an already open session to use instead (not closed by :meth:`close`).
    """

    def __init__(
        self,
        world: str,
        settings: SessionSettings | None = None,
        *,
        encoding: Encoding = Encoding.JSON,
        session: zenoh.Session | None = None,
    ) -> None:
        self.keys = Keys(world)
        self.world = world
        self.encoding = encoding
        self._owns_session = session is None
        self.session = session if session is not None else open_session(world, settings)
        self._resources: list[_Closable] = []
        self._closed = False

    def _track(self, resource: Any) -> Any:
        self._resources.append(resource)
        return resource

    def publisher(
        self, key: str, *, congestion: Congestion = Congestion.BLOCK, express: bool = False
    ) -> Publisher[Message]:
        """A publisher on ``key`` in this bridge's encoding."""
        return self._track(
            Publisher(self.session, key, encoding=self.encoding, congestion=congestion, express=express)
        )

    def subscribe(
        self,
        key: str,
        callback: Callable[[M, Received], None],
        *,
        expected: type[M] | None = None,
    ) -> Subscriber[M]:
        """Call ``callback(message, received)`` for every good message on ``key``."""
        return self._track(Subscriber(self.session, key, callback, expected=expected))

    def query(
        self,
        key: str,
        request: Message | None,
        expected: type[M],
        *,
        timeout: float | None = 5.0,
        request_id: str | None = None,
    ) -> M:
        """Query ``key`` and return the answer (see :func:`bridge.queries.query`)."""
        encoding = self.encoding
        return query(
            self.session, key, request, expected, timeout=timeout, encoding=encoding, request_id=request_id
        )

    def queryable(
        self,
        key: str,
        handler: Callable[[Any, str], Message],
        *,
        expected: tuple[type[Message], ...] | None = None,
        allow_empty: bool = True,
        inline: bool = False,
    ) -> Queryable[Message]:
        """Answer queries on ``key`` with ``handler`` (see :class:`bridge.queries.Queryable`)."""
        return self._track(
            Queryable(self.session, key, handler, expected=expected, allow_empty=allow_empty, inline=inline)
        )

    def token(self, role: str, name: str) -> Token:
        """Declare this node alive as ``role``/``name`` until closed."""
        return self._track(Token(self.session, self.keys.alive(role, name)))

    def presence(
        self, role: str = "*", on_change: Callable[[PresenceEvent], None] | None = None
    ) -> PresenceWatcher:
        """Watch the nodes of ``role`` (``*``: all) appear and disappear."""
        return self._track(PresenceWatcher(self.session, self.keys.alive(role, "*"), on_change))

    def close(self) -> None:
        """Close everything this bridge made, then its session; safe to call twice."""
        if self._closed:
            return
        self._closed = True
        for resource in reversed(self._resources):
            resource.close()
        self._resources.clear()
        if self._owns_session:
            try:
                self.session.close()
            except Exception:
                log.debug("closing the Zenoh session failed", exc_info=True)

    def __enter__(self) -> Bridge:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
