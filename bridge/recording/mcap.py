"""Recording a world to MCAP, and reading it back.

Every message on the world's keys goes into an MCAP file (the ``mcap`` package): one
channel per key and message type, its schema the message's JSON Schema (encoding
``jsonschema``), its messages JSON, so Foxglove opens the file as it is. The engine's
handshake answer is recorded first, on ``toyroom/<world>/engine/info``. Records are written
unchunked and the file is flushed at least every second, so a recorder that is killed
loses at most the last second; :func:`read_mcap` reads such a cut-off file up to where it
stops (:mod:`.readable` says where, and which ticks it kept).
"""

from __future__ import annotations

import json
import logging
import threading
import time
from collections.abc import Callable, Iterator
from pathlib import Path
from typing import IO

from mcap.records import Metadata
from mcap.stream_reader import StreamReader
from mcap.writer import Writer

from protocol import EngineInfo, Message, encode, tag_of
from protocol.schema import message_schema

from ..bridge import Bridge
from .readable import Recorded, read_recording
from .trace import Recorder, episode_of, write_trace

FLUSH_SECONDS = 0.5
log = logging.getLogger("toyroom.recording")
SETTINGS_METADATA = "toyroom.settings"
"""The MCAP metadata record that holds the brain's ``settings.toml`` (key ``toml``)."""


class McapRecorder(Recorder):
    """Writes every message of a world to an MCAP file (see the module docstring)."""

    def __init__(
        self,
        bridge: Bridge,
        path: Path,
        *,
        info: EngineInfo | None = None,
        timeout: float = 30.0,
        settings: Callable[[], str | None] | None = None,
    ) -> None:
        self.path = path
        self._settings = settings
        self._file: IO[bytes] = path.open("wb")
        self._writer = Writer(self._file, use_chunking=False)
        self._writer.start(profile="", library="toyroom")
        self._schemas: dict[str, int] = {}
        self._channels: dict[tuple[str, str], int] = {}
        self._stop = threading.Event()
        self._flusher = threading.Thread(target=self._flush_every, name="mcap flush", daemon=True)
        super().__init__(bridge, info=info, timeout=timeout)
        self._flusher.start()

    def _channel(self, key: str, message: Message) -> int:
        tag = tag_of(type(message))
        if tag not in self._schemas:
            schema = json.dumps(message_schema(type(message))).encode()
            self._schemas[tag] = self._writer.register_schema(
                name=f"toyroom.{tag}", encoding="jsonschema", data=schema
            )
        channel = self._channels.get((key, tag))
        if channel is None:
            channel = self._writer.register_channel(
                topic=key, message_encoding="json", schema_id=self._schemas[tag]
            )
            self._channels[(key, tag)] = channel
        return channel

    def _store(self, key: str, message: Message) -> None:
        now = time.time_ns()
        self._writer.add_message(
            channel_id=self._channel(key, message),
            log_time=now,
            data=encode(message),
            publish_time=now,
            sequence=self.count,
        )

    def _flush_every(self) -> None:
        while not self._stop.wait(FLUSH_SECONDS):
            with self._lock:
                if self._open and self.error is None:
                    try:
                        self._file.flush()
                    except OSError as err:
                        self._failed(err)

    def _finish(self) -> None:
        self._stop.set()
        text = self._settings() if self._settings is not None else None
        try:
            # the brain's settings, so that ``toyroom infer`` on the file reproduces its run
            if text and self.error is None:
                self._writer.add_metadata(SETTINGS_METADATA, {"toml": text})
            if self.error is None:
                self._writer.finish()
        finally:
            self._file.close()


def read_mcap(path: Path) -> Iterator[Recorded]:
    """The messages of an MCAP file in recorded order, up to where a cut-off file stops.

    Raises:
        RecordingError: the file is missing, not an MCAP file, or holds no message.
    """
    return iter(read_recording(path).records)


def mcap_to_trace(source: Path, target: Path) -> int:
    """Write (what is readable of) an MCAP recording as a ``trace.jsonl``; return the number
    of messages. A cut-off or damaged file is warned about (the byte offset, what was
    dropped and the ticks kept).

    Raises:
        RecordingError: the file is missing, not an MCAP file, not a toyroom recording, or
            holds no message.
        TraceError: naming ``source`` (never ``target``) when it holds no handshake or state.
    """
    recording = read_recording(source)
    if recording.cut is not None:
        log.warning("%s", recording.cut.warning())
    messages = list(recording.messages())
    episode_of(messages, source)  # no episode: said of the user's file, not of the trace made of it
    return write_trace(messages, target)


def recorded_settings(path: Path) -> str | None:
    """The brain settings (TOML text) recorded in an MCAP file, if any."""
    with path.open("rb") as handle:
        reader = StreamReader(handle, skip_magic=False, emit_chunks=False, validate_crcs=False)
        try:
            for record in reader.records:
                if isinstance(record, Metadata) and record.name == SETTINGS_METADATA:
                    return record.metadata.get("toml")
        except Exception:  # a file cut off mid-record: no settings were written  # noqa: BLE001
            return None
    return None
