"""``toyroom gateway``: one world's protocol over a WebSocket, for clients without Zenoh.

The gateway opens one Zenoh session on the world (loopback, as every node does) and a
WebSocket server (the ``websockets`` library's threaded server: one thread per client,
which reads its frames; another of the client's own sends them, :mod:`.outbox`). Frames are
documented in :mod:`protocol.frames` and ``protocol/README.md``.

Safe defaults: it listens on ``127.0.0.1`` only; browsers' pages may connect only from a
loopback origin (plus ``--origin``); with ``--token FILE`` a client must present the
file's secret in its hello. Pings every ``ping`` seconds: a client that answers none and
sends nothing is dropped after about twice that (:mod:`.keepalive`), and its liveliness
token goes with it. Each client has its own bounded queue of frames to send
(:mod:`.outbox`): one too slow to read is dropped, never holding up the others.
"""

from __future__ import annotations

import logging
import re
import threading
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import urlsplit

import zenoh
from websockets.sync.server import Server, ServerConnection, serve
from websockets.typing import Origin

from bridge.errors import ConfigError
from bridge.session import LOOPBACK, SessionSettings, is_loopback, open_session
from protocol.limits import MAX_FRAME_BYTES

from .link import ClientLink, LinkSettings
from .outbox import QueueLimits
from .secret import read_secret

log = logging.getLogger("toyroom.gateway")

DEFAULT_PORT = 7448
"""The gateway's default port (beside Zenoh's 7447), so a Unity client needs no setting."""
DEFAULT_URL = f"ws://{LOOPBACK}:{DEFAULT_PORT}"
MAX_FRAME = MAX_FRAME_BYTES
"""Largest frame accepted, in bytes (16 MiB: every scene within :mod:`protocol.limits` fits)."""


_LOOPBACK_ORIGIN = re.compile(r"^https?://(localhost|127\.\d+\.\d+\.\d+|\[::1\])(:\d+)?$")


def parse_listen(url: str) -> tuple[str, int]:
    """``ws://HOST:PORT`` as ``(host, port)``; a :class:`ConfigError` naming what is wrong."""
    parts = urlsplit(url)
    if parts.scheme != "ws" or not parts.hostname or parts.path not in ("", "/"):
        raise ConfigError(f"--listen takes ws://HOST:PORT (e.g. {DEFAULT_URL}), got {url!r}")
    try:
        port = parts.port if parts.port is not None else DEFAULT_PORT
    except ValueError:
        raise ConfigError(f"--listen: the port of {url!r} is not a number in 0-65535") from None
    return parts.hostname, port


@dataclass(frozen=True)
class GatewaySettings:
    """How a gateway serves. ``listen`` is a ``ws://HOST:PORT`` URL (port 0: any free port)."""

    world: str
    listen: str = DEFAULT_URL
    token_file: Path | None = None
    origins: tuple[str, ...] = ()
    """Browser origins allowed besides loopback ones (``https://example.org``)."""
    ping: float = 0.5
    """Seconds between pings; a client silent for twice this is dropped."""
    queue: QueueLimits = QueueLimits()
    """How many frames and bytes a client may have waiting to be sent before it is dropped."""
    session: SessionSettings = field(default_factory=SessionSettings)


class Gateway:
    """A running gateway; use as a context manager or call :meth:`close`.

    Attributes:
        url: the ``ws://`` URL it listens on (with the real port when asked for port 0).
    """

    def __init__(self, settings: GatewaySettings) -> None:

        host, port = parse_listen(settings.listen)
        if not is_loopback(f"tcp/{host}:{port}"):
            log.warning(
                "the gateway listens on %s: other machines can reach it; use --token (and a TLS proxy) there",
                host,
            )
        secret = read_secret(settings.token_file) if settings.token_file is not None else None
        self.settings = settings
        self.links: set[ClientLink] = set()
        self._lock = threading.Lock()
        self._link_settings = LinkSettings(
            world=settings.world,
            secret=secret,
            gateway="toyroom gateway",
            queue=settings.queue,
            ping=settings.ping,
        )
        self.session: zenoh.Session = open_session(settings.world, settings.session)
        try:
            self._server: Server = serve(
                self._handle,
                host,
                port,
                origins=[None, _LOOPBACK_ORIGIN, *(Origin(o) for o in settings.origins)],
                compression=None,
                max_size=MAX_FRAME,
                ping_interval=None,  # the links' own keepalive (.keepalive)
                ping_timeout=None,
                close_timeout=0.2,
            )
        except OSError as err:
            self.session.close()
            raise ConfigError(f"the gateway cannot listen on {settings.listen}: {err.strerror}") from None
        bound_port = self._server.socket.getsockname()[1]
        self.url = f"ws://{host}:{bound_port}"
        self._thread = threading.Thread(target=self._server.serve_forever, name="gateway", daemon=True)
        self._thread.start()
        log.info("gateway for world '%s' on %s", settings.world, self.url)

    def _handle(self, socket: ServerConnection) -> None:
        link = ClientLink(socket, self.session, self._link_settings)
        with self._lock:
            self.links.add(link)
        try:
            link.run()
        finally:
            with self._lock:
                self.links.discard(link)

    def close(self) -> None:
        """Stop serving, drop every client (their tokens withdrawn) and close the session."""
        self._server.shutdown()
        self._thread.join(timeout=5.0)
        with self._lock:
            links = list(self.links)
        for link in links:
            link.close()
        self.session.close()

    def __enter__(self) -> Gateway:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
