"""Reading an MCAP file cut anywhere, and recordings that mix two worlds (issue 64,
items 12 and 13), without a process: :func:`read_recording` on files written with the
``mcap`` library as the recorder writes them (unchunked, JSON messages)."""

from __future__ import annotations

from pathlib import Path

import msgspec
import pytest
from mcap.writer import Writer
from support import golden_examples

from bridge.recording.readable import RecordingError, read_recording
from bridge.recording.trace import write_trace
from protocol import Message, State, encode


def messages_of(world: str, ticks: int = 3) -> list[tuple[str, Message]]:
    """A short recording's ``(key, message)``: the handshake, then ``ticks`` states."""
    golden = golden_examples()
    state = golden["state"]
    assert isinstance(state, State)
    states = [msgspec.structs.replace(state, tick=tick) for tick in range(ticks)]
    prefix = f"toyroom/{world}"
    return [(f"{prefix}/engine/info", golden["engine_info"])] + [
        (f"{prefix}/engine/state", s) for s in states
    ]


def write_mcap(path: Path, messages: list[tuple[str, Message]]) -> list[int]:
    """An MCAP file of ``messages`` (with a metadata record, as the recorder ends its files);
    the byte offset where each message's record ends."""
    ends = []
    with path.open("wb") as handle:
        writer = Writer(handle, use_chunking=False)
        writer.start(profile="", library="test")
        schema = writer.register_schema(name="toyroom", encoding="jsonschema", data=b"{}")
        channels: dict[str, int] = {}
        for time, (key, message) in enumerate(messages, start=1):
            if key not in channels:
                channels[key] = writer.register_channel(topic=key, message_encoding="json", schema_id=schema)
            writer.add_message(channels[key], log_time=time, data=encode(message), publish_time=time)
            ends.append(handle.tell())
        writer.add_metadata("toyroom.settings", {"toml": "[model]\nbeta = 2.0\n"})
        writer.finish()
    return ends


def cut_points(size: int, ends: list[int]) -> list[int]:
    """Where to cut a file of ``size`` bytes whose messages end at ``ends``: at every byte of
    its first 64 (the opening magic and header), of its last 256 (after the last message: the
    summary, the footer, the closing magic) and within 12 of each message's end, and at
    every 17th byte between."""
    near = {end + d for end in ends for d in range(-12, 13)}
    every = set(range(1, 64)) | set(range(size - 256, size)) | near | set(range(1, size, 17))
    return sorted(n for n in every if 0 < n < size)


def test_an_mcap_file_cut_anywhere_is_cut_off_and_keeps_its_whole_messages(tmp_path: Path) -> None:
    whole = tmp_path / "whole.mcap"
    ends = write_mcap(whole, messages_of("a"))
    data = whole.read_bytes()
    assert read_recording(whole).cut is None, "the whole file was read as not whole"
    cut = tmp_path / "cut.mcap"
    for size in cut_points(len(data), ends):
        cut.write_bytes(data[:size])
        whole_messages = sum(1 for end in ends if end <= size)
        try:
            recording = read_recording(cut)
        except RecordingError as err:
            line = f"{cut}: an MCAP recording cut off at byte {size}, before its first whole message ("
            assert whole_messages == 0 and str(err).startswith(line), (
                f"cut at byte {size} of {len(data)} ({whole_messages} whole messages): "
                f"expected {line!r}..., got {err}"
            )
            continue
        assert recording.cut is not None and recording.cut.kind == "cut off", (
            f"cut at byte {size} of {len(data)}: expected 'cut off', got {recording.cut}"
        )
        assert len(recording.records) == recording.cut.messages == whole_messages, (
            f"cut at byte {size} of {len(data)}: expected the {whole_messages} whole messages kept, "
            f"got {len(recording.records)} ({recording.cut.warning()})"
        )
        assert f"{cut}: cut off: unreadable from byte " in recording.cut.warning(), recording.cut.warning()


def test_a_file_that_is_no_mcap_is_still_not_an_mcap_recording(tmp_path: Path) -> None:
    """Bytes that do not start with the MCAP magic are no MCAP recording, however short."""
    for garbage in (b"x", b"\x89MCAQ", b"PK\x03\x04" + bytes(100)):
        path = tmp_path / "other.mcap"
        path.write_bytes(garbage)
        with pytest.raises(
            RecordingError, match="not an MCAP recording: it does not start with the MCAP magic"
        ):
            read_recording(path)


@pytest.mark.parametrize("suffix", [".mcap", ".jsonl"])
def test_a_recording_of_two_worlds_is_refused_naming_them(tmp_path: Path, suffix: str) -> None:
    first, second = messages_of("first"), messages_of("second")
    mixed = [message for pair in zip(first, second, strict=True) for message in pair]
    path = tmp_path / f"mixed{suffix}"
    if suffix == ".mcap":
        write_mcap(path, mixed)
    else:
        write_trace(mixed, path)
    with pytest.raises(RecordingError) as refused:
        read_recording(path)
    said = str(refused.value)
    assert said.startswith(f"{path}: mixes the messages of 2 worlds ('first', 'second')"), (
        f"expected the two worlds named, got {said}"
    )
    one = tmp_path / f"one{suffix}"
    if suffix == ".mcap":
        write_mcap(one, first)
    else:
        write_trace(first, one)
    assert len(read_recording(one).records) == len(first), "a recording of one world was not read whole"
