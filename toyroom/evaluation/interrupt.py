"""Stopping an evaluation on SIGINT (Ctrl-C), SIGTERM or SIGHUP within seconds.

Every node process an evaluation starts in this process (engines, brains, the episode
generator, the planner) is started through :data:`NODES`, which keeps it until it is
stopped. While :func:`catch_signals` is entered (``toyroom eval`` enters it), a stop signal
no longer ends the process at once: it marks :data:`NODES` as stopping and sends SIGTERM to
every node it holds. From then on no node starts (:meth:`NodeRegistry.start` raises
:class:`EvaluationStopped`), a run whose nodes were stopped raises it instead of being tried
again, and the evaluation keeps only the episodes that finished before the signal, then says
so and exits ``128 + signal``.
"""

from __future__ import annotations

import contextlib
import signal
import subprocess
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from types import FrameType
from typing import Any

from bridge.errors import BridgeError
from bridge.processes import start_node, stop_node

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM, signal.SIGHUP)
"""The signals that stop an evaluation."""
GRACE_S = 2.0
"""Seconds a node gets to exit on SIGTERM before SIGKILL, once the evaluation stops."""


def signal_name(signum: int) -> str:
    """``SIGINT`` for 2, or ``signal N`` for a number with no name."""
    try:
        return signal.Signals(signum).name
    except ValueError:
        return f"signal {signum}"


class EvaluationStopped(BridgeError):
    """The evaluation was stopped by signal :attr:`signum`; ``kept`` of ``total`` episodes
    are kept in ``where`` (once the evaluation has counted them)."""

    def __init__(
        self,
        signum: int,
        kept: int | None = None,
        total: int = 0,
        where: Path | None = None,
        unit: str = "episode",
    ) -> None:
        self.signum, self.kept, self.total, self.where = signum, kept, total, where
        said = f"stopped by {signal_name(signum)}"
        if kept is not None:
            said += (
                f": kept {kept} of {total} {unit}s in {where}; run the same command again to finish"
                if kept
                else f": no {unit} had finished ({total} to run); nothing kept"
            )
        super().__init__(said)


class NodeRegistry:
    """The node processes an evaluation started in this process and has not stopped yet,
    and whether (by which signal) it was asked to stop."""

    def __init__(self) -> None:
        self._lock = threading.RLock()  # re-entrant: the signal handler runs in the main thread
        self._live: set[subprocess.Popen[Any]] = set()
        self.signum: int | None = None

    @property
    def stopping(self) -> bool:
        """Whether a stop signal came."""
        return self.signum is not None

    def reset(self) -> None:
        """Forget an earlier evaluation's stop (each evaluation starts unstopped)."""
        with self._lock:
            self.signum = None
            self._live.clear()

    def check(self) -> None:
        """Raise :class:`EvaluationStopped` once a stop signal came."""
        if self.signum is not None:
            raise EvaluationStopped(self.signum)

    def start(
        self, command: list[str], log_path: Path, *, piped: bool = False, append: bool = False
    ) -> subprocess.Popen[bytes]:
        """:func:`bridge.processes.start_node` (``piped``, ``append``: as it says), kept here
        until :meth:`stop` (refused once a stop signal came)."""
        with self._lock:
            self.check()
            process = start_node(command, log_path, piped=piped, append=append)
            self._live.add(process)
            return process

    def run(self, command: list[str], timeout: float) -> subprocess.CompletedProcess[str]:
        """``subprocess.run(command)`` (text output captured, ``timeout`` s at most), kept here
        while it runs; a process stopped by a stop signal raises :class:`EvaluationStopped`.

        Raises:
            subprocess.TimeoutExpired: it ran past ``timeout`` (it is killed)."""
        with self._lock:
            self.check()
            process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
            self._live.add(process)
        try:
            out, err = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            process.kill()
            process.communicate()
            raise
        finally:
            with self._lock:
                self._live.discard(process)
        self.check()  # stopped on the way: what it wrote is no answer
        return subprocess.CompletedProcess(command, process.returncode, out, err)

    def stop(self, process: subprocess.Popen[bytes], grace: float = 10.0) -> None:
        """:func:`bridge.processes.stop_node` (``GRACE_S`` at most once stopping), and forget it."""
        stop_node(process, grace=min(grace, GRACE_S) if self.stopping else grace)
        with self._lock:
            self._live.discard(process)

    def signalled(self, signum: int) -> None:
        """A stop signal came: refuse new nodes and send SIGTERM to every live one (quick:
        this runs in a signal handler)."""
        with self._lock:
            if self.signum is None:
                self.signum = signum
            for process in self._live:
                if process.poll() is None:
                    with contextlib.suppress(OSError):
                        process.terminate()

    def finish(self, grace: float = GRACE_S) -> None:
        """Stop every node still alive: SIGTERM, up to ``grace`` s, then SIGKILL; all reaped."""
        with self._lock:
            live = list(self._live)
        for process in live:
            if process.poll() is None:
                with contextlib.suppress(OSError):
                    process.terminate()
        deadline = time.monotonic() + grace
        for process in live:
            try:
                process.wait(timeout=max(0.0, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait(timeout=grace)
        with self._lock:
            self._live.difference_update(live)


NODES = NodeRegistry()
"""The node processes of the evaluation running in this process."""


@contextlib.contextmanager
def catch_signals() -> Iterator[NodeRegistry]:
    """Within it, :data:`STOP_SIGNALS` stop the evaluation (:meth:`NodeRegistry.signalled`)
    instead of the process; the earlier handlers are restored after (main thread only)."""

    def handler(signum: int, _frame: FrameType | None) -> None:
        NODES.signalled(signum)

    earlier = {sig: signal.signal(sig, handler) for sig in STOP_SIGNALS}
    try:
        yield NODES
    finally:
        for sig, previous in earlier.items():
            signal.signal(sig, previous)
