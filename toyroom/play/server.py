"""``toyroom play``'s server: one page and one WebSocket per participant, on the
``websockets`` library's threaded server (plain HTTP for the page, no build step).

- ``GET /play/<participant>?token=T``: the page (``page.html``); a wrong or missing token is
  refused with 403, an unknown participant with 404.
- ``/ws/<participant>?token=T``: the page's WebSocket. The token again, and the ``Origin``
  (a browser's page may connect only from this server's own origin, the one it was served
  from: another site's page cannot drive a participant's person). Frames are JSON: the
  server sends ``scene`` (the map), then ``view`` (what the person sees, what they heard, the
  open question) every state; the page sends ``{"type": "key", "key", "pressed"}`` for every key
  press (:mod:`.frames`). A frame that is not one (not JSON, nested too deeply, another type)
  is answered with ``{"type": "error", "message"}`` and one log line; the world runs on.

Each participant has a world of their own (:class:`.world.PlayWorld`), started when their
page first connects. Loopback by default; anything else is warned about.
"""

from __future__ import annotations

import json
import logging
import secrets
import socket
import threading
from collections.abc import Callable
from http import HTTPStatus
from pathlib import Path
from urllib.parse import parse_qs, urlsplit

from websockets.exceptions import ConnectionClosed
from websockets.http11 import Request, Response
from websockets.sync.server import Server, ServerConnection, serve

from bridge.errors import ConfigError
from bridge.session import LOOPBACK

from .config import PlayConfig
from .frames import FrameRefused, StartPressed, read_frame
from .world import TAKEN_OVER, PlayWorld

log = logging.getLogger("toyroom.play")
PAGE = Path(__file__).with_name("page.html")
"""The participant's page: plain HTML and JavaScript."""
WILDCARDS = ("0.0.0.0", "::", "")
"""Hosts that mean every interface: the links then name this machine by its host name."""
MAX_FRAME = 64 * 1024
"""Largest frame a page may send, in bytes (a key press is well under 200)."""


def parse_listen(text: str) -> tuple[str, int]:
    """``HOST:PORT`` (or ``http://HOST:PORT``) as ``(host, port)`` (port 0: any free port); a
    :class:`ConfigError` naming what is wrong."""
    host, sep, port = text.removeprefix("http://").rstrip("/").rpartition(":")
    if not sep or not host or not port.isdigit() or int(port) > 65535:
        raise ConfigError(f"--listen takes HOST:PORT (e.g. {LOOPBACK}:8470), got {text!r}")
    return host.strip("[]"), int(port)


def is_loopback_host(host: str) -> bool:
    """Whether ``host`` names this machine only (``localhost``, ``::1``, ``127.*``)."""
    return host in ("localhost", "::1") or host.startswith("127.")


class PlayServer:
    """Serves the participants' pages and worlds; a context manager.

    Args:
        config: what every world runs.
        participants: the participants' ids (each gets a random token).
        listen: ``HOST:PORT`` to serve on.
        world_prefix: the participants' worlds are ``<prefix>-<participant>``.
    """

    def __init__(self, config: PlayConfig, participants: list[str], listen: str, world_prefix: str) -> None:
        host, port = parse_listen(listen)
        self.config = config
        self.tokens = {p: secrets.token_urlsafe(16) for p in participants}
        self.worlds = {p: PlayWorld(config, p, f"{world_prefix}-{p}") for p in participants}
        self._starting: dict[str, threading.Lock] = {p: threading.Lock() for p in participants}
        self._send_locks: dict[int, threading.Lock] = {}
        try:
            self._server: Server = serve(
                self._handle,
                host,
                port,
                process_request=self._request,
                compression=None,
                max_size=MAX_FRAME,
                ping_interval=2.0,
                ping_timeout=10.0,
                close_timeout=0.5,
            )
        except OSError as err:
            raise ConfigError(f"toyroom play cannot listen on {listen}: {err.strerror}") from None
        self.host, self.port = host, self._server.socket.getsockname()[1]
        shown = socket.gethostname() if host in WILDCARDS else host  # a link must name this machine
        self.origin = f"http://{shown if ':' not in shown else f'[{shown}]'}:{self.port}"
        self.origins = {self.origin}
        if is_loopback_host(host):
            self.origins |= {f"http://localhost:{self.port}", f"http://{LOOPBACK}:{self.port}"}
        self._thread = threading.Thread(target=self._server.serve_forever, name="play server", daemon=True)
        self._thread.start()

    def link(self, participant: str) -> str:
        """The participant's link (with their token)."""
        return f"{self.origin}/play/{participant}?token={self.tokens[participant]}"

    def _who(self, path: str, prefix: str) -> tuple[str | None, str]:
        """``(participant, token)`` of a request path under ``prefix``."""
        parts = urlsplit(path)
        if not parts.path.startswith(prefix):
            return None, ""
        token = parse_qs(parts.query).get("token", [""])[0]
        return parts.path[len(prefix) :].strip("/"), token

    def _request(self, connection: ServerConnection, request: Request) -> Response | None:
        """Serve the page, or check a WebSocket's participant, token and origin (``None``:
        go on with the WebSocket handshake)."""
        participant, token = self._who(request.path, "/ws/")
        upgrade = request.headers.get("Upgrade", "").lower() == "websocket"
        if participant is None:
            participant, token = self._who(request.path, "/play/")
            if participant is None or upgrade:
                return connection.respond(
                    HTTPStatus.NOT_FOUND, "not found: the link is /play/<participant>?token=...\n"
                )
        refused = self._refused(participant, token)
        if refused is not None:
            return connection.respond(*refused)
        if request.path.startswith("/ws/"):
            origin = request.headers.get("Origin")
            own = {f"http://{request.headers.get('Host', '')}"}  # the page this server sent
            if origin is not None and origin not in self.origins | own:
                return connection.respond(HTTPStatus.FORBIDDEN, f"origin {origin} may not connect\n")
            return None
        response = connection.respond(HTTPStatus.OK, PAGE.read_text(encoding="utf-8"))
        response.headers["Content-Type"] = "text/html; charset=utf-8"
        response.headers["Cache-Control"] = "no-store"
        return response

    def _refused(self, participant: str, token: str) -> tuple[HTTPStatus, str] | None:
        expected = self.tokens.get(participant)
        if expected is None:
            return HTTPStatus.NOT_FOUND, f"no participant '{participant}' here\n"
        if not secrets.compare_digest(token.encode(), expected.encode()):
            return HTTPStatus.FORBIDDEN, "wrong or missing token: use the link you were given\n"
        return None

    def _handle(self, connection: ServerConnection) -> None:
        participant, _ = self._who(connection.request.path if connection.request else "", "/ws/")
        world = self.worlds[participant or ""]
        lock = threading.Lock()

        def send(message: dict[str, object]) -> None:
            with lock:
                connection.send(json.dumps(message))

        world.attach(send)
        try:
            if self._started(participant or "", world):
                for frame in connection:
                    self._on_frame(world, frame, send)
        except ConnectionClosed:
            pass
        finally:
            world.detach(send)

    def _started(self, participant: str, world: PlayWorld) -> bool:
        """Start ``participant``'s world unless it runs (or has ended); ``False`` when it
        could not start (the world is ended with the reason, and the page told)."""
        try:
            with self._starting[participant]:
                if world.bridge is None and world.ended is None:
                    log.info("starting %s's world '%s'", participant, world.world)
                    world.start()
        except Exception as err:  # the world could not start: the page is told
            log.exception("%s's world failed", participant)
            world.end(f"the world could not start: {err}")
            return False
        return True

    def _on_frame(
        self, world: PlayWorld, frame: str | bytes, send: Callable[[dict[str, object]], None]
    ) -> None:
        """Act on one frame from the page: the start or a key press, or an ``error`` frame back
        saying what was wrong with it (one log line); the world runs on either way. A page that
        another tab took over is told that its frames are no longer taken."""
        try:
            read = read_frame(frame)
        except FrameRefused as err:
            log.warning("%s: a frame refused: %s", world.participant, err)
            send({"type": "error", "message": str(err)})
            return
        if not world.current(send):
            send({"type": "error", "message": f"not taken: {TAKEN_OVER}"})
            return
        if isinstance(read, StartPressed):
            study = world.config.study
            if study is not None and study.consent and not read.consented:
                send({"type": "error", "message": "the study asks for your consent before the start"})
            else:
                world.begin(send)
            return
        try:
            world.key(read.key, read.pressed)
        except Exception as err:  # a world ending as the key comes: said, the page stays
            log.warning("%s: the key %r was not sent: %s", world.participant, read.key, err)
            send({"type": "error", "message": f"the key {read.key!r} was not sent: {err}"})

    def close(self) -> None:
        """Stop serving; end every world still running (marked incomplete)."""
        self._server.shutdown()
        self._thread.join(timeout=5.0)
        for world in self.worlds.values():
            world.end("the server was stopped")

    def __enter__(self) -> PlayServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
