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

from bridge.errors import BridgeError
from bridge.processes import start_node, stop_nodes
from bridge.recording.events import write_events_csv
from bridge.recording.readable import TraceError
from bridge.recording.trace import trace_records
from protocol import Error as ProtocolErrorBase
from protocol import State

from .outfolder import FAILED

BRAIN_OUTPUTS = ("mind.csv", "beliefs.png", "preferences.png", "report.md")
"""What the brain writes at the end of an episode (from its estimates, or the trace's)."""


@dataclass(frozen=True)
class RunOutcome:
    """How a run ended.

    Attributes:
        status: the exit status: 0 finished, 1 failed, ``128 + N`` interrupted by signal N.
        reason: why it did not finish (empty when it did).
        infer: the engine failed while the brain was well: the brain's outputs are to be
            inferred from the trace.
        node: the node that failed (``engine`` or ``brain``) and its exit status, for the
            end of its log.
        removed: why the brain's outputs were removed though the brain finished (empty: it
            did not finish).
    """

    status: int
    reason: str = ""
    infer: bool = False
    node: tuple[str, int | None] | None = None
    removed: str = ""


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


def not_one_episode(path: Path) -> str | None:
    """What keeps ``path`` from being one episode's record, or ``None`` when its states are
    one episode's ticks 0..n, in order, each once. E.g. ``trace.jsonl is not one episode's
    ticks 0..n: it holds episode 1 ticks 0-214, then episode 2 ticks 0-621`` (an engine reset
    mid-run), or ``... episode 1 ticks 0-209, then episode 1 ticks 211-621`` (a lost tick)."""
    runs: list[list[int]] = []  # [episode, first tick, last tick] of each unbroken stretch
    try:
        for _, _, message in trace_records(path, strict=False):
            if not isinstance(message, State):
                continue
            last = runs[-1] if runs else None
            if last is not None and last[0] == message.episode and last[2] + 1 == message.tick:
                last[2] = message.tick
            else:
                runs.append([message.episode, message.tick, message.tick])
    except TraceError as err:
        return str(err)
    if len(runs) == 1 and runs[0][1] == 0:
        return None
    held = ", then ".join(f"episode {e} ticks {a}-{b}" for e, a, b in runs) or "no state"
    return f"{path.name} is not one episode's ticks 0..n: it holds {held}"


def infer_argv(folder: Path, observer: str, settings: list[str]) -> list[str]:
    """``toyroom infer``'s arguments that make the brain's outputs in ``folder`` from its
    trace (the ``settings.toml`` beside the trace is used unless ``settings`` names others)."""
    return ["infer", str(folder / "trace.jsonl"), "--out", str(folder), "--observer", observer, *settings]


def infer_from_trace(folder: Path, argv: list[str], stop: threading.Event) -> bool | None:
    """Run ``toyroom infer`` with ``argv`` (:func:`infer_argv`), its output in
    ``folder/infer.log``; whether it succeeded, or ``None`` when ``stop`` was set first
    (it is then stopped)."""
    process = start_node([sys.executable, "-m", "toyroom", *argv], folder / "infer.log", group=True)
    try:
        while process.poll() is None:
            if stop.wait(0.1):
                return None
        return process.returncode == 0
    finally:
        stop_nodes([process])


def failure_note(
    reason: str,
    folder: Path,
    span: TraceSpan | None,
    argv: list[str],
    inferred: bool | None,
    removed: str = "",
) -> str:
    """The ``FAILED`` note of a run that did not finish, whose outputs are in ``folder``.

    Args:
        reason: why it did not finish.
        folder: the run's folder, which holds its outputs.
        span: the ticks its trace holds (``None``: none).
        argv: the ``toyroom infer`` arguments that recover the brain's outputs (with the paths
            the folder will have).
        inferred: whether they were inferred here (``None``: not tried).
        removed: why they were removed though the brain finished (empty: it did not).
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
            "inferring them failed (infer.log says why)"
            if inferred is False
            else removed or "the brain did not finish"
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
