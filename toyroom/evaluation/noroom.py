"""A full disk during ``toyroom eval``: no fault of the brain or the engine, so no run is
tried again for it and no episode is counted as failed; the evaluation stops instead, keeps
the episodes that finished (for the same command to resume) and says so in one line (exit 1).

A full disk shows either as an ``OSError`` of this process (``ENOSPC``, ``EDQUOT``, ``EFBIG``:
:func:`bridge.recording.atomic.disk_full`), or as a node that exited with the system's words
for it in its log (the brain could not write its minds).
"""

from __future__ import annotations

import os
from pathlib import Path

from bridge.recording.atomic import OutputError, disk_full, disk_full_in, output_error


def check_room(err: BaseException, logs: Path, tag: str) -> None:
    """Raise :class:`OutputError` when the failed run (or episode) ``tag`` failed for a full
    disk: its own ``err`` (or the error of a process it quotes), or a node's log in ``logs``
    saying so (``None`` otherwise: the run may be tried again)."""
    if isinstance(err, OSError) and disk_full(err):
        raise output_error(err)  # no run is to blame: none is tried again
    if (quoted := disk_full_in(str(err))) is not None:  # a process's error (generating the episodes)
        raise OutputError(OSError(quoted[0], os.strerror(quoted[0])), None, f"{tag}: {quoted[1]}") from err
    for log in sorted(logs.glob(f"{tag}.*.log")):
        try:
            found = disk_full_in(log.read_text(encoding="utf-8", errors="replace"))
        except OSError:
            continue
        if found is not None:
            code, line = found
            node = log.name.removeprefix(f"{tag}.").split(".")[0]  # engine, brain
            said = f"{tag}: the {node} found no room to write ({line}; its log: {log})"
            raise OutputError(OSError(code, os.strerror(code)), log, said) from err


def stopped_for_room(err: OutputError, kept: int, total: int, where: Path) -> OutputError:
    """``err``, saying also what the evaluation kept and how to finish it."""
    line = f"{err}; kept {kept} of {total} episodes in {where}: make room and run the same command again"
    return OutputError(err, err.path, line)
