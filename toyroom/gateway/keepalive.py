"""The gateway's keepalive: a client that answers no ping and sends nothing is dropped.

Every ``interval`` seconds a client is pinged (through its :class:`~.outbox.Outbox`, ahead of
its queued frames); one that neither answers (a pong) nor sends a frame within ``interval``
seconds of the ping is dropped with 1011 ``keepalive ping timeout``, its liveliness token
withdrawn at once. A frame from the client counts as much as a pong: a client sending
faster than the gateway reads has its pong queued behind its own frames, and is alive
(``websockets``' own keepalive, which counts pongs only, dropped an engine putting states
at full rate). So a killed or hung client is dropped within about twice ``interval``.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable

from .outbox import Outbox

SILENT = 1011
"""The close code of a client dropped for answering no ping (``websockets``' own for this)."""


class Keepalive:
    """Pings one client until :meth:`stop` (see the module docstring).

    Args:
        heard: when the last frame came from the client (``time.monotonic``).
    """

    def __init__(self, outbox: Outbox, interval: float, heard: Callable[[], float]) -> None:
        self.outbox = outbox
        self.interval = interval
        self.heard = heard
        self._stop = threading.Event()
        threading.Thread(target=self._run, name="gateway-keepalive", daemon=True).start()

    def stop(self) -> None:
        self._stop.set()

    def _run(self) -> None:
        step = self.interval / 10
        while not self._stop.wait(self.interval):
            ping = self.outbox.ping()
            while not ping.answered():
                if self._stop.wait(step):
                    return
                if self.heard() < ping.asked and time.monotonic() - ping.asked > self.interval:
                    silent = f"(no pong and no frame for {self.interval:g} s)"
                    self.outbox.drop(SILENT, "keepalive ping timeout", silent)
                    return
