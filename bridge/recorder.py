"""Recording a world to ``trace.jsonl``: every message on the world's keys, one JSON object
per line, so a run can be analysed again without an engine.

Each line is ``{"key": ..., "tick": ..., "payload": {...}}``; ``tick`` is the message's tick
when it has one, else ``null``. The engine's handshake answer comes first, under the key
``toyroom/<world>/engine/info``. Lines are flushed as they are written.
"""

from __future__ import annotations

import json
import threading
from pathlib import Path
from typing import IO

from protocol import EngineInfo, Message, to_builtins

from .handshake import handshake
from .node import Bridge
from .typed import Received


def trace_line(key: str, message: Message) -> str:
    """One line of a trace (without the newline)."""
    payload = to_builtins(message)
    tick = payload.get("tick")
    return json.dumps({"key": key, "tick": tick if isinstance(tick, int) else None, "payload": payload})


class Recorder:
    """Records every message of ``bridge``'s world, the engine's handshake first. A context
    manager; subclasses say how a message is stored (:meth:`_store`) and how the file ends
    (:meth:`_finish`).

    Args:
        bridge: an open bridge on the world.
        info: the engine's handshake answer to record first (``None``: ask the engine).
        timeout: seconds to wait for the engine's handshake.
    """

    def __init__(self, bridge: Bridge, *, info: EngineInfo | None = None, timeout: float = 30.0) -> None:
        self.count = 0
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
            if self._open:
                self._store(received.key, message)
                self.count += 1

    def close(self) -> None:
        """Stop recording and finish the file; safe to call twice."""
        self._subscriber.close()
        with self._lock:
            if self._open:
                self._open = False
                self._finish()

    def __enter__(self) -> Recorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


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
