"""The rating server's HTTP server: Python's threaded ``http.server``, bounded.

- At most ``max_connections`` connections at once: one more is answered ``503`` at once
  and closed (one warning per run of refusals), so idle sockets cannot take every thread.
- A connection that sends nothing for ``idle_timeout`` seconds is closed (one debug line).
- A client that goes away mid-request (a closed tab, a reset, a timeout) is one info line,
  never a traceback; any other failure of a request is logged with its traceback.
"""

from __future__ import annotations

import logging
import socket
import sys
import threading
from dataclasses import dataclass
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from typing import Any

log = logging.getLogger("toyroom.rating")

_BUSY_TEXT = b"too many connections: try again in a while"
BUSY = (
    b"HTTP/1.0 503 Service Unavailable\r\nContent-Type: text/plain; charset=utf-8\r\n"
    + f"Content-Length: {len(_BUSY_TEXT)}\r\nRetry-After: 5\r\nConnection: close\r\n\r\n".encode()
    + _BUSY_TEXT
)
"""The whole answer to a connection over the limit."""


@dataclass(frozen=True)
class ServerLimits:
    """How much the rating server holds."""

    idle_timeout: float = 30.0
    """Seconds a connection may send nothing (or stall mid-request) before it is closed."""
    max_connections: int = 64
    """Connections served at once; one more is answered 503."""


DEFAULT_LIMITS = ServerLimits()
"""30 s idle, 64 connections: a lab's participants with a few tabs each."""


class BoundedHTTPServer(ThreadingHTTPServer):
    """A threaded HTTP server with :class:`ServerLimits` (see the module docstring)."""

    daemon_threads = True

    def __init__(
        self, address: tuple[str, int], handler: type[BaseHTTPRequestHandler], limits: ServerLimits
    ) -> None:
        self.limits = limits
        self._slots = threading.BoundedSemaphore(limits.max_connections)
        self._busy_said = False
        handler.timeout = limits.idle_timeout  # the socket's timeout for every read and write
        super().__init__(address, handler)

    def process_request(self, request: Any, client_address: Any) -> None:
        if not self._slots.acquire(blocking=False):
            self._refuse(request, client_address)
            return
        try:
            super().process_request(request, client_address)
        except BaseException:
            self._slots.release()  # no thread took it
            raise

    def process_request_thread(self, request: Any, client_address: Any) -> None:
        try:
            super().process_request_thread(request, client_address)
        finally:
            self._busy_said = False
            self._slots.release()

    def _refuse(self, request: socket.socket, client_address: Any) -> None:
        """Answer 503 and close: the server holds ``max_connections`` already."""
        if not self._busy_said:
            self._busy_said = True
            log.warning(
                "refusing connections (503): %d are open, the most this server holds",
                self.limits.max_connections,
            )
        try:
            request.settimeout(1.0)
            request.sendall(BUSY)
        except OSError:
            pass
        self.shutdown_request(request)

    def handle_error(self, request: Any, client_address: Any) -> None:
        """One line for a client that went away; a traceback for anything else."""
        error = sys.exc_info()[1]
        peer = f"{client_address[0]}:{client_address[1]}" if client_address else "?"
        if isinstance(error, ConnectionError | TimeoutError):
            log.info("client %s went away mid-request (%s)", peer, type(error).__name__)
        else:
            log.error("a request from %s failed", peer, exc_info=True)
