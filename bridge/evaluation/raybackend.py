"""The Ray backend of ``toyroom eval`` and ``toyroom fit`` (``pip install 'toyroom[ray]'``):
every episode (or fit job) a Ray task, so a sweep can go to a cluster. Locally, Ray is
started on loopback only, with usage statistics off; on a cluster, set ``RAY_ADDRESS``."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from typing import TypeVar

J = TypeVar("J")
R = TypeVar("R")


def run_with_ray(
    fn: Callable[[J], R],
    jobs: Sequence[J],
    workers: int,
    progress: Callable[[int], None] | None = None,
) -> list[R]:
    """``fn(job)`` for every job, as Ray tasks; the results in the order of ``jobs``."""
    os.environ.setdefault("RAY_USAGE_STATS_ENABLED", "0")
    import ray

    started_here = not ray.is_initialized()
    if started_here:
        if os.environ.get("RAY_ADDRESS"):
            ray.init(address=os.environ["RAY_ADDRESS"], log_to_driver=False)
        else:
            ray.init(
                num_cpus=workers,
                include_dashboard=False,
                log_to_driver=False,
                _node_ip_address="127.0.0.1",
            )
    try:
        task = ray.remote(num_cpus=1)(fn)
        refs = [task.remote(job) for job in jobs]
        pending = list(refs)
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            if progress is not None:
                progress(len(done))
        return list(ray.get(refs))
    finally:
        if started_here:
            ray.shutdown()
