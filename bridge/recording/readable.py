"""What is readable of a recording, in either format, under one policy.

A recording is a ``trace.jsonl`` (:mod:`.trace`) or an MCAP file (:mod:`.mcap`). Either may
be cut off (a recorder killed mid-write, a copy that stopped, a full disk) or damaged
further in. Both are read the same way: every message up to the first byte that cannot be
read is kept, and a :class:`Cut` says where reading stopped (the byte offset), why, and
which ticks were kept. Commands warn with :meth:`Cut.warning` and, with ``--strict``,
refuse such a file. A file that is missing, that is no recording of either format, or
whose readable part holds no message is a :class:`RecordingError` naming the file and the
problem.
"""

from __future__ import annotations

import json
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO

import msgspec
from mcap.exceptions import EndOfFile, InvalidMagic, McapError
from mcap.records import Channel, Footer
from mcap.records import Message as McapMessage
from mcap.stream_reader import StreamReader

from protocol import Message, ProtocolError, decode

from ..errors import BridgeError

MCAP_MAGIC = b"\x89MCAP0\r\n"
"""The eight bytes every MCAP file starts (and a finished one ends) with."""


class TraceError(BridgeError):
    """A trace that cannot be read: names the file (and line) and what is wrong."""


class RecordingError(TraceError):
    """A recording that cannot be read at all: missing, of neither format, or without a
    readable message. Names the file and the problem in one line."""


@dataclass(frozen=True)
class Recorded:
    """One recorded message: its key, its JSON payload, and when it was recorded (ns since
    the epoch; 0 in a ``trace.jsonl``, which keeps no times)."""

    key: str
    data: bytes
    log_time: int = 0


@dataclass(frozen=True)
class Cut:
    """Where a recording stopped being readable.

    Attributes:
        path: the file.
        offset: the byte offset of the first byte not read (everything before it was kept).
        size: the file's size in bytes.
        reason: why reading stopped there.
        ticks: the lowest and highest tick of the engine states kept (``None``: none).
        messages: how many messages were kept.
    """

    path: Path
    offset: int
    size: int
    reason: str
    ticks: tuple[int, int] | None
    messages: int

    def warning(self) -> str:
        """One line: the file, where and why it broke, and what was kept."""
        kept = f"ticks {self.ticks[0]}-{self.ticks[1]}" if self.ticks else "no tick"
        return (
            f"{self.path}: unreadable from byte {self.offset} of {self.size} ({self.reason}); "
            f"kept {kept} ({self.messages} messages before it)"
        )


@dataclass(frozen=True)
class Recording:
    """The readable part of a recording: its messages in recorded order, and where it broke
    (``cut``; ``None`` for a whole file)."""

    path: Path
    format: str
    """``mcap`` or ``trace`` (a ``trace.jsonl``)."""
    records: tuple[Recorded, ...]
    cut: Cut | None = None

    def messages(self) -> Iterator[tuple[str, Message]]:
        """``(key, message)`` of every record this version of the protocol decodes (others,
        such as a newer peer's message types, are passed over)."""
        for record in self.records:
            try:
                yield record.key, decode(record.data)
            except ProtocolError:
                continue


def _tick_range(records: list[Recorded]) -> tuple[int, int] | None:
    """The lowest and highest tick of the engine states among ``records``."""
    ticks = []
    for record in records:
        if not record.key.endswith("/engine/state"):
            continue
        try:
            tick = msgspec.json.decode(record.data).get("tick")
        except (msgspec.DecodeError, AttributeError):
            continue
        if isinstance(tick, int) and not isinstance(tick, bool):
            ticks.append(tick)
    return (min(ticks), max(ticks)) if ticks else None


def _ended(
    path: Path, kind: str, records: list[Recorded], offset: int, size: int, reason: str | None
) -> Recording:
    """The recording (of format ``kind``) read, or the error when nothing of it could be."""
    if not records:
        what = "an MCAP recording" if kind == "mcap" else "a recording (trace.jsonl or MCAP)"
        problem = f"not {what}: {reason}" if reason else "holds no messages"
        raise RecordingError(f"{path}: {problem}")
    cut = None
    if reason is not None:
        cut = Cut(path, offset, size, reason, _tick_range(records), len(records))
    return Recording(path, kind, tuple(records), cut)


def _starts_with_magic(path: Path) -> bool:
    with path.open("rb") as handle:
        return handle.read(len(MCAP_MAGIC)) == MCAP_MAGIC


class _Counting:
    """A binary file that counts the bytes read from it (the MCAP reader's position)."""

    def __init__(self, handle: IO[bytes]) -> None:
        self.handle = handle
        self.count = 0

    def read(self, size: int = -1) -> bytes:
        data = self.handle.read(size)
        self.count += len(data)
        return data


def _read_mcap(path: Path, size: int) -> Recording:
    records: list[Recorded] = []
    channels: dict[int, Channel] = {}
    end, reason = 0, None
    with path.open("rb") as handle:
        counting = _Counting(handle)
        reader = StreamReader(
            counting,  # type: ignore[arg-type]
            skip_magic=False,
            emit_chunks=False,
            validate_crcs=False,
            record_size_limit=size,
        )
        try:
            for record in reader.records:
                end = counting.count
                if isinstance(record, Channel):
                    channels[record.id] = record
                elif isinstance(record, McapMessage) and record.channel_id in channels:
                    topic = channels[record.channel_id].topic
                    records.append(Recorded(topic, bytes(record.data), record.log_time))
                elif isinstance(record, Footer):
                    return _ended(path, "mcap", records, end, size, None)
        except InvalidMagic:
            reason = "it does not start with the MCAP magic bytes"  # (the footer returns first)
        except EndOfFile:
            reason = (
                "it ends without the MCAP footer: the recorder did not finish the file"
                if counting.count == end
                else "it ends mid-record"
            )
        except (McapError, ValueError, UnicodeDecodeError, OverflowError, MemoryError) as err:
            reason = f"a damaged record ({type(err).__name__}: {err})"
    return _ended(path, "mcap", records, end, size, reason)


def _read_trace(path: Path, size: int) -> Recording:
    records: list[Recorded] = []
    offset, reason = 0, None
    with path.open("rb") as handle:
        for number, raw in enumerate(handle, start=1):
            if raw.strip():
                try:
                    line = json.loads(raw)
                    key, payload = line["key"], line["payload"]
                    if not isinstance(key, str) or not isinstance(payload, dict):
                        raise TypeError("expected a string 'key' and an object 'payload'")
                except (ValueError, KeyError, TypeError) as err:
                    if not records:
                        kind = "a recording (trace.jsonl or MCAP)"
                        raise RecordingError(f"{path}:{number}: not {kind}: {err}") from None
                    cut_short = not raw.endswith(b"\n")
                    reason = f"line {number} is cut off" if cut_short else f"line {number}: {err}"
                    break
                records.append(Recorded(key, json.dumps(payload).encode()))
            offset += len(raw)
    return _ended(path, "trace", records, offset, size, reason)


def read_recording(path: Path) -> Recording:
    """Read what is readable of a ``trace.jsonl`` or an MCAP file (told apart by the MCAP
    magic bytes, or the ``.mcap`` suffix).

    Raises:
        RecordingError: the file is missing, unreadable, of neither format, or holds no
            readable message; one line naming the file and the problem.
    """
    if not path.exists():
        raise RecordingError(f"{path}: no such file")
    if path.is_dir():
        raise RecordingError(f"{path}: a folder, not a recording (trace.jsonl or .mcap)")
    try:
        size = path.stat().st_size
        is_mcap = path.suffix == ".mcap" or _starts_with_magic(path)
        if size == 0:
            raise RecordingError(f"{path}: an empty file, not a recording")
        return _read_mcap(path, size) if is_mcap else _read_trace(path, size)
    except OSError as err:
        raise RecordingError(f"{path}: cannot read it ({err.strerror or err})") from None
