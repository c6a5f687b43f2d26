"""What ``toyroom eval --out DIR`` leaves in ``DIR``, and how a new evaluation meets an earlier one.

- A finished evaluation (``metrics.json``, and no ``unfinished-eval.json``): a new one into
  the same ``DIR`` is refused before anything starts, naming it (exit 2), as ``toyroom run``
  refuses a folder it would spoil, unless ``--fresh`` is given. An unfinished one is resumed
  by the same command and refused for another (:mod:`.resume`).
- ``--fresh`` first removes the earlier evaluation's outputs, finished or not: the names of
  :data:`EVAL_OUTPUTS` alone (other things in ``DIR`` stay), every scratch folder among them;
  in a ``DIR`` that holds no evaluation, nothing.
- The scratch folder (``toyroom-eval-*``) holds each run's node logs, its brain's minds and
  inputs, the generated scenarios and the planner tables. Once the evaluation is finished
  only what explains it stays (:func:`prune_scratch`): the node logs (``metrics.json`` and
  the terminal send a failed episode's reader there) and the scenarios; the minds and inputs,
  most of its size (about 2 MB per episode), go. So ``DIR`` holds at most one scratch folder,
  a small one once finished.
"""

from __future__ import annotations

import fnmatch
import json
import shutil
from pathlib import Path

from .resume import EPISODES, STATE, IncompatibleRun

SCRATCH = "toyroom-eval-*"
"""The scratch folders of the evaluations (``tempfile.mkdtemp`` names them so)."""
EVAL_OUTPUTS = (
    "metrics.json",
    "episodes.json",
    EPISODES,
    "report.md",
    "metrics-*.png",
    "days-*.png",
    "recordings",
    SCRATCH,
    "work",
    STATE,
    f"{STATE}.new",
    ".*.partial-*",
)
"""What an evaluation writes into ``DIR`` (``fnmatch`` patterns): what ``--fresh`` removes."""
KEPT_IN_SCRATCH = ("*.log", "*.toml")
"""What a finished evaluation's scratch folder keeps: the node logs and the scenarios (and
their maps)."""


def finished_evaluation(out: Path) -> str | None:
    """What the finished evaluation in ``out`` is (``6 episodes x 2 conditions``), or ``None``
    when ``out`` holds none (nothing, or an unfinished one)."""
    metrics = out / "metrics.json"
    if not metrics.is_file() or (out / STATE).exists():
        return None
    try:
        data = json.loads(metrics.read_text(encoding="utf-8"))
        count = data.get("episodes", data.get("households"))
        conditions = len(data["conditions"])
    except (OSError, ValueError, KeyError, TypeError):
        return "an evaluation (its metrics.json)"
    unit = "households" if "households" in data else "episodes"
    return f"a finished evaluation ({count} {unit} x {conditions} condition{'s' * (conditions != 1)})"


def check_out(out: Path, fresh: bool) -> None:
    """Before an evaluation into ``out`` starts: refuse a finished one there unless
    ``fresh``; with ``fresh``, remove the earlier evaluation's outputs (:func:`clear`).

    Raises:
        IncompatibleRun: ``out`` holds a finished evaluation and not ``fresh``.
    """
    if fresh:
        clear(out)
        return
    held = finished_evaluation(out)
    if held is not None:
        raise IncompatibleRun(
            f"--out {out} holds {held}: run with --fresh to replace it, or choose another --out"
        )


def _is_output(name: str) -> bool:
    return any(fnmatch.fnmatchcase(name, pattern) for pattern in EVAL_OUTPUTS)


def clear(out: Path) -> None:
    """Remove an earlier evaluation's outputs from ``out`` (:data:`EVAL_OUTPUTS`), leaving
    anything else there as it is; nothing when ``out`` holds no evaluation (a ``recordings``
    or ``work`` folder of someone else's stays)."""
    if not out.is_dir():
        return
    marks = ("metrics.json", STATE, EPISODES)
    if not (any((out / mark).is_file() for mark in marks) or any(out.glob(SCRATCH))):
        return
    for entry in sorted(out.iterdir()):
        if not _is_output(entry.name):
            continue
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry)
        else:
            entry.unlink()


def prune_scratch(workdir: Path) -> None:
    """Keep of a finished evaluation's scratch folder only its node logs and scenarios
    (:data:`KEPT_IN_SCRATCH`); the rest (the runs' minds and inputs, planner tables, solved
    values) goes, and the folders left empty with it."""
    if not workdir.is_dir():
        return
    for path in sorted(workdir.rglob("*"), key=lambda p: len(p.parts), reverse=True):
        if path.is_dir() and not path.is_symlink():
            if not any(path.iterdir()):
                path.rmdir()
        elif not any(fnmatch.fnmatchcase(path.name, pattern) for pattern in KEPT_IN_SCRATCH):
            path.unlink()
