"""Stopping a node's main thread on SIGINT or SIGTERM.

Python runs signal handlers in the main thread, between bytecodes. The kernel may deliver
a signal to any thread of the process, Zenoh's native threads included; a main thread
blocked in ``Event.wait()`` without a timeout is then never woken to run the handler, and
the node ignores SIGTERM (seen in 2 of about 1000 engine processes of ``toyroom eval``).
So the main thread waits in short slices.
"""

from __future__ import annotations

import signal
import threading

POLL_S = 0.2
"""Seconds between two looks at the stop event: the longest a signal waits to be handled."""


def stop_on_signals(stop: threading.Event) -> None:
    """Set ``stop`` on SIGINT and SIGTERM (call from the main thread)."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())


def wait_for_stop(stop: threading.Event) -> None:
    """Block until ``stop`` is set, waking every ``POLL_S`` so that signal handlers run."""
    while not stop.wait(POLL_S):
        pass
