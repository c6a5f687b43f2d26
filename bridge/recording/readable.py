"""What is readable of a recording, in either format, under one policy.

A recording is a ``trace.jsonl`` (:mod:`.trace`) or an MCAP file (:mod:`.mcap`). Either may
be cut off (a recorder killed mid-write, a copy that stopped, a full disk) or damaged
further in. Both are read the same way: every message up to the first byte that cannot be
read is kept; of those, a message on a toyroom key that does not decode (a field of the
wrong type, a number that is not finite, bytes that are not JSON) is damage and is dropped
(:class:`Dropped`: its byte offset, key, tick and what is wrong), and messages on topics
that are not toyroom keys (``toyroom/<world>/...``: another program's) are passed over. A
:class:`Cut` says where reading stopped (the byte offset) and why, what was dropped, and
which ticks were kept. Commands warn with :meth:`Cut.warning` and, with ``--strict``,
refuse such a file. An MCAP file is read by :mod:`.mcapstream`: one that ends early (inside
its opening magic, mid-record, without its footer, inside its summary or footer, inside its
closing magic) is cut off, and keeps every message whole before the cut. A file that is
missing, that is no recording of either format, that holds no message on a toyroom key (a
foreign MCAP), whose readable part holds no message (a file cut off before its first whole
message says so), or that mixes the keys of two worlds (``toyroom/a/...`` and
``toyroom/b/...``: no recorder writes that) is a :class:`RecordingError` naming the file and
the problem (the worlds found).

A message of a type this version does not know, declared by a newer minor version of the
protocol, is no damage (minor versions only add): it is kept for replay and passed over by
:meth:`Recording.messages`.
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from protocol import PROTOCOL_VERSION, Message, ProtocolError, State, Version, decode, read_header

from ..errors import BridgeError
from .mcapstream import read_mcap_file, starts_with_magic

TOYROOM_KEY = re.compile(r"toyroom/[^/*$#?]+(?:/[^/*$#?]+)+")
"""A key a toyroom recorder writes: ``toyroom/<world>/...``, no empty chunk, no wildcard."""
SHOWN = 3
"""How many dropped messages (or foreign topics) a line names before saying how many more."""


class TraceError(BridgeError):
    """A trace that cannot be read: names the file (and line) and what is wrong."""


class RecordingError(TraceError):
    """A recording that cannot be read at all: missing, of neither format, foreign, or
    without a readable message. Names the file and the problem in one line."""


@dataclass(frozen=True)
class Recorded:
    """One recorded message: its key, its JSON payload, and when it was recorded (ns since
    the epoch; 0 in a ``trace.jsonl``, which keeps no times)."""

    key: str
    data: bytes
    log_time: int = 0
    offset: int = 0
    """Where its record (its line in a ``trace.jsonl``) starts in the file, in bytes."""


@dataclass(frozen=True)
class Dropped:
    """A message inside a recording that does not decode: damage, dropped."""

    offset: int
    """Where its record starts in the file, in bytes."""
    key: str
    tick: object
    """Its ``tick`` as written (``None``: none could be read), e.g. ``'abc'``."""
    reason: str
    """Why it does not decode (the protocol's error: the field and what came)."""

    def describe(self) -> str:
        """``byte 1234: engine/state tick 'abc': invalid 'state' message at field $.tick: ...``."""
        tick = "" if self.tick is None else f" tick {self.tick!r}"
        return f"byte {self.offset}: {self.key.split('/', 2)[-1]}{tick}: {self.reason}"


def _listed(items: Sequence[str]) -> str:
    """The first :data:`SHOWN` of ``items``, then how many more."""
    more = f"; and {len(items) - SHOWN} more" if len(items) > SHOWN else ""
    return "; ".join(items[:SHOWN]) + more


@dataclass(frozen=True)
class Cut:
    """Why a recording is not whole: where it stopped being readable, the messages inside it
    dropped as damaged, or both.

    Attributes:
        path: the file.
        offset: the byte offset of the first byte not read (everything before it was kept;
            the file's size when it was read to its end).
        size: the file's size in bytes.
        reason: why reading stopped there (``None``: it did not; the file was read to its end).
        ticks: the lowest and highest tick of the engine states kept (``None``: none).
        messages: how many messages were kept.
        dropped: the messages that do not decode, dropped (in file order).
    """

    path: Path
    offset: int
    size: int
    reason: str | None
    ticks: tuple[int, int] | None
    messages: int
    dropped: tuple[Dropped, ...] = ()
    early: bool = True
    """Whether the file ends early (cut off: its end is missing); ``False``: reading stopped
    at a damaged record with the file's end after it."""

    @property
    def kind(self) -> str:
        """``cut off``, ``damaged`` or ``cut off and damaged``."""
        if self.reason is None or not self.early:
            return "damaged"
        return "cut off and damaged" if self.dropped else "cut off"

    def warning(self) -> str:
        """One line: the file, where and why it broke, what was dropped, and what was kept."""
        kept = f"ticks {self.ticks[0]}-{self.ticks[1]}" if self.ticks else "no tick"
        count = len(self.dropped)
        dropped = (
            f"dropped {count} message{'s' if count != 1 else ''} that cannot be decoded "
            f"({_listed([d.describe() for d in self.dropped])})"
        )
        if self.reason is None:
            return f"{self.path}: damaged: {dropped}; kept {kept} ({self.messages} messages)"
        also = f"; {dropped}" if self.dropped else ""
        return (
            f"{self.path}: {self.kind}: unreadable from byte {self.offset} of {self.size} ({self.reason}); "
            f"kept {kept} ({self.messages} messages before it){also}"
        )

    def note(self) -> str:
        """A paragraph for a report (Markdown): the recording was not whole, and what of it
        the report stands on."""
        return f"**The recording was {self.kind}**; this report stands on what was kept: {self.warning()}\n"


@dataclass(frozen=True)
class Recording:
    """The readable part of a recording: its records on toyroom keys in recorded order
    (damaged ones dropped), and why it is not whole (``cut``; ``None`` for a whole file)."""

    path: Path
    format: str
    """``mcap`` or ``trace`` (a ``trace.jsonl``)."""
    records: tuple[Recorded, ...]
    """Every record on a toyroom key that is not damage (a newer minor's types included)."""
    cut: Cut | None = None
    decoded: tuple[tuple[str, Message], ...] = ()
    """``(key, message)`` of every record this version of the protocol decodes."""
    foreign: tuple[str, ...] = ()
    """The topics passed over as not toyroom keys, each once, in file order."""

    def messages(self) -> Iterator[tuple[str, Message]]:
        """``(key, message)`` of every record this version of the protocol decodes (others,
        such as a newer peer's message types, are passed over)."""
        return iter(self.decoded)


def _tick_range(messages: Sequence[tuple[str, Message]]) -> tuple[int, int] | None:
    """The lowest and highest tick of the engine states among ``messages``."""
    ticks = [m.tick for key, m in messages if isinstance(m, State) and key.endswith("/engine/state")]
    return (min(ticks), max(ticks)) if ticks else None


def _written_tick(data: bytes) -> object:
    """The ``tick`` of a payload as written (``None``: it has none, or is no JSON object)."""
    try:
        value = json.loads(data)
    except (ValueError, RecursionError):
        return None
    return value.get("tick") if isinstance(value, dict) else None


def _newer_type(data: bytes) -> bool:
    """Whether a payload that does not decode declares a newer minor version of the protocol
    (a message type added since: no damage, as minor versions only add)."""
    try:
        header = read_header(data)
        return Version.parse(header.protocol) > Version.parse(PROTOCOL_VERSION)
    except ProtocolError:
        return False


@dataclass(frozen=True)
class _Sorted:
    """A recording's records, sorted (see the module docstring)."""

    records: list[Recorded] = field(default_factory=list)
    decoded: list[tuple[str, Message]] = field(default_factory=list)
    dropped: list[Dropped] = field(default_factory=list)
    foreign: dict[str, None] = field(default_factory=dict)


def _sort(records: list[Recorded]) -> _Sorted:
    """Keep the toyroom records that decode (or are a newer minor's types), drop the damaged
    ones, pass over foreign topics."""
    found = _Sorted()
    for record in records:
        if TOYROOM_KEY.fullmatch(record.key) is None:
            found.foreign.setdefault(record.key)
            continue
        try:
            found.decoded.append((record.key, decode(record.data)))
        except ProtocolError as err:
            if not _newer_type(record.data):
                tick = _written_tick(record.data)
                found.dropped.append(Dropped(record.offset, record.key, tick, str(err)))
                continue
        found.records.append(record)
    return found


def _one_world(path: Path, found: _Sorted) -> None:
    """Nothing, when the toyroom records (kept or dropped) are of one world.

    Raises:
        RecordingError: naming the worlds (``toyroom/<world>/...``) found, in file order."""
    keys = [r.key for r in found.records] + [d.key for d in found.dropped]
    worlds = list(dict.fromkeys(key.split("/")[1] for key in keys))
    if len(worlds) > 1:
        named = ", ".join(map(repr, worlds[:SHOWN]))
        more = f", and {len(worlds) - SHOWN} more" if len(worlds) > SHOWN else ""
        raise RecordingError(
            f"{path}: mixes the messages of {len(worlds)} worlds ({named}{more}): a recording is of "
            "one world (toyroom/<world>/...); record each world to its own file"
        )


def _ended(
    path: Path,
    kind: str,
    records: list[Recorded],
    offset: int,
    size: int,
    reason: str | None,
    early: bool = False,
) -> Recording:
    """The recording (of format ``kind``) read, or the error when nothing of it could be
    (``early``: reading stopped because the file ends before its end)."""
    if not records:
        what = "an MCAP recording" if kind == "mcap" else "a recording (trace.jsonl or MCAP)"
        if early:
            raise RecordingError(
                f"{path}: {what} cut off at byte {size}, before its first whole message ({reason})"
            )
        problem = f"not {what}: {reason}" if reason else "holds no messages"
        raise RecordingError(f"{path}: {problem}")
    found = _sort(records)
    if not found.records and not found.dropped:
        raise RecordingError(
            f"{path}: not a toyroom recording: none of its topics is a toyroom key "
            f"(toyroom/<world>/...): {_listed([repr(t) for t in found.foreign])}"
        )
    _one_world(path, found)
    cut = None
    if reason is not None or found.dropped:
        end = offset if reason is not None else size
        ticks = _tick_range(found.decoded)
        cut = Cut(path, end, size, reason, ticks, len(found.records), tuple(found.dropped), early)
    return Recording(path, kind, tuple(found.records), cut, tuple(found.decoded), tuple(found.foreign))


def _read_mcap(path: Path, size: int) -> Recording:
    read = read_mcap_file(path, size)
    records = [Recorded(*message) for message in read.messages]
    return _ended(path, "mcap", records, read.end, size, read.reason, read.early)


def _read_trace(path: Path, size: int) -> Recording:
    records: list[Recorded] = []
    offset, reason, cut_short = 0, None, False
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
                records.append(Recorded(key, json.dumps(payload).encode(), offset=offset))
            offset += len(raw)
    return _ended(path, "trace", records, offset, size, reason, cut_short)


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
        is_mcap = path.suffix == ".mcap" or starts_with_magic(path)
        if size == 0:
            raise RecordingError(f"{path}: an empty file, not a recording")
        return _read_mcap(path, size) if is_mcap else _read_trace(path, size)
    except OSError as err:
        raise RecordingError(f"{path}: cannot read it ({err.strerror or err})") from None
