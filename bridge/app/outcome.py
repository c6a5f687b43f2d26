"""How a ``toyroom run`` ended, and what a run that did not finish leaves behind: the span of
its ``trace.jsonl``, the brain's outputs inferred from it when the engine failed, and the
``FAILED`` note that says why and which ``toyroom infer`` command recovers the rest."""

from __future__ import annotations

import json
import shlex
import signal
import sys
import threading
from dataclasses import dataclass
from pathlib import Path

from protocol import Error as ProtocolErrorBase

from ..errors import BridgeError
from ..processes import start_node, stop_nodes
from ..recording.events import write_events_csv
from .outfolder import FAILED

BRAIN_OUTPUTS = ("mind.csv", "beliefs.png", "preferences.png", "report.md")
"""What the brain writes at the end of an episode (from its estimates, or the trace's)."""


@dataclass(frozen=True)
class Outcome:
    """How a run ended.

    Attributes:
        status: the exit status: 0 finished, 1 failed, ``128 + N`` interrupted by signal N.
        reason: why it did not finish (empty when it did).
        infer: the engine failed while the brain was well: the brain's outputs are to be
            inferred from the trace.
        node: the node that failed (``engine`` or ``brain``) and its exit status, for the
            end of its log.
    """

    status: int
    reason: str = ""
    infer: bool = False
    node: tuple[str, int | None] | None = None


def exit_text(status: int | None) -> str:
    """``exited with status 3``, or ``was killed by SIGKILL`` for a negative status."""
    if status is not None and status < 0:
        try:
            return f"was killed by {signal.Signals(-status).name}"
        except ValueError:
            return f"was killed by signal {-status}"
    return f"exited with status {status}"


@dataclass(frozen=True)
class TraceSpan:
    """The ticks of the engine states in a trace."""

    first: int
    last: int

    def text(self) -> str:
        return f"ticks {self.first}-{self.last}"


def trace_span(path: Path) -> TraceSpan | None:
    """The ticks of ``path``'s states, or ``None`` when it holds no state (or is missing)."""
    ticks: list[int] = []
    try:
        with path.open(encoding="utf-8") as handle:
            for line in handle:
                try:
                    record = json.loads(line)
                except ValueError:
                    continue
                if str(record.get("key", "")).endswith("/state") and isinstance(record.get("tick"), int):
                    ticks.append(record["tick"])
    except OSError:
        return None
    return TraceSpan(min(ticks), max(ticks)) if ticks else None


def infer_argv(folder: Path, observer: str, settings: list[str]) -> list[str]:
    """``toyroom infer``'s arguments that make the brain's outputs in ``folder`` from its
    trace (the ``settings.toml`` beside the trace is used unless ``settings`` names others)."""
    return ["infer", str(folder / "trace.jsonl"), "--out", str(folder), "--observer", observer, *settings]


def infer_from_trace(folder: Path, argv: list[str], stop: threading.Event) -> bool | None:
    """Run ``toyroom infer`` with ``argv`` (:func:`infer_argv`), its output in
    ``folder/infer.log``; whether it succeeded, or ``None`` when ``stop`` was set first
    (it is then stopped)."""
    process = start_node([sys.executable, "-m", "bridge", *argv], folder / "infer.log", group=True)
    try:
        while process.poll() is None:
            if stop.wait(0.1):
                return None
        return process.returncode == 0
    finally:
        stop_nodes([process])


def failure_note(
    reason: str, folder: Path, span: TraceSpan | None, argv: list[str], inferred: bool | None
) -> str:
    """The ``FAILED`` note of a run that did not finish, whose outputs are in ``folder``.

    Args:
        reason: why it did not finish.
        span: the ticks its trace holds (``None``: none).
        argv: the ``toyroom infer`` arguments that recover the brain's outputs (with the paths
            the folder will have).
        inferred: whether they were inferred here (``None``: not tried).
    """
    kept = sorted(p.name + ("/" if p.is_dir() else "") for p in folder.iterdir() if p.name != FAILED)
    command = shlex.join(["toyroom", *argv])
    lines = [f"toyroom run did not finish: {reason}.", "", f"Here: {', '.join(kept) or 'nothing'}."]
    if span is None:
        lines.append(
            "No state of the episode was recorded, so there is nothing to infer from; the logs say why."
        )
    elif inferred:
        lines += [
            f"trace.jsonl holds {span.text()}; {', '.join(BRAIN_OUTPUTS)} were inferred from it with",
            f"  {command}",
        ]
    else:
        why = (
            "inferring them failed (infer.log says why)" if inferred is False else "the brain did not finish"
        )
        lines += [
            f"trace.jsonl holds {span.text()}; {', '.join(BRAIN_OUTPUTS)} are not here ({why}).",
            "Recover them from the trace with",
            f"  {command}",
        ]
    return "\n".join(lines) + "\n"


def running_note(pid: int, argv: list[str]) -> str:
    """The ``FAILED`` note a run's folder holds while the run is on: it stays if the run is
    killed before it can write why (SIGKILL, a crash, the machine stopped)."""
    return (
        f"toyroom run (process {pid}) has not finished: it is still running, or it was killed\n"
        "before it could say why (SIGKILL, a crash, the machine stopped).\n"
        "Recover mind.csv, the figures and report.md from what was recorded with\n"
        f"  {shlex.join(['toyroom', *argv])}\n"
    )


def discard_brain_outputs(folder: Path) -> None:
    """Remove the brain's outputs: a brain stopped before it exited may have left them half
    written."""
    for name in BRAIN_OUTPUTS:
        (folder / name).unlink(missing_ok=True)


def events_csv(folder: Path) -> int | None:
    """Write ``folder/events.csv`` from its trace; the number of rows, or ``None`` when the
    trace cannot be read (missing, or no handshake)."""
    try:
        return write_events_csv(folder / "trace.jsonl", folder / "events.csv")
    except (BridgeError, ProtocolErrorBase, OSError, ValueError):
        (folder / "events.csv").unlink(missing_ok=True)
        return None
