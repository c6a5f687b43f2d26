"""One client's outgoing frames: a bounded queue, and the thread that writes it to the socket.

Zenoh's threads (samples, queries) and the client's reader thread put frames here and never
wait on the socket: this client's writer thread sends them, in order. So a client that reads
slowly, or not at all, holds up nobody but itself. Its queue is bounded
(:class:`QueueLimits`: :data:`MAX_QUEUED_FRAMES` frames, :data:`MAX_QUEUED_BYTES` bytes);
a frame that would go beyond either drops the client (:meth:`Outbox.drop`): one warning
naming it and the queue, the frames still queued discarded, and the socket closed with
:data:`TOO_SLOW` (1008) and the reason ``too slow: N frames queued``. A client that reads
nothing never receives that close frame: its connection is cut :data:`DROP_GRACE` seconds
later. Its liveliness token is withdrawn at the drop (``on_drop``), and the rest it declared
once its reader thread ends (:meth:`~toyroom.gateway.link.ClientLink.close`).

Pings (:meth:`Outbox.ping`, for :mod:`.keepalive`) go ahead of the queued frames, behind the
frame in flight only. The socket's own send buffer is held to :data:`SEND_BUFFER`, so that
what waits for a slow client waits mostly in the queue that is bounded, not in the kernel.
"""

from __future__ import annotations

import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass
from socket import SHUT_RDWR, SO_SNDBUF, SOL_SOCKET

from websockets.exceptions import ConnectionClosed
from websockets.sync.server import ServerConnection

log = logging.getLogger("toyroom.gateway")

MAX_QUEUED_FRAMES = 4096
"""Frames a client may have waiting to be sent: 0.4 s of states at 10 kHz, over a minute at 60 Hz."""
MAX_QUEUED_BYTES = 64 * 1024 * 1024
"""Bytes a client may have waiting to be sent (four of the largest frames; a frame alone in
the queue is sent whatever its size)."""
SEND_BUFFER = 256 * 1024
"""Bytes of a client's socket send buffer (``SO_SNDBUF``; Linux doubles it), instead of the
kernel's growing it up to 4 MiB, a few thousand states unaccounted for; on loopback the
gateway sends far faster than that needs."""
DROP_GRACE = 1.0
"""Seconds a dropped client has to take the frame being sent and the close frame before its
connection is cut."""
TOO_SLOW = 1008
"""The close code of a client dropped for a full queue (policy violation); the reason is
``too slow: N frames queued``."""


@dataclass(frozen=True)
class QueueLimits:
    """How much a client may have waiting to be sent before it is dropped."""

    frames: int = MAX_QUEUED_FRAMES
    bytes: int = MAX_QUEUED_BYTES

    def __post_init__(self) -> None:
        if self.frames < 1 or self.bytes < 1:
            raise ValueError(f"a client's queue holds at least 1 frame and 1 byte, got {self}")


@dataclass(frozen=True)
class _End:
    """The writer's last item: close the socket with ``code`` (``None``: leave it as it is)."""

    code: int | None = None
    reason: str = ""


class Ping:
    """A ping asked of the writer: ``asked`` (``time.monotonic``), and once sent, the event
    its pong sets."""

    def __init__(self) -> None:
        self.asked = time.monotonic()
        self.pong: threading.Event | None = None

    def answered(self) -> bool:
        return self.pong is not None and self.pong.is_set()


class Outbox:
    """One client's queue of encoded frames and its writer thread (see the module docstring).

    Attributes:
        dropped: why the client was dropped (the close reason), or ``None``.
    """

    def __init__(
        self,
        socket: ServerConnection,
        name: Callable[[], str],
        limits: QueueLimits,
        on_drop: Callable[[], None] = lambda: None,
    ) -> None:
        self.socket = socket
        self.name = name
        self.limits = limits
        self.on_drop = on_drop
        self.dropped: str | None = None
        try:
            socket.socket.setsockopt(SOL_SOCKET, SO_SNDBUF, SEND_BUFFER)
        except OSError:  # closed already: the writer ends at its first frame
            pass
        self._queue: deque[bytes | Ping | _End] = deque()
        self._bytes = 0
        self._open = True
        self._ready = threading.Condition()
        self._writer = threading.Thread(target=self._write, name="gateway-writer", daemon=True)
        self._writer.start()

    def put(self, frame: bytes) -> None:
        """Queue one encoded frame, at once (never waits on the socket); a client whose queue
        it would overflow is dropped instead. Discarded once the outbox is finished."""
        with self._ready:
            if not self._open:
                return
            frames, size = len(self._queue), self._bytes
            if frames == 0 or (frames < self.limits.frames and size + len(frame) <= self.limits.bytes):
                self._queue.append(frame)
                self._bytes += len(frame)
                self._ready.notify()
                return
        limits = f"the limit is {self.limits.frames} frames or {self.limits.bytes} bytes"
        self.drop(TOO_SLOW, f"too slow: {frames} frames queued", f"({size} bytes), {limits}")

    def ping(self) -> Ping:
        """Ask the writer for a ping, ahead of the queued frames (never answered once finished)."""
        ping = Ping()
        with self._ready:
            if self._open:
                self._queue.appendleft(ping)
                self._ready.notify()
        return ping

    def drop(self, code: int, reason: str, detail: str = "") -> None:
        """Drop the client (once): one warning, the queue discarded, and on a thread of its own
        (never in the Zenoh callback that found the queue full), its token withdrawn and its
        socket closed with ``code`` and ``reason``, or cut after :data:`DROP_GRACE` s."""
        with self._ready:
            if not self._open:
                return
            self.dropped = reason
            self._end_locked(_End())
        log.warning("client %s dropped: %s%s", self.name(), reason, f" {detail}" if detail else "")
        threading.Thread(target=self._close_dropped, args=(code, reason), daemon=True).start()

    def finish(self, code: int | None = None, reason: str = "") -> None:
        """No more frames: the writer sends those queued, then closes the socket with ``code``
        (``None``: not at all, as when it is closed already) and ends. Safe twice."""
        with self._ready:
            if self._open:
                self._open = False
                self._queue.append(_End(code, reason))
                self._ready.notify()

    def _end_locked(self, end: _End) -> None:
        """Discard what is queued and end the writer after the frame in flight."""
        self._open = False
        self._queue.clear()
        self._bytes = 0
        self._queue.append(end)
        self._ready.notify()

    def _write(self) -> None:
        """The writer thread: send each frame in order until the end or a closed socket."""
        while True:
            with self._ready:
                while not self._queue:
                    self._ready.wait()
                item = self._queue.popleft()
                if isinstance(item, bytes):
                    self._bytes -= len(item)
            if isinstance(item, _End):
                if item.code is not None:
                    self.socket.close(item.code, item.reason)
                return
            try:
                if isinstance(item, Ping):
                    item.pong = self.socket.ping()
                else:
                    self.socket.send(item, text=True)
            except ConnectionClosed:
                with self._ready:
                    self._end_locked(_End())
                return

    def _close_dropped(self, code: int, reason: str) -> None:
        """Withdraw a dropped client's token and close its socket, cutting the connection if
        the frame in flight or the close frame is not taken within :data:`DROP_GRACE` s."""
        self.on_drop()
        cut = threading.Timer(DROP_GRACE, self._cut)
        cut.start()
        try:
            self.socket.close(code, reason)
        finally:
            cut.cancel()

    def _cut(self) -> None:
        """End the TCP connection under the socket: a blocked send fails, the reader ends."""
        try:
            self.socket.socket.shutdown(SHUT_RDWR)
        except OSError:
            pass
