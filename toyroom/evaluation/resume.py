"""An unfinished evaluation, resumed by running the same command again.

While an evaluation runs, its output folder holds :data:`STATE` (:class:`Unfinished`): what
its results depend on (:class:`Plan`: the arguments that change an episode's scores, and the
code's version), its scratch folder, and the seconds spent so far; each finished episode is
appended to ``episodes.jsonl`` as it comes back (with its condition's name). The file is
removed once ``metrics.json`` is written. A later evaluation into the same folder finds it:
with the same plan, it keeps the episodes already there and runs only the others (episodes
are deterministic by seed and index, and are ordered by index, so the metrics are those of
an uninterrupted run); with another, it is refused, naming what differs, unless ``--fresh``
discards the unfinished one. Arguments that change no score (``--workers``, ``--batch``,
``--backend``, ``--address``) may differ.
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import importlib.metadata
import json
import shutil
import tempfile
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import msgspec
import msgspec.structs

from bridge.errors import BridgeError
from bridge.processes import CHECKOUT
from bridge.recording.atomic import appended, write_bytes, write_text

from .conditions import Condition
from .records import EpisodeRecord

STATE = "unfinished-eval.json"
"""The file in the output folder that marks an unfinished evaluation."""
EPISODES = "episodes.jsonl"
"""Every finished episode's entry, one a line, in the order they finished."""
SOURCES = ("protocol", "bridge", "brain", "sim2d", "toyroom")
"""The packages whose files make the code's version (:func:`code_version`)."""
SOURCE_SUFFIXES = (".py", ".toml", ".json")


class IncompatibleRun(BridgeError):
    """The output folder holds an unfinished evaluation of another command or code."""


class Plan(msgspec.Struct, frozen=True, kw_only=True):
    """What an evaluation's scores depend on: an unfinished one is resumed only by the same."""

    episodes: int
    seed: int
    conditions: list[str]
    """Each condition's fields, as JSON."""
    brain_args: list[str]
    settings_file: str
    """The SHA-256 of the ``--settings`` file's bytes (``""`` without one)."""
    policies: list[str]
    record: bool
    max_ticks: int
    code: str
    """The code's version (:func:`code_version`)."""
    days: int = 1
    """A household's days (``--days``; 1: single episodes)."""


class Unfinished(msgspec.Struct, kw_only=True):
    """:data:`STATE`: the plan, the scratch folder's name in the output folder, and the wall
    and CPU seconds the evaluation's earlier sessions spent (for ``metrics.json``'s timing)."""

    plan: Plan
    workdir: str
    seconds: float = 0.0
    cpu: dict[str, float] = msgspec.field(default_factory=dict)


def code_version() -> str:
    """``toyroom VERSION, source SHA``: the package's version and a hash of the source files
    of its four packages (so an edit of a checkout counts as another version)."""
    try:
        version = importlib.metadata.version("toyroom")
    except importlib.metadata.PackageNotFoundError:
        version = "unknown"
    digest = hashlib.sha256()
    for package in SOURCES:
        for path in sorted((CHECKOUT / package).rglob("*")):
            if path.suffix in SOURCE_SUFFIXES and "__pycache__" not in path.parts and path.is_file():
                digest.update(path.relative_to(CHECKOUT).as_posix().encode() + b"\0")
                digest.update(path.read_bytes() + b"\0")
    return f"toyroom {version}, source {digest.hexdigest()[:12]}"


def plan_of(
    episodes: int,
    seed: int,
    conditions: Sequence[Condition],
    brain_args: Sequence[str],
    policies: Sequence[str],
    record: bool,
    max_ticks: int,
    days: int = 1,
) -> Plan:
    """The plan of an evaluation with these arguments, under this code."""
    settings = ""
    if "--settings" in brain_args:
        path = Path(brain_args[list(brain_args).index("--settings") + 1])
        settings = hashlib.sha256(path.read_bytes()).hexdigest() if path.is_file() else ""
    return Plan(
        episodes=episodes,
        seed=seed,
        conditions=[json.dumps(dataclasses.asdict(c), sort_keys=True) for c in conditions],
        brain_args=list(brain_args),
        settings_file=settings,
        policies=list(policies),
        record=record,
        max_ticks=max_ticks,
        code=code_version(),
        days=days,
    )


def differences(earlier: Plan, now: Plan) -> list[str]:
    """What differs between two plans, one ``NAME: EARLIER, now NOW`` each."""
    old, new = msgspec.to_builtins(earlier), msgspec.to_builtins(now)
    names = {"settings_file": "the --settings file", "code": "code", "brain_args": "brain options"}
    return [
        f"{names.get(key, '--' + key.replace('_', '-'))}: {old[key]}, now {new[key]}"
        for key in new
        if old.get(key) != new[key]
    ]


def begin(
    out: Path, plan: Plan, names: Sequence[str], fresh: bool
) -> tuple[Unfinished, dict[tuple[str, int], EpisodeRecord]]:
    """The evaluation's state in ``out`` and the episodes kept from its earlier sessions, by
    (condition name, of ``names``; index): an unfinished one of the same plan resumed, or
    (none, or ``fresh``) a new one begun (``episodes.jsonl`` emptied, a new scratch folder).

    Raises:
        IncompatibleRun: ``out`` holds an unfinished evaluation of another plan (and not
            ``fresh``), or an unreadable :data:`STATE`.
    """
    state, resumed = start(out, plan, fresh)
    return state, read_kept(out / EPISODES, names, plan.episodes) if resumed else {}


def start(out: Path, plan: Plan, fresh: bool, workdir: str | None = None) -> tuple[Unfinished, bool]:
    """The evaluation's state in ``out``, and whether it is an earlier session's resumed (its
    entries in ``episodes.jsonl`` kept), as :func:`begin` says; a new one's scratch folder is
    ``workdir`` in ``out`` (emptied first) when given, else a new ``toyroom-eval-*``.

    Raises:
        IncompatibleRun: as :func:`begin`.
    """
    path = out / STATE
    if path.exists() and not fresh:
        earlier = _read_state(path)
        changed = differences(earlier.plan, plan)
        if changed:
            raise IncompatibleRun(
                f"{out} holds an unfinished evaluation of another command or code ({'; '.join(changed)}): "
                "run with --fresh to discard its episodes, or choose another --out"
            )
        (out / earlier.workdir).mkdir(parents=True, exist_ok=True)
        return earlier, True
    if path.exists():  # --fresh: the unfinished evaluation's scratch folder goes too
        with contextlib.suppress(IncompatibleRun):
            shutil.rmtree(out / _read_state(path).workdir, ignore_errors=True)
    if workdir is None:
        workdir = Path(tempfile.mkdtemp(prefix="toyroom-eval-", dir=out)).name
    else:  # what an evaluation left there without a state (older code, a kill) is no session of this one
        shutil.rmtree(out / workdir, ignore_errors=True)
        (out / workdir).mkdir(parents=True)
    state = Unfinished(plan=plan, workdir=workdir)
    save(out, state)
    write_text(out / EPISODES, "")
    return state, False


def _read_state(path: Path) -> Unfinished:
    """:data:`STATE`.

    Raises:
        IncompatibleRun: it cannot be read."""
    try:
        return msgspec.json.decode(path.read_bytes(), type=Unfinished)
    except (OSError, msgspec.DecodeError, msgspec.ValidationError) as err:
        raise IncompatibleRun(f"{path}: unreadable ({err}): run with --fresh to start afresh") from None


def read_kept(path: Path, names: Sequence[str], episodes: int) -> dict[tuple[str, int], EpisodeRecord]:
    """The finished episodes in ``episodes.jsonl`` of the conditions ``names`` and indices
    below ``episodes``, by (condition, index) (a line cut off by a killed process, or one
    that is no episode's record, is skipped: that episode runs again)."""
    kept: dict[tuple[str, int], EpisodeRecord] = {}
    lines = path.read_bytes().splitlines() if path.exists() else []
    for line in lines:
        try:
            data = msgspec.json.decode(line, type=dict[str, Any])
            condition = data.pop("condition", None)
            entry = EpisodeRecord.from_builtins(data)
        except (msgspec.DecodeError, msgspec.ValidationError):
            continue
        if condition in names and 0 <= entry.index < episodes:
            kept[(condition, entry.index)] = entry
    return kept


def keep(path: Path, condition: str, entry: EpisodeRecord) -> None:
    """Append a finished episode's ``entry`` (of ``condition``) to ``episodes.jsonl``: its
    JSON object (:meth:`~.records.EpisodeRecord.to_builtins`) with the condition's name."""
    appended(path, json.dumps({**entry.to_builtins(), "condition": condition}) + "\n")


def save(out: Path, state: Unfinished) -> None:
    """Write :data:`STATE` into ``out`` (replaced whole: never half written)."""
    write_bytes(out / STATE, msgspec.json.encode(state))


def finished(out: Path) -> None:
    """The evaluation is complete: no longer an unfinished one."""
    (out / STATE).unlink(missing_ok=True)


class Ledger:
    """This session of an evaluation: it keeps each finished episode (:func:`keep`) and,
    with it, the state's seconds spent (earlier sessions' and this one's so far, so that an
    evaluation killed outright still counts them)."""

    def __init__(self, out: Path, state: Unfinished, cpu: Callable[[], dict[str, float]]) -> None:
        self.out, self.state, self._cpu = out, state, cpu
        self.started, self.cpu_started = time.monotonic(), cpu()
        self.count = 0
        self._lock = threading.Lock()  # a households evaluation keeps its days from its threads

    def keep(self, condition: str, entry: EpisodeRecord) -> None:
        """Append a finished episode to ``episodes.jsonl`` and save the seconds spent."""
        self.append(json.dumps({**entry.to_builtins(), "condition": condition}) + "\n")

    def append(self, line: str) -> None:
        """Append ``line`` (an entry, with its newline) to ``episodes.jsonl`` and save the
        seconds spent (from any thread)."""
        with self._lock:
            appended(self.out / EPISODES, line)
            self.count += 1
            self.save()

    def seconds(self) -> float:
        """Wall seconds of the whole evaluation (earlier sessions' and this one's)."""
        return self.state.seconds + (time.monotonic() - self.started)

    def cpu(self) -> dict[str, float]:
        """CPU seconds of the whole evaluation, by ``cpu()``'s keys."""
        now = self._cpu()
        return {k: self.state.cpu.get(k, 0.0) + (now[k] - self.cpu_started[k]) for k in self.cpu_started}

    def save(self) -> None:
        """Write the state with the seconds spent so far."""
        save(self.out, msgspec.structs.replace(self.state, seconds=self.seconds(), cpu=self.cpu()))
