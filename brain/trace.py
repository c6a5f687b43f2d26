"""Reading a ``trace.jsonl`` back: the engine's handshake and, tick by tick, the state and
the events of one episode, exactly what the live brain consumed."""

from __future__ import annotations

import json
from collections import defaultdict
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from protocol import EngineInfo, Event, ProtocolError, State, decode

from .errors import TraceError


@dataclass(frozen=True)
class Trace:
    """A recorded episode: the handshake and ``(state, events)`` per tick, in tick order."""

    info: EngineInfo
    ticks: tuple[tuple[State, tuple[Event, ...]], ...]

    def __iter__(self) -> Iterator[tuple[State, tuple[Event, ...]]]:
        return iter(self.ticks)


def read_trace(path: Path, episode: int | None = None) -> Trace:
    """Read a trace; ``episode`` defaults to the last one recorded.

    Raises:
        TraceError: naming the file and line when a line is not a trace line, or when the
            trace has no handshake or no state.
    """
    info: EngineInfo | None = None
    states: dict[tuple[int, int], State] = {}
    events: dict[tuple[int, int], list[Event]] = defaultdict(list)
    try:
        handle = path.open(encoding="utf-8")
    except OSError as err:
        raise TraceError(f"{path}: cannot read the trace ({err})") from None
    with handle:
        for number, line in enumerate(handle, start=1):
            if not line.strip():
                continue
            try:
                record = json.loads(line)
                key = str(record["key"])
                message = decode(json.dumps(record["payload"]).encode())
            except (ValueError, KeyError, TypeError, ProtocolError) as err:
                raise TraceError(f"{path}:{number}: not a trace line ({err})") from None
            if key.endswith("/engine/info") and isinstance(message, EngineInfo):
                info = message
            elif isinstance(message, State) and key.endswith("/engine/state"):
                states[(message.episode, message.tick)] = message
            elif isinstance(message, Event) and key.endswith("/engine/events"):
                events[(message.episode, message.tick)].append(message)
    if info is None:
        raise TraceError(f"{path}: no engine handshake (engine/info) in the trace")
    if not states:
        raise TraceError(f"{path}: no engine state in the trace")
    chosen = episode if episode is not None else max(e for e, _ in states)
    ticks = tuple(
        (states[key], tuple(events.get(key, ()))) for key in sorted(k for k in states if k[0] == chosen)
    )
    if not ticks:
        raise TraceError(f"{path}: no state of episode {chosen}")
    return Trace(info=info, ticks=ticks)
