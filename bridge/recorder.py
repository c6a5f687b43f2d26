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


class TraceRecorder:
    """Writes every message of ``bridge``'s world to ``path``. A context manager.

    Args:
        bridge: an open bridge on the world.
        path: the ``.jsonl`` file to write (truncated).
        info: the engine's handshake answer to write first (``None``: ask the engine).
        timeout: seconds to wait for the engine's handshake.
    """

    def __init__(
        self, bridge: Bridge, path: Path, *, info: EngineInfo | None = None, timeout: float = 30.0
    ) -> None:
        self.path = path
        self.count = 0
        self._lock = threading.Lock()
        self._file: IO[str] | None = path.open("w", encoding="utf-8")
        self._subscriber = bridge.subscribe(bridge.keys.all, self._write)
        info = (
            info
            if info is not None
            else handshake(bridge, client="toyroom-recorder", role="recorder", timeout=timeout)
        )
        self._write(info, Received(bridge.keys.info, bridge.encoding))

    def _write(self, message: Message, received: Received) -> None:
        line = trace_line(received.key, message)
        with self._lock:
            if self._file is None:
                return
            self._file.write(line + "\n")
            self._file.flush()
            self.count += 1

    def close(self) -> None:
        """Stop recording and close the file; safe to call twice."""
        self._subscriber.close()
        with self._lock:
            if self._file is not None:
                self._file.close()
                self._file = None

    def __enter__(self) -> TraceRecorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
