"""The local backend of ``toyroom eval``: chunks of episodes on a pool of threads (each
thread drives its episodes' node processes), every episode handed on as its chunk comes
back, and a stop signal (:mod:`.interrupt`) honoured within seconds: the pool is looked at
every :data:`POLL_S` s, nothing that comes back after the signal is kept, the nodes are
stopped and the threads' queued chunks cancelled."""

from __future__ import annotations

import signal
from collections.abc import Callable, Sequence
from concurrent.futures import FIRST_COMPLETED, Future, ThreadPoolExecutor, wait
from typing import TypeVar

from .interrupt import NODES

J = TypeVar("J")
R = TypeVar("R")

POLL_S = 0.2
"""Seconds between two looks at the pool (and at a stop signal)."""


def run_chunks(
    chunks: Sequence[Sequence[J]],
    run: Callable[[Sequence[J]], list[R]],
    workers: int,
    done: Callable[[J, R], None],
) -> None:
    """``run(chunk)`` for every chunk, ``workers`` at a time, and ``done(job, result)`` for
    each job of a chunk as the chunk comes back (in the calling thread).

    Raises:
        EvaluationStopped: a stop signal came (or KeyboardInterrupt, outside
            :func:`~.interrupt.catch_signals`); every node is stopped first, and what came
            back before the signal was handed to ``done``.
    """
    pool = ThreadPoolExecutor(max_workers=workers)
    futures: dict[Future[list[R]], Sequence[J]] = {pool.submit(run, chunk): chunk for chunk in chunks}
    pending = set(futures)
    try:
        while pending and not NODES.stopping:
            finished, pending = wait(pending, timeout=POLL_S, return_when=FIRST_COMPLETED)
            if NODES.stopping:  # what came back with the signal may be a stopped node's doing
                break
            for future in finished:
                for job, result in zip(futures[future], future.result(), strict=True):
                    done(job, result)
    except KeyboardInterrupt:
        NODES.signalled(signal.SIGINT)
    finally:
        if NODES.stopping:
            NODES.finish()
        pool.shutdown(wait=True, cancel_futures=True)
    NODES.check()
