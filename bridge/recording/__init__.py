"""Recordings: ``trace.jsonl`` (:mod:`.trace`, written and read there alone), MCAP files
that Foxglove opens (:mod:`.mcap`), replaying them (:mod:`.replay`), and ``events.csv``
read off a trace (:mod:`.events`)."""

from .events import EventRow, event_rows, write_events_csv
from .mcap import McapRecorder, mcap_to_trace, read_mcap
from .trace import Trace, TraceError, TraceRecorder, read_trace, trace_records

__all__ = [
    "event_rows",
    "mcap_to_trace",
    "read_mcap",
    "read_trace",
    "trace_records",
    "write_events_csv",
    "EventRow",
    "McapRecorder",
    "Trace",
    "TraceError",
    "TraceRecorder",
]
