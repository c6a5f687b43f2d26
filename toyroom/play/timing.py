"""Whether a play recording held real time (pure over a recording): the engine's ticks per
wall-clock second while it ran, against what its rate asks for."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from bridge.recording.readable import read_recording

PAUSE_S = 1.0
"""A gap between two recorded states longer than this (s) is a pause (the page away), not
counted."""


def held_rate(path: Path, rate: float, tick_seconds: float) -> float | None:
    """The engine's achieved speed over the recording's last episode as a fraction of the
    asked one (``rate`` x wall clock, ticks of ``tick_seconds``): 1.0 held real time exactly,
    0.5 ran at half speed. ``None``: fewer than two states. States are those on
    ``engine/state``, timed by the recorder's clock (``log_time``); pauses are left out."""
    ticks: list[tuple[int, int, int]] = []  # (episode, tick, log time ns)
    for record in read_recording(path).records:
        if record.key.endswith("/engine/state"):
            payload = json.loads(record.data)
            ticks.append((int(payload["episode"]), int(payload["tick"]), record.log_time))
    if not ticks:
        return None
    last = max(e for e, _, _ in ticks)
    array = np.array([(t, ns) for e, t, ns in ticks if e == last], dtype=float).reshape(-1, 2)
    if len(array) < 2:
        return None
    steps, seconds = np.diff(array[:, 0]), np.diff(array[:, 1]) / 1e9
    running = seconds <= PAUSE_S
    wall = float(seconds[running].sum())
    if wall <= 0:
        return None
    return float(steps[running].sum()) * tick_seconds / rate / wall
