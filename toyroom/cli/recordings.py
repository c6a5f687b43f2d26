"""How the commands that take a recording, ``toyroom infer`` and ``toyroom replay``
(:mod:`.commands.infer`, :mod:`.commands.replay`), read it: first, under the one policy of
:mod:`bridge.recording.readable`, and only then write or publish anything. A missing file, or
one that is no recording, is one line naming it and the problem (exit 2), with nothing written;
a cut-off or damaged one is used as far as it can be read, with a warning naming the byte offset
where it broke and the ticks kept, and refused with ``--strict`` in one line (exit 1): a file
whose end is missing (its footer or closing MCAP magic) is cut off, even when every message in
it is whole. A file that mixes two worlds is no recording (exit 2)."""

from __future__ import annotations

import sys
from pathlib import Path

from bridge.recording.readable import Recording, read_recording


def checked(path: Path, command: str, strict: bool) -> Recording | None:
    """The readable part of the recording at ``path``, after a warning when it is cut off or
    damaged; ``None`` when it is and ``strict`` refuses it (one line on stderr, either way).

    Raises:
        RecordingError: the file is missing, of neither format, holds no message, or mixes
            two worlds.
    """
    recording = read_recording(path)
    if recording.cut is None:
        return recording
    if strict:
        line = f"refused: {recording.cut.warning()} (--strict refuses a recording that is not whole)"
        print(f"toyroom {command}: {line}", file=sys.stderr, flush=True)
        return None
    print(f"toyroom {command}: warning: {recording.cut.warning()}", file=sys.stderr, flush=True)
    return recording
