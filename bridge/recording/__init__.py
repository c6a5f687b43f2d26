"""Recordings: ``trace.jsonl`` (:mod:`.trace`, written and read there alone), MCAP files
that Foxglove opens (:mod:`.mcap`), what is readable of either, whole, cut off, damaged
inside or foreign (:mod:`.readable`), replaying them (:mod:`.replay`), and ``events.csv``
read off a trace (:mod:`.events`); output files written whole or not at all (:mod:`.atomic`)."""

from .atomic import OutputError, disk_full, replacing
from .events import EventRow, event_rows, write_events_csv
from .mcap import McapRecorder, mcap_to_trace, read_mcap
from .readable import Cut, Dropped, Recorded, Recording, RecordingError, read_recording
from .trace import Trace, TraceError, TraceRecorder, episode_of, read_trace, trace_records, write_trace

__all__ = [
    "disk_full",
    "replacing",
    "episode_of",
    "event_rows",
    "mcap_to_trace",
    "read_mcap",
    "read_recording",
    "read_trace",
    "trace_records",
    "write_events_csv",
    "write_trace",
    "Cut",
    "Dropped",
    "EventRow",
    "McapRecorder",
    "OutputError",
    "Recorded",
    "Recording",
    "RecordingError",
    "Trace",
    "TraceError",
    "TraceRecorder",
]
