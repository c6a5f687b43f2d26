"""A brain's run log: what it handled and what it inferred, as JSON lines, for a program
that scores the run afterwards (``toyroom eval``) instead of listening to every message.

Two files in one directory: ``inputs.jsonl`` holds the engine's handshake (``engine_info``:
the scene; again if the engine came back), and every state the brain handled, each
followed by the events that came with it, one protocol message per line, in order; and
``minds-<observer>.jsonl`` the live observer's ``mind`` messages, one per line, exactly as
published (the shadow observers' files have the same form: :mod:`brain.outputs.shadows`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import IO

from protocol import EngineInfo, Event, Mind, State, encode

from ..tracking.tracker import Observer
from .shadows import shadow_path


def inputs_path(directory: Path) -> Path:
    """Where a run log's states and events go: ``DIR/inputs.jsonl``."""
    return directory / "inputs.jsonl"


class RunLog:
    """Writes a run's inputs and the live ``observer``'s minds into ``directory`` (created if
    missing; files of an earlier run there are replaced)."""

    def __init__(self, directory: Path, observer: Observer) -> None:
        directory.mkdir(parents=True, exist_ok=True)
        self._inputs: IO[bytes] = inputs_path(directory).open("wb")
        self._minds: IO[bytes] = shadow_path(directory, observer).open("wb")

    def engine(self, info: EngineInfo) -> None:
        """The handshake of the engine followed from here on."""
        self._inputs.write(encode(info) + b"\n")

    def inputs(self, state: State, events: Sequence[Event]) -> None:
        """One tick as the brain received it: its state, then its events."""
        self._inputs.write(b"".join(encode(m) + b"\n" for m in (state, *events)))

    def mind(self, mind: Mind) -> None:
        self._minds.write(encode(mind) + b"\n")

    def close(self) -> None:
        """Finish both files; safe to call twice."""
        self._inputs.close()
        self._minds.close()
