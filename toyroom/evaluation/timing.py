"""How long an evaluation took (``metrics.json``'s ``timing``): wall seconds, each episode's
and each kind of run's own seconds, and the CPU seconds of the evaluator and of its node
processes."""

from __future__ import annotations

import resource
from typing import Any

from .records import EpisodeRecord


def cpu_seconds() -> dict[str, float]:
    """CPU seconds used so far by this process (the evaluator) and by its finished child
    processes (the nodes, and the scenario generator)."""
    me, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return {"evaluator": me.ru_utime + me.ru_stime, "nodes": children.ru_utime + children.ru_stime}


def timing(
    results: list[EpisodeRecord], took: float, workers: int, cpu: dict[str, float] | None = None
) -> dict[str, Any]:
    """How long the evaluation took: wall seconds in all and per episode (with ``workers`` at
    a time), one episode's own seconds and each kind of run's, averaged, and the CPU seconds
    per episode of the evaluator and of the node processes (``cpu``: the whole evaluation's;
    ``None`` with Ray, whose workers are not this process's children). The wall seconds per
    episode can be no lower than the CPU seconds per episode over the machine's cores."""
    own = [r.seconds for r in results if r.seconds is not None]
    runs: dict[str, list[float]] = {}
    for r in results:
        for name, seconds in (r.run_seconds or {}).items():
            runs.setdefault(name, []).append(seconds)
    return {
        "seconds": took,
        "workers": workers,
        "seconds_per_episode": took / max(1, len(results)),
        "episode_seconds_mean": sum(own) / len(own) if own else None,
        "run_seconds_mean": {name: sum(v) / len(v) for name, v in sorted(runs.items())},
        "cpu_seconds_per_episode": (
            None if cpu is None else {k: v / max(1, len(results)) for k, v in sorted(cpu.items())}
        ),
    }
