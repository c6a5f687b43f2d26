"""A play recording: the MCAP file of one participant's world, ended by the ``toyroom.play``
metadata record that says who played, how it ended and why (:func:`play_metadata`)."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from mcap.records import Metadata
from mcap.stream_reader import StreamReader

from bridge.bridge import Bridge
from bridge.recording.mcap import McapRecorder
from protocol import EngineInfo

PLAY_METADATA = "toyroom.play"
"""The MCAP metadata record of a play recording: participant, person, scenario, world,
``rate``, ``complete`` (``"true"`` or ``"false"``), ``outcome`` (``goal_reached``,
``timed_out``, ``ended`` or ``incomplete``), ``reason`` and ``last_tick``."""


def play_metadata(path: Path) -> dict[str, str] | None:
    """The ``toyroom.play`` metadata of a play recording (``None``: none, as in a file whose
    server was killed: incomplete too)."""
    with path.open("rb") as handle:
        reader = StreamReader(handle, skip_magic=False, emit_chunks=False, validate_crcs=False)
        try:
            for record in reader.records:
                if isinstance(record, Metadata) and record.name == PLAY_METADATA:
                    return dict(record.metadata)
        except Exception:  # a file cut off mid-record  # noqa: BLE001
            return None
    return None


class PlayRecorder(McapRecorder):
    """An MCAP recorder that ends its file with the ``toyroom.play`` metadata record."""

    def __init__(
        self, bridge: Bridge, path: Path, info: EngineInfo, meta: Callable[[], dict[str, str]]
    ) -> None:
        self._meta = meta
        super().__init__(bridge, path, info=info)

    def _finish(self) -> None:
        self._writer.add_metadata(PLAY_METADATA, self._meta())
        super()._finish()


def complete_only(paths: Sequence[Path], include: bool) -> tuple[list[Path], list[str]]:
    """The recordings to use (``toyroom fit``, ``toyroom rate``), and a note for each
    incomplete ``toyroom play`` recording left out (its metadata says ``complete = false``: the
    page was closed, the world ended early); with ``include``, every recording, and no note."""
    kept, left = [], []
    for path in paths:
        meta = play_metadata(path) if path.suffix == ".mcap" and path.is_file() else None
        if meta is not None and meta.get("complete") == "false" and not include:
            left.append(f"{path} ({meta.get('reason') or 'incomplete'})")
        else:
            kept.append(path)
    return kept, left
