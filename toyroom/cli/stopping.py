"""How ``toyroom run`` is asked to stop: SIGINT (Ctrl-C), SIGTERM or SIGHUP.

While a :class:`StopRequest` is entered, these signals no longer end the process at once:
the first one is kept (:attr:`StopRequest.signum`) and sets :attr:`StopRequest.event`; the
main thread looks at it wherever it waits (every wait there is a short slice, see
:mod:`bridge.processes`) and raises :class:`Interrupted` (:meth:`StopRequest.check`), so the
run stops its nodes and writes what it can before it exits with ``128 + signal`` (130 for
SIGINT, 143 for SIGTERM, 129 for SIGHUP, as a shell reports a process killed by it).
"""

from __future__ import annotations

import signal
import threading
from types import FrameType

from bridge.errors import BridgeError

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
"""The signals that ask a run to stop."""


class Interrupted(BridgeError):
    """The run was asked to stop by signal :attr:`signum`."""

    def __init__(self, signum: int) -> None:
        super().__init__(f"interrupted by {signal_name(signum)}")
        self.signum = signum


def signal_name(signum: int) -> str:
    """``SIGTERM`` for 15, or ``signal N`` for a number with no name."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


class StopRequest:
    """A context manager that turns :data:`STOP_SIGNALS` into a request to stop (restoring the
    previous handlers on exit). Outside the main thread it installs nothing (Python runs
    signal handlers there alone) and only :attr:`event` works."""

    def __init__(self) -> None:
        self.event = threading.Event()
        self.signum: int | None = None
        self._previous: dict[signal.Signals, object] = {}

    def _handle(self, signum: int, _: FrameType | None) -> None:
        if self.signum is None:
            self.signum = signum
        self.event.set()

    def __enter__(self) -> StopRequest:
        if threading.current_thread() is threading.main_thread():
            for sig in STOP_SIGNALS:
                self._previous[sig] = signal.signal(sig, self._handle)
        return self

    def __exit__(self, *exc: object) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)  # type: ignore[arg-type]
        self._previous.clear()

    def check(self) -> None:
        """Raise :class:`Interrupted` when a stop was asked for.

        Raises:
            Interrupted: naming the first signal received.
        """
        if self.signum is not None:
            raise Interrupted(self.signum)

    @property
    def exit_status(self) -> int:
        """``128 + signal`` once a signal came, else 0."""
        return 128 + self.signum if self.signum is not None else 0
