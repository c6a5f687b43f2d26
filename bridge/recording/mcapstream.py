"""An MCAP file read record by record, as far as it can be: the messages whole in it, and
where and why reading stopped.

A finished MCAP file starts and ends with :data:`MCAP_MAGIC`, its footer just before the
closing one. A file that ends before that (inside the opening magic, mid-record, without a
footer, inside the summary or footer, inside the closing magic) is cut off; a record that
cannot be read with the file's end whole after it is damage. Either way every message
before it is kept; :mod:`.readable` says what of them is a toyroom recording.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import IO

from mcap.exceptions import EndOfFile, InvalidMagic, McapError, RecordLengthLimitExceeded
from mcap.records import Channel, DataEnd, Footer
from mcap.records import Message as McapMessage
from mcap.stream_reader import StreamReader

MCAP_MAGIC = b"\x89MCAP0\r\n"
"""The eight bytes every MCAP file starts (and a finished one ends) with."""
NO_MAGIC = "it does not start with the MCAP magic bytes"


def starts_with_magic(path: Path) -> bool:
    """Whether the file starts with the MCAP magic, or is a file cut off inside it."""
    with path.open("rb") as handle:
        head = handle.read(len(MCAP_MAGIC))
    return bool(head) and MCAP_MAGIC.startswith(head)


def _ends_with_magic(path: Path, size: int) -> bool:
    """Whether the file (``size`` bytes) ends with the MCAP magic, as a finished one does."""
    if size < 2 * len(MCAP_MAGIC):
        return False
    with path.open("rb") as handle:
        handle.seek(size - len(MCAP_MAGIC))
        return handle.read() == MCAP_MAGIC


class _Counting:
    """A binary file that counts the bytes read from it (the MCAP reader's position), and
    raises :class:`EndOfFile` when it ends inside a read (the file is cut off there)."""

    def __init__(self, handle: IO[bytes]) -> None:
        self.handle = handle
        self.count = 0

    def read(self, size: int = -1) -> bytes:
        data = self.handle.read(size)
        self.count += len(data)
        if 0 < size and len(data) < size:
            raise EndOfFile()
        return data


@dataclass
class McapRead:
    """What was read of an MCAP file.

    Attributes:
        messages: ``(topic, data, log time in ns, byte offset of its record)`` of every whole
            message on a declared channel, in file order.
        end: the byte offset just past the last whole record (past the closing magic when
            the file was read to its end).
        reason: why reading stopped before the end (``None``: it did not).
        early: whether it stopped because the file is cut off (rather than damaged).
    """

    messages: list[tuple[str, bytes, int, int]] = field(default_factory=list)
    end: int = len(MCAP_MAGIC)
    reason: str | None = None
    early: bool = False
    data_ended: bool = False
    """Whether the data section's end (``DataEnd``: every message is before it) was read."""
    footer: bool = False

    def ran_out(self, path: Path, size: int, count: int) -> None:
        """Say why a read (or a record's length) ran past the end of the file at ``path``
        (``size`` bytes) after ``count`` bytes: it is cut off, unless it is no MCAP file at
        all or its end is whole (then the record is damage)."""
        if count < len(MCAP_MAGIC) and not starts_with_magic(path):
            self.reason = NO_MAGIC  # a few bytes of something else
        elif self.footer or not _ends_with_magic(path, size):
            self.early, self.reason = True, self._cut_reason(count)
        else:
            self.reason = "a damaged record: it runs past the end of the file, whose end is whole"

    def _cut_reason(self, count: int) -> str:
        """Why a file that ends at byte ``count``, inside a read, is cut off."""
        if count < len(MCAP_MAGIC):
            return "it ends inside the MCAP magic bytes it starts with"
        if self.footer:
            return "it ends inside the MCAP magic bytes that close it, after the footer"
        if self.data_ended:
            return "it ends after its last message, inside the summary and footer that close it"
        if count == self.end:
            return "it ends without the MCAP footer: the recorder did not finish the file"
        return "it ends mid-record"


def _records(read: McapRead, counting: _Counting, size: int) -> None:
    """Read records into ``read`` until the closing magic (or an exception)."""
    channels: dict[int, Channel] = {}
    reader = StreamReader(
        counting,  # type: ignore[arg-type]
        skip_magic=False,
        emit_chunks=False,
        validate_crcs=False,
        record_size_limit=size,
    )
    for record in reader.records:
        start, read.end = read.end, counting.count
        if isinstance(record, Channel):
            channels[record.id] = record
        elif isinstance(record, McapMessage) and record.channel_id in channels:
            topic = channels[record.channel_id].topic
            read.messages.append((topic, bytes(record.data), record.log_time, start))
        read.data_ended |= isinstance(record, DataEnd)
        read.footer |= isinstance(record, Footer)
    read.end = counting.count  # the closing magic, read


def read_mcap_file(path: Path, size: int) -> McapRead:
    """Every whole message of the MCAP file at ``path`` (``size`` bytes), up to where it
    stops being readable (see the module docstring).

    Raises:
        OSError: the file cannot be read.
    """
    read = McapRead()
    with path.open("rb") as handle:
        counting = _Counting(handle)
        try:
            _records(read, counting, size)
        except (EndOfFile, RecordLengthLimitExceeded):
            read.ran_out(path, size, counting.count)
        except InvalidMagic:
            read.reason = "the MCAP magic bytes that close it are wrong" if read.footer else NO_MAGIC
        except (McapError, ValueError, UnicodeDecodeError, OverflowError, MemoryError) as err:
            read.reason = f"a damaged record ({type(err).__name__}: {err})"
    return read
