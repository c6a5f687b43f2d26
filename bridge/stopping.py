"""Stopping: a node's main thread on SIGINT or SIGTERM, and a child process group.

Python runs signal handlers in the main thread, between bytecodes. The kernel may deliver
a signal to any thread of the process, Zenoh's native threads included; a main thread
blocked in ``Event.wait()`` without a timeout is then never woken to run the handler, and
the node ignores SIGTERM (seen in 2 of about 1000 engine processes of ``toyroom eval``).
So the main thread waits in short slices.
"""

from __future__ import annotations

import os
import signal
import subprocess
import threading
import time

POLL_S = 0.2
"""Seconds between two looks at the stop event: the longest a signal waits to be handled."""


def stop_on_signals(stop: threading.Event) -> None:
    """Set ``stop`` on SIGINT and SIGTERM (call from the main thread)."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())


def wait_for_stop(stop: threading.Event, timeout: float | None = None) -> bool:
    """Block until ``stop`` is set (or ``timeout`` seconds have passed), waking every
    ``POLL_S`` so that signal handlers run; whether ``stop`` is set."""
    deadline = None if timeout is None else time.monotonic() + timeout
    while not stop.wait(POLL_S if deadline is None else max(0.0, min(POLL_S, deadline - time.monotonic()))):
        if deadline is not None and time.monotonic() >= deadline:
            return False
    return True


def stop_process_group(process: subprocess.Popen[bytes], grace: float = 5.0) -> None:
    """Stop the process group ``process`` leads (``start_new_session=True``): SIGTERM, up to
    ``grace`` s for the leader to exit (reaped), then SIGKILL to whatever of the group is left
    (helpers the leader did not wait for)."""
    try:
        os.killpg(process.pid, signal.SIGTERM)
    except ProcessLookupError:
        process.poll()
        return
    try:
        process.wait(timeout=grace)
    except subprocess.TimeoutExpired:
        pass
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    process.wait(timeout=grace)
