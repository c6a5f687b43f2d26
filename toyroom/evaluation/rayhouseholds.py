"""``toyroom eval --days N --backend ray``: each household a Ray task (:mod:`.raybackend`).

A household's chains run one after another on whichever node Ray gives it, in a scratch folder
of that node (removed after), as :func:`.households.run_household` runs them locally. Nothing is
read from or written to the driver's disk there: a household resumed from an earlier session
(:mod:`.chaindays`) gets its finished chain days and its folder's scenarios, mornings and memory
files by value, and what the task made comes back by value: its day records (with the ``node``
it ran on), its finished chain days, which the driver appends to ``episodes.jsonl`` as the
household arrives, and its folder as a finished local evaluation keeps it (pruned,
:func:`.chaindays.prune_work`), which the driver writes into ``OUT/work``. A stop signal cancels
the households still running; their chain days are not kept (they run again on resume).
"""

from __future__ import annotations

import dataclasses
import shutil
import tempfile
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import msgspec.structs

from .chaindays import ChainDay, prune_work
from .households import HouseholdJob, run_household
from .interrupt import NODES
from .raybackend import node_id, run_with_ray
from .rayepisodes import write_files
from .records import EpisodeRecord

CARRIED = ("memory/*.sqlite", "mornings/*/*.json", "scenarios/*/*.toml")
"""What a resumed household's task needs of its folder, relative to it."""


@dataclass(frozen=True)
class HouseholdTask:
    """A household to live: its job, the chain days an earlier session finished, and its
    folder's files (:data:`CARRIED`) by their paths relative to the scratch folder."""

    job: HouseholdJob
    kept: Mapping[tuple[str, int], ChainDay]
    files: Mapping[str, bytes]


@dataclass(frozen=True)
class ShippedHousehold:
    """What a household task sends back (:mod:`.rayhouseholds`)."""

    condition: str
    index: int
    records: list[EpisodeRecord]
    days: list[ChainDay]
    """The chain days this task finished."""
    files: dict[str, bytes]
    """The files it made, by their paths relative to the output folder."""


def run_shipped_household(task: HouseholdTask) -> ShippedHousehold:
    """:func:`.households.run_household` of ``task`` in a scratch folder of this node."""
    node = node_id()
    finished: list[ChainDay] = []
    with tempfile.TemporaryDirectory(prefix="toyroom-household-") as scratch:
        root = Path(scratch)
        work = root / Path(task.job.workdir).name
        write_files(work, dict(task.files))
        local = dataclasses.replace(task.job, workdir=str(work))
        records = run_household(local, task.kept, finished.append)
        shutil.rmtree(work / "values", ignore_errors=True)
        prune_work(work)
        made = {
            p.relative_to(root).as_posix(): p.read_bytes() for p in sorted(root.rglob("*")) if p.is_file()
        }
    records = [msgspec.structs.replace(record, node=node) for record in records]
    return ShippedHousehold(task.job.condition.name, task.job.index, records, finished, made)


def carried(workdir: Path, job: HouseholdJob) -> dict[str, bytes]:
    """The files of ``job``'s folder a resumed task needs (:data:`CARRIED`), by their paths
    relative to ``workdir``."""
    home = workdir / job.condition.name / f"household-{job.index}"
    paths = sorted({path for pattern in CARRIED for path in home.glob(pattern) if path.is_file()})
    return {path.relative_to(workdir).as_posix(): path.read_bytes() for path in paths}


def live_on_ray(
    jobs: Sequence[HouseholdJob],
    kept: Mapping[tuple[str, int], Mapping[tuple[str, int], ChainDay]],
    workers: int,
    address: str | None,
    keep: Callable[[ChainDay], None],
    done: Callable[[HouseholdJob, list[EpisodeRecord]], None],
) -> None:
    """Every household of ``jobs`` a Ray task (:func:`run_shipped_household`) on the cluster at
    ``address`` (default ``RAY_ADDRESS``; none: a Ray started here); as each arrives, its files
    written into the output folder (the workdir's parent), each of its chain days to ``keep``,
    and ``done(job, records)``.

    Raises:
        EvaluationStopped: a stop signal came (:mod:`.interrupt`): the tasks left are cancelled.
    """
    if not jobs:
        return
    workdir = Path(jobs[0].workdir)
    by_key = {(job.condition.name, job.index): job for job in jobs}
    tasks = []
    for job in jobs:
        earlier = dict(kept.get((job.condition.name, job.index), {}))
        tasks.append(HouseholdTask(job, earlier, carried(workdir, job) if earlier else {}))

    def arrived(shipped: ShippedHousehold) -> ShippedHousehold:
        NODES.check()  # what arrives with a stop signal is not kept
        write_files(workdir.parent, shipped.files)
        for day in shipped.days:
            keep(day)
        done(by_key[(shipped.condition, shipped.index)], shipped.records)
        return dataclasses.replace(shipped, files={}, days=[])  # the files' bytes are not kept

    run_with_ray(run_shipped_household, tasks, workers, address=address, arrived=arrived, check=NODES.check)
