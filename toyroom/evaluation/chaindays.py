"""A households evaluation (``toyroom eval --days N``) resumed, and its scratch folder kept small.

Each day a chain of a household finishes (:mod:`.households`) is one :class:`ChainDay`,
appended to ``episodes.jsonl`` as it comes back (:meth:`.resume.Ledger.append`): its scores,
seconds and failed attempts, and where its scenario and its next morning are in the scratch
folder (``OUT/work``). A later session of the same command (:mod:`.resume`: the same plan,
``--days`` included) reads them back (:func:`read_days`); each chain then goes on from the day
after its last finished one, from that day's morning and with its memory file as that day left
it (a day cut off mid-way is run again from its morning: the brain starts a day from the end of
the day before, whatever checkpoint the cut day left). Days are deterministic, so the metrics
are those of an uninterrupted run.

Once the evaluation is finished, :func:`prune_work` keeps of ``OUT/work`` what explains it and
what ``studies/household_desires.py`` reads (:data:`KEPT_IN_WORK`), the minds gzipped: about
1% of its size.
"""

from __future__ import annotations

import fnmatch
import gzip
import shutil
from collections.abc import Sequence
from pathlib import Path

import msgspec

from .records import RunScores


class ChainDay(msgspec.Struct, kw_only=True, tag="chain_day"):
    """One finished day of one chain of a household, as ``episodes.jsonl`` keeps it."""

    condition: str
    household: int
    chain: str
    day: int
    scenario: str
    """The day's scenario, relative to the scratch folder."""
    runs: dict[str, RunScores] = {}
    """The run's scores by the keys of the day's record (:meth:`.households.Chain.key`)."""
    seconds: float = 0.0
    failed_runs: list[str] = []
    """The failed attempts of the day's run, each run again."""
    morning: str | None = None
    """The next day's morning, relative to the scratch folder (``None``: the last day)."""
    error: str | None = None
    """Why the chain stopped on this day (its later days are not run)."""


Kept = dict[tuple[str, int], dict[tuple[str, int], ChainDay]]
"""Finished chain days by (condition, household), then by (chain, day)."""


def read_days(path: Path, names: Sequence[str], households: int, days: int) -> Kept:
    """The finished chain days in ``episodes.jsonl`` of the conditions ``names``, households
    below ``households`` and days up to ``days`` (a line cut off by a killed process, or one
    that is no chain day, is skipped: that day runs again)."""
    kept: Kept = {}
    lines = path.read_bytes().splitlines() if path.exists() else []
    for line in lines:
        try:
            entry = msgspec.json.decode(line, type=ChainDay)
        except (msgspec.DecodeError, msgspec.ValidationError):
            continue
        if entry.condition in names and 0 <= entry.household < households and 1 <= entry.day <= days:
            kept.setdefault((entry.condition, entry.household), {})[(entry.chain, entry.day)] = entry
    return kept


def line_of(entry: ChainDay) -> str:
    """``entry`` as a line of ``episodes.jsonl``."""
    return msgspec.json.encode(entry).decode() + "\n"


MINDS = ("minds-btom.jsonl", "minds-btom.jsonl.gz")
KEPT_IN_WORK = ("*.log", "*.toml", "*.json", "*.sqlite", *MINDS)
"""What a finished households evaluation keeps of ``OUT/work``: the node logs, each day's
scenario, the mornings, the memory files, and the BToM brain's minds of the observing chains
(``logs/observe*/``, read by ``studies/household_desires.py``), gzipped (``.jsonl.gz``)."""
OBSERVING_LOGS = "observe*"
"""The chains whose ``minds-btom.jsonl`` are kept."""


def prune_work(workdir: Path) -> None:
    """Keep of a finished households evaluation's ``workdir`` only :data:`KEPT_IN_WORK` (the
    minds gzipped; a folder pruned already stays as it is): the inputs, the baselines' minds
    and the acting chains' minds go (they are scored already), and the folders left empty."""
    if not workdir.is_dir():
        return
    for path in sorted(workdir.rglob("*"), key=lambda p: len(p.parts), reverse=True):
        if path.is_dir() and not path.is_symlink():
            if not any(path.iterdir()):
                path.rmdir()
        elif not _kept(path, workdir):
            path.unlink()
        elif path.suffix == ".jsonl":
            with path.open("rb") as source, gzip.open(f"{path}.gz", "wb") as packed:
                shutil.copyfileobj(source, packed)
            path.unlink()


def _kept(path: Path, workdir: Path) -> bool:
    """Whether ``path`` in ``workdir`` stays (:data:`KEPT_IN_WORK`)."""
    if not any(fnmatch.fnmatchcase(path.name, pattern) for pattern in KEPT_IN_WORK):
        return False
    if path.name not in MINDS:
        return True
    parts = path.relative_to(workdir).parts  # CONDITION/household-I/logs/CHAIN/RUN.shadows/minds
    return len(parts) > 3 and parts[2] == "logs" and fnmatch.fnmatchcase(parts[3], OBSERVING_LOGS)
