"""``trace.jsonl``, written and read here alone: every message on a world's keys, one JSON
object per line, so a run can be analysed again without an engine.

Each line is ``{"key": ..., "tick": ..., "payload": {...}}``; ``tick`` is the message's tick
when it has one, else ``null``. The engine's handshake answer comes first, under the key
``toyroom/<world>/engine/info`` (:attr:`protocol.Keys.info`). Lines are flushed as they are
written. :func:`trace_records` reads the lines back; :func:`read_trace` the episode a brain
consumed (the handshake, then each tick's state and events) from a trace or an MCAP file,
keeping what is readable of a cut-off one (:mod:`.readable`).
"""

from __future__ import annotations

import json
import logging
import threading
from collections import defaultdict
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO

from protocol import EngineInfo, Event, Keys, Message, ProtocolError, State, decode, to_builtins

from ..bridge import Bridge
from ..handshake import handshake
from ..pubsub import Received
from .readable import TraceError, read_recording

log = logging.getLogger("toyroom.recording")


def trace_line(key: str, message: Message) -> str:
    """One line of a trace (without the newline)."""
    payload = to_builtins(message)
    tick = payload.get("tick")
    return json.dumps({"key": key, "tick": tick if isinstance(tick, int) else None, "payload": payload})


def write_trace(messages: Iterable[tuple[str, Message]], target: Path) -> int:
    """Write ``(key, message)`` pairs as a ``trace.jsonl``; return how many."""
    count = 0
    with target.open("w", encoding="utf-8") as out:
        for key, message in messages:
            out.write(trace_line(key, message) + "\n")
            count += 1
    return count


class Recorder:
    """Records every message of ``bridge``'s world, the engine's handshake first. A context
    manager; subclasses say how a message is stored (:meth:`_store`) and how the file ends
    (:meth:`_finish`), in :attr:`path`. A write that fails (a full disk) ends the recording:
    :attr:`error` says why, in one line, and the messages after it are dropped (not one
    traceback per message); the caller says so.

    Args:
        bridge: an open bridge on the world.
        info: the engine's handshake answer to record first (``None``: ask the engine).
        timeout: seconds to wait for the engine's handshake.
    """

    path: Path
    """The file written."""

    def __init__(self, bridge: Bridge, *, info: EngineInfo | None = None, timeout: float = 30.0) -> None:
        self.count = 0
        self.error: str | None = None
        """Why the recording stopped being written (``None``: it did not)."""
        self._lock = threading.Lock()
        self._open = True
        self._subscriber = bridge.subscribe(bridge.keys.all, self._write)
        if info is None:
            info = handshake(bridge, client="toyroom-recorder", role="recorder", timeout=timeout)
        self._write(info, Received(bridge.keys.info, bridge.encoding))

    def _store(self, key: str, message: Message) -> None:
        raise NotImplementedError

    def _finish(self) -> None:
        raise NotImplementedError

    def _write(self, message: Message, received: Received) -> None:
        with self._lock:
            if self._open and self.error is None:
                try:
                    self._store(received.key, message)
                except OSError as err:
                    self._failed(err)
                    return
                self.count += 1

    def _failed(self, err: OSError) -> None:
        """A write failed: the recording ends here (the first failure is the one said)."""
        if self.error is None:
            self.error = write_error(err, self.path)
            log.debug("%s: the recording stops here", self.error)  # the caller reports it

    def close(self) -> None:
        """Stop recording and finish the file; safe to call twice."""
        self._subscriber.close()
        with self._lock:
            if self._open:
                self._open = False
                try:
                    self._finish()
                except OSError as err:  # its last records could not be written
                    self._failed(err)

    def __enter__(self) -> Recorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def write_error(err: OSError, path: Path) -> str:
    """One line for a failed write: ``no space left on device writing trace.jsonl``."""
    what = err.strerror or str(err)
    return f"{what[:1].lower()}{what[1:]} writing {path.name}"


class TraceRecorder(Recorder):
    """Writes every message of a world to a ``trace.jsonl`` (flushed line by line)."""

    def __init__(
        self, bridge: Bridge, path: Path, *, info: EngineInfo | None = None, timeout: float = 30.0
    ) -> None:
        self.path = path
        self._file: IO[str] = path.open("w", encoding="utf-8")
        super().__init__(bridge, info=info, timeout=timeout)

    def _store(self, key: str, message: Message) -> None:
        self._file.write(trace_line(key, message) + "\n")
        self._file.flush()

    def _finish(self) -> None:
        self._file.close()


@dataclass(frozen=True)
class Trace:
    """A recorded episode: the handshake and ``(state, events)`` per tick, in tick order."""

    info: EngineInfo
    ticks: tuple[tuple[State, tuple[Event, ...]], ...]

    def __iter__(self) -> Iterator[tuple[State, tuple[Event, ...]]]:
        return iter(self.ticks)


def trace_records(path: Path, *, strict: bool = True) -> Iterator[tuple[int, str, Message]]:
    """``(line number, key, message)`` of every line of a trace, in file order.

    Raises:
        TraceError: when the file cannot be read, or (``strict``) naming the file and line
            of a line that is not a trace line; without ``strict`` such lines are skipped.
    """
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
                if strict:
                    raise TraceError(f"{path}:{number}: not a trace line ({err})") from None
                continue
            yield number, key, message


def read_trace(path: Path, episode: int | None = None, *, strict: bool = False) -> Trace:
    """Read the episode a brain consumed from a trace (or an MCAP file); ``episode``
    defaults to the last one. Of a cut-off or damaged file, the part before the break is
    read, with a warning naming the byte offset and the ticks kept (:mod:`.readable`).

    Raises:
        TraceError: naming the file when it is missing, of neither format, cut off (only
            with ``strict``), or has no handshake or no state.
    """
    recording = read_recording(path)
    if recording.cut is not None:
        if strict:
            raise TraceError(recording.cut.warning())
        log.warning("%s", recording.cut.warning())
    return episode_of(recording.messages(), path, episode)


def episode_of(messages: Iterable[tuple[str, Message]], path: Path, episode: int | None = None) -> Trace:
    """The episode (default: the last) in a recording's ``(key, message)`` pairs.

    Raises:
        TraceError: naming ``path`` when there is no handshake, no state, or no state of
            ``episode``.
    """
    info: EngineInfo | None = None
    keys: Keys | None = None
    states: dict[tuple[int, int], State] = {}
    events: dict[tuple[int, int], list[Event]] = defaultdict(list)
    for key, message in messages:
        if isinstance(message, EngineInfo) and info is None:
            info, keys = message, Keys(key.split("/")[1]) if key.count("/") >= 2 else None
        elif keys is None or key not in (keys.state, keys.events):
            continue
        elif isinstance(message, State):
            states[(message.episode, message.tick)] = message
        elif isinstance(message, Event):
            events[(message.episode, message.tick)].append(message)
    if info is None:
        raise TraceError(f"{path}: no engine handshake (engine/info) in the recording")
    if not states:
        raise TraceError(f"{path}: no engine state in the recording")
    chosen = episode if episode is not None else max(e for e, _ in states)
    ticks = tuple(
        (states[key], tuple(events.get(key, ()))) for key in sorted(k for k in states if k[0] == chosen)
    )
    if not ticks:
        raise TraceError(f"{path}: no state of episode {chosen}")
    return Trace(info=info, ticks=ticks)
