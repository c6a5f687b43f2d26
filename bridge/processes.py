"""Node processes: stopping a node on SIGINT or SIGTERM, stopping a child's process group,
and launching node processes (their command lines, their logs, waiting for an engine).

Python runs signal handlers in the main thread, between bytecodes. The kernel may deliver
a signal to any thread of the process, Zenoh's native threads included; a main thread
blocked in ``Event.wait()`` without a timeout is then never woken to run the handler, and
the node ignores SIGTERM (seen in 2 of about 1000 engine processes of ``toyroom eval``).
So the main thread waits in short slices (:func:`wait_for_stop`).

Nodes are started as ``python -m sim2d`` and ``python -m brain`` (the bridge never imports
them); a started node's output goes to a log kept with the results, and it is stopped with
SIGTERM, then SIGKILL after a grace (:func:`stop_nodes`: a whole process group each, for nodes
started as group leaders). The brain's settings are checked by the brain itself, as a process,
before any node starts (:func:`check_brain_settings`).
"""

from __future__ import annotations

import logging
import os
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

from protocol import EngineInfo

from .bridge import Bridge
from .errors import BridgeError, NoReply
from .flags import settings_argv
from .handshake import handshake
from .session import DEFAULT_LEASE_MS, SessionSettings

POLL_S = 0.2
"""Seconds between two looks at the stop event: the longest a signal waits to be handled."""
PARENT_VARIABLE = "TOYROOM_PARENT_PID"
"""Set by :func:`node_environment` to the starting process's pid: a node waiting in
:func:`wait_for_stop` stops when its parent is no longer that process (it was killed without
stopping its nodes, e.g. ``toyroom eval`` by SIGKILL or an unhandled SIGTERM), instead of
running on, an orphan. A node started by hand (no variable) is left alone, ``nohup`` too."""


STARTER_GONE = "the process that started this node (pid %s) is gone: stopping"


def starter_gone() -> bool:
    """Whether the process that started this node (:data:`PARENT_VARIABLE`) is no longer its
    parent; never for a node started by hand (no variable)."""
    parent = os.environ.get(PARENT_VARIABLE, "")
    return parent.isdigit() and os.getppid() != int(parent)


def stop_on_signals(stop: threading.Event) -> None:
    """Set ``stop`` on SIGINT and SIGTERM (call from the main thread)."""
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())


def wait_for_stop(stop: threading.Event, timeout: float | None = None) -> bool:
    """Block until ``stop`` is set (or ``timeout`` seconds have passed), waking every
    ``POLL_S`` so that signal handlers run; whether ``stop`` is set."""
    deadline = None if timeout is None else time.monotonic() + timeout
    while not stop.wait(POLL_S if deadline is None else max(0.0, min(POLL_S, deadline - time.monotonic()))):
        if starter_gone():
            log.warning(STARTER_GONE, os.environ[PARENT_VARIABLE])
            stop.set()
            return True
        if deadline is not None and time.monotonic() >= deadline:
            return False
    return True


def exit_with_parent() -> threading.Thread | None:
    """For a node that blocks elsewhere than :func:`wait_for_stop` (the brain, waiting on the
    engine): a daemon thread that sends this process SIGTERM once the process that started it
    (:data:`PARENT_VARIABLE`) is gone, so it stops as on a signal instead of running on, an
    orphan. ``None`` (no thread) for a node started by hand."""
    if not os.environ.get(PARENT_VARIABLE, "").isdigit():
        return None

    def watch() -> None:
        while not starter_gone():
            time.sleep(POLL_S)
        log.warning(STARTER_GONE, os.environ[PARENT_VARIABLE])
        os.kill(os.getpid(), signal.SIGTERM)

    thread = threading.Thread(target=watch, name="parent-watch", daemon=True)
    thread.start()
    return thread


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


log = logging.getLogger("toyroom.run")


def network_args(settings: SessionSettings) -> list[str]:
    """The network flags of a node's command line that give it ``settings`` (its Zenoh config file,
    mode, listen and connect endpoints)."""
    args: list[str] = []
    if settings.config_file is not None:
        args += ["--zenoh-config", str(settings.config_file)]
    if settings.mode is not None:
        args += ["--mode", settings.mode]
    for endpoint in settings.listen or ():
        args += ["--listen", endpoint]
    for endpoint in settings.connect or ():
        args += ["--connect", endpoint]
    return args


CHECKOUT = Path(__file__).resolve().parents[1]
"""The source checkout this package runs from (when it does: an installed wheel has no
``examples/`` or the C# SDK beside it)."""


def source_file(relative: str, what: str = "") -> Path:
    """``relative`` in the source checkout, or a :class:`BridgeError` saying in one line that
    ``what`` (the command, when empty) needs a source checkout."""
    path = CHECKOUT / relative
    if not path.is_file():
        raise BridgeError(
            f"{what + ' ' if what else ''}needs a source checkout: {relative} is not part of the "
            "installed package (clone the repository and run it there)"
        )
    return path


GRID_ENGINE = "examples/grid_engine/main.py"
"""The example engine written from the protocol documents alone (plain zenoh and json)."""


def node_command(package: str, world: str, settings: SessionSettings, *args: str) -> list[str]:
    """The command line of a node process (with Python's fault handler on, so a crash in
    native code leaves every thread's Python stack in the node's log)."""
    return [
        sys.executable,
        "-X",
        "faulthandler",
        "-m",
        package,
        "--world",
        world,
        *network_args(settings),
        *([] if settings.lease_ms == DEFAULT_LEASE_MS else ["--lease-ms", str(settings.lease_ms)]),
        *args,
    ]


def engine_command(
    engine: str, world: str, settings: SessionSettings, *args: str, gateway: str | None = None
) -> list[str]:
    """The command line of an engine: ``sim2d``, or ``grid`` (default loopback network only,
    or through the gateway at the ``ws://`` URL ``gateway``)."""
    if engine == "grid":
        through = ["--gateway", gateway] if gateway else []
        return [
            sys.executable,
            str(source_file(GRID_ENGINE, "--engine grid")),
            "--world",
            world,
            *through,
            *args,
        ]
    if engine != "sim2d":
        raise BridgeError(f"no engine '{engine}' here (sim2d or grid)")
    if gateway is not None:
        raise BridgeError("the sim2d engine speaks Zenoh only (no --gateway)")
    return node_command("sim2d", world, settings, *args)


BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS")
"""The variables that set how many threads numpy's BLAS uses in a node (one, unless the user
set them): the nodes of a run or an evaluation already keep every core busy as processes, and
BLAS threads spinning beside them halved ``toyroom eval``'s throughput on 2 cores (same
metrics, 209 s against 106 s for 6 embodied episodes) for a 5% gain in a brain alone."""


def node_environment(child: bool = True) -> dict[str, str]:
    """The environment a node starts with: this one, with single-threaded BLAS unless set,
    and, for a ``child`` process, this process's pid (:data:`PARENT_VARIABLE`: the node stops
    if this process dies; a node this process becomes by ``exec`` keeps what it inherited)."""
    env = dict(os.environ)
    for name in BLAS_THREADS:
        env.setdefault(name, "1")
    if child:
        env[PARENT_VARIABLE] = str(os.getpid())
    return env


def start_node(
    command: list[str], log_path: Path, *, group: bool = False, piped: bool = False, append: bool = False
) -> subprocess.Popen[bytes]:
    """Start a node with its output going to ``log_path`` (kept with the results), with
    :func:`node_environment`; with ``group``, as the leader of a process group of its own
    (a terminal's Ctrl-C then reaches only this process, which stops the node with
    :func:`stop_nodes`, helpers and all); with ``piped``, its standard input and output are
    pipes of the caller's (a node it talks to: ``python -m brain --episodes -``), and only its
    standard error goes to ``log_path``; with ``append``, the log is appended to (one log for
    the nodes that take turns at the same work)."""
    with log_path.open("ab" if append else "wb") as handle:
        return subprocess.Popen(
            command,
            stdin=subprocess.PIPE if piped else None,
            stdout=subprocess.PIPE if piped else handle,
            stderr=handle if piped else subprocess.STDOUT,
            env=node_environment(),
            start_new_session=group,
        )


def _signal_group(process: subprocess.Popen[bytes], sig: signal.Signals) -> None:
    """Send ``sig`` to the process group ``process`` leads (nothing when the group is gone)."""
    try:
        os.killpg(process.pid, sig)
    except (ProcessLookupError, PermissionError):
        pass


def stop_nodes(processes: Sequence[subprocess.Popen[bytes] | None], grace: float = 10.0) -> None:
    """Stop nodes started with ``group=True``, all at once: SIGTERM to every group, up to
    ``grace`` seconds for the leaders to exit, then SIGKILL to whatever is left of each group
    (a leader that ignored SIGTERM, helpers it did not wait for); every leader is reaped.
    Safe to call twice, and for nodes that have exited."""
    started = [p for p in processes if p is not None]
    for process in started:
        _signal_group(process, signal.SIGTERM)
    deadline = time.monotonic() + grace
    for process in started:
        try:
            process.wait(timeout=max(0.0, deadline - time.monotonic()))
        except subprocess.TimeoutExpired:
            log.warning("process %d ignored SIGTERM for %g s: killed", process.pid, grace)
    for process in started:
        _signal_group(process, signal.SIGKILL)
        process.wait(timeout=grace)


def check_brain_settings(settings: Path | None, overrides: Sequence[str], timeout: float = 120.0) -> None:
    """Ask the brain whether a settings file and ``NAME=VALUE`` overrides are allowed, before
    any node starts (``python -m brain check-settings``: a process, as the bridge never imports
    the brain). Nothing to ask when both are empty: the defaults are allowed.

    Raises:
        BridgeError: the brain's answer, naming the setting, its value and what is allowed.
    """
    if settings is None and not overrides:
        return
    command = [sys.executable, "-m", "brain", "check-settings", *settings_argv(settings, overrides)]
    result = subprocess.run(
        command, capture_output=True, text=True, timeout=timeout, env=node_environment(), check=False
    )
    if result.returncode != 0:
        lines = [line.removeprefix("brain: ") for line in result.stderr.splitlines() if line.strip()]
        raise BridgeError(f"bad settings: {lines[-1] if lines else f'exit status {result.returncode}'}")


def stop_node(process: subprocess.Popen[bytes], grace: float = 10.0) -> None:
    """SIGTERM, then SIGKILL if it has not exited within ``grace`` seconds."""
    if process.poll() is not None:
        return
    process.terminate()
    try:
        process.wait(timeout=grace)
    except subprocess.TimeoutExpired:
        log.warning("process %d ignored SIGTERM for %g s: killed", process.pid, grace)
        process.kill()
        process.wait(timeout=grace)


def report_failure(node: str, status: int | None, log_path: Path, lines: int = 20) -> None:
    """Say that a node failed, with the end of its log."""
    tail = (
        log_path.read_text(encoding="utf-8", errors="replace").splitlines()[-lines:]
        if log_path.exists()
        else []
    )
    print(f"toyroom run: the {node} exited with status {status}; end of {log_path}:", file=sys.stderr)
    for line in tail:
        print(f"  {line}", file=sys.stderr)


def wait_for_engine(
    bridge: Bridge,
    engine: subprocess.Popen[bytes],
    timeout: float = 60.0,
    stop: threading.Event | None = None,
) -> EngineInfo | None:
    """The engine's handshake, or ``None`` when its process exits first (or ``stop`` is set)."""
    deadline = time.monotonic() + timeout
    while engine.poll() is None and not (stop is not None and stop.is_set()):
        try:
            return handshake(bridge, client="toyroom-run", role="recorder", timeout=0.5)
        except NoReply:
            if time.monotonic() > deadline:
                raise
    return None
