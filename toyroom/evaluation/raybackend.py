"""The Ray backend of ``toyroom eval`` and ``toyroom fit`` (``pip install 'toyroom[ray]'``):
every episode (or fit job) a Ray task, so a sweep can go to a cluster (``--address``, or
``RAY_ADDRESS``); without one, Ray is started in this process, on loopback only, with usage
statistics off. Tasks are spread over the cluster's nodes.

Nothing of a task is read from, or written to, the driver's disk: the files a job names (a
scenario and its map, a recording) go with the task by value (``shipped``, each put in Ray's
object store once), and what a task makes comes back by value, for the driver to write. A node of a
cluster need not see the driver's files, only have the same toyroom installed.
"""

from __future__ import annotations

import os
import signal
import socket
import threading
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TypeVar

from bridge.errors import ConfigError

J = TypeVar("J")
R = TypeVar("R")

LOOPBACK = "127.0.0.1"
WAIT_S = 0.2
"""Seconds between two calls of ``run_with_ray``'s ``check`` while tasks run."""
LOCAL_ONLY = "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"
"""Ray's switch for clusters that never leave the machine: at ``0`` (read when Ray is
imported) Ray takes this machine's address to be ``127.0.0.1``, so its servers listen on
loopback only. Otherwise Ray turns ``127.0.0.1`` (``_node_ip_address``, ``ray start
--node-ip-address``, a cluster address) into the address of the machine's route out, and
listens on every interface."""


def cluster_address(address: str | None = None) -> str | None:
    """The Ray cluster to run on: ``address``, else ``RAY_ADDRESS``; ``None``: none (Ray is
    started in this process)."""
    return address or os.environ.get("RAY_ADDRESS") or None


def on_loopback(address: str) -> bool:
    """Whether a cluster address (``HOST:PORT``, not a ``ray://`` client address) is on this
    machine's loopback."""
    if "://" in address:
        return False
    host = address.rsplit(":", 1)[0].strip("[]").lower()
    return host in ("localhost", "::1") or host.startswith("127.")


def check_answers(address: str, timeout: float = 5.0) -> None:
    """Fail fast when nothing listens at a cluster address ``HOST:PORT`` (Ray itself would
    try for minutes); other forms (``auto``, ``ray://...``) are left to Ray.

    Raises:
        ConfigError: naming the address."""
    host, _, port = address.rpartition(":")
    if "://" in address or not host or not port.isdigit():
        return
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=timeout):
            pass
    except OSError as err:
        raise ConfigError(f"no Ray cluster answers at {address} ({err})") from None


def connect(address: str | None, workers: int) -> bool:
    """Join the cluster at ``address``, or (``None``) start Ray here with ``workers`` CPUs on
    loopback; ``False`` when this process was connected already (it stays so).

    Raises:
        ConfigError: nothing listens at ``address`` (:func:`check_answers`).
    """
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    if address is None or on_loopback(address):
        os.environ.setdefault(LOCAL_ONLY, "0")  # before Ray is imported: it reads it then
    import ray

    if ray.is_initialized():
        return False
    if address is not None:
        check_answers(address)
        ray.init(address=address, log_to_driver=False)
    else:
        ray.init(
            num_cpus=workers,
            include_dashboard=False,
            log_to_driver=False,
            _node_ip_address=LOOPBACK,
        )
    return True


def node_id() -> str:
    """The Ray node a task runs on (its hex id; empty outside Ray)."""
    import ray

    return ray.get_runtime_context().get_node_id() if ray.is_initialized() else ""


def run_with_ray(
    fn: Callable[..., R],
    jobs: Sequence[J],
    workers: int,
    progress: Callable[[int], None] | None = None,
    *,
    address: str | None = None,
    shipped: Callable[[J], Sequence[str]] | None = None,
    arrived: Callable[[R], R] | None = None,
    check: Callable[[], None] | None = None,
) -> list[R]:
    """``fn(job)`` for every job, as Ray tasks; the results in the order of ``jobs``.

    Args:
        fn: the task, run once per job.
        jobs: what ``fn`` is called with, one task each.
        workers: the CPUs of a Ray started here (no ``address``).
        progress: called with how many results have just arrived, each time some do.
        address: the cluster (:func:`cluster_address`: default ``RAY_ADDRESS``; none: Ray
            started here on loopback with ``workers`` CPUs).
        shipped: the files a job needs (paths on this machine), which go with it by value:
            ``fn(job, *files)``, each file as ``(its name, its bytes)``.
        arrived: applied to each result as it arrives (what it returns is kept), e.g. to
            write it out.
        check: called every ``WAIT_S`` s while tasks run; what it raises (a stop signal came)
            cancels the tasks left and is raised here. With it, the signal handlers this
            process had before Ray started are kept (Ray replaces SIGTERM's).
    """
    handlers = _handlers() if check is not None else {}
    started_here = connect(cluster_address(address), workers)
    for sig, handler in handlers.items():
        signal.signal(sig, handler)
    import ray

    try:
        task = ray.remote(num_cpus=1)(fn).options(scheduling_strategy="SPREAD")
        needs = [list(shipped(job)) if shipped is not None else [] for job in jobs]
        files = _put_files(ray, [path for paths in needs for path in paths])
        refs = [task.remote(job, *(files[p] for p in paths)) for job, paths in zip(jobs, needs, strict=True)]
        order = {ref: n for n, ref in enumerate(refs)}
        results: dict[int, R] = {}
        pending = list(refs)
        while pending:
            done, pending = ray.wait(pending, num_returns=1, timeout=None if check is None else WAIT_S)
            _checked(ray, check, pending)
            for ref in done:
                result = ray.get(ref)
                results[order[ref]] = arrived(result) if arrived is not None else result
            if progress is not None and done:
                progress(len(done))
        return [results[n] for n in range(len(jobs))]
    finally:
        if started_here:
            ray.shutdown()


def _handlers() -> dict[int, Any]:
    """SIGINT's and SIGTERM's handlers now (none outside the main thread: none can be set)."""
    if threading.current_thread() is not threading.main_thread():
        return {}
    return {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}


def _checked(ray: Any, check: Callable[[], None] | None, pending: Sequence[Any]) -> None:
    """``check()``; if it raises, every pending task is cancelled (its worker killed) first."""
    if check is None:
        return
    try:
        check()
    except BaseException:
        for ref in pending:
            ray.cancel(ref, force=True)
        raise


def _put_files(ray: Any, paths: Sequence[str]) -> dict[str, Any]:
    """Each file's ``(name, bytes)`` in Ray's object store, once per file, by its path."""
    return {path: ray.put((Path(path).name, Path(path).read_bytes())) for path in dict.fromkeys(paths)}
