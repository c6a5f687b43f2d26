"""``toyroom eval``'s episodes as Ray tasks (:mod:`.raybackend`), on one machine or a cluster.

An episode runs on whichever node Ray gives it: its engine and brain processes are started
there, over that node's loopback Zenoh, each run on a world of its own (:func:`~.runs.run_once`:
a random name, so keys of its own and, but by a rare chance, a port of its own: two worlds of
one port share its sessions' mesh, not their messages), in a scratch folder of that node,
removed after. Its scenario (and its map) comes with it by value; its entry (with the
``node`` it ran on), its node processes' logs and its recordings come back by value, and the
driver writes them where a local evaluation does: ``episodes.jsonl`` as they arrive, the logs
in ``<workdir>/<condition>/logs/`` and the recordings in ``recordings/<condition>/`` of the
output folder. Each episode solves its map's values itself (``--values-cache`` in its scratch
folder, about a second).
"""

from __future__ import annotations

import dataclasses
import tempfile
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

import msgspec.structs

from bridge.recording.atomic import write_bytes

from .episodes import EpisodeJob, run_episode
from .interrupt import NODES
from .raybackend import node_id, run_with_ray
from .records import EpisodeRecord


@dataclass(frozen=True)
class Shipped:
    """What an episode task sends back: its entry, and the files it made that a local
    evaluation keeps, by their paths relative to the output folder."""

    entry: EpisodeRecord
    files: dict[str, bytes]
    condition: str = ""
    """The name of the episode's condition."""


def scenario_files(scenario: str) -> list[str]:
    """The files of a scenario (none for ``""``): its own, then its map's when that is a file
    beside it (``map = "NAME.map.toml"``, or ``map = "NAME"`` with ``NAME.map.toml`` beside
    it, as a generated house's is; a bundled map is on every node)."""
    if not scenario:
        return []
    path = Path(scenario)
    try:
        name = tomllib.loads(path.read_text(encoding="utf-8")).get("map")
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return [scenario]  # the node's engine says what is wrong with it
    if not isinstance(name, str) or not name or Path(name).name != name:
        return [scenario]
    beside = path.parent / (name if name.endswith(".toml") else f"{name}.map.toml")
    return [scenario, str(beside)] if beside.is_file() else [scenario]


def run_shipped(job: EpisodeJob, *files: tuple[str, bytes]) -> Shipped:
    """:func:`~.episodes.run_episode` of ``job`` in a scratch folder of this node (its
    ``workdir`` as named there), from its scenario's ``files`` (:func:`scenario_files`: each
    ``(name, bytes)``, the scenario first; none: the job generates it)."""
    node = node_id()
    with tempfile.TemporaryDirectory(prefix="toyroom-episode-") as scratch:
        root = Path(scratch)
        local = dataclasses.replace(job, workdir=str(root / Path(job.workdir).name), scenario="")
        scenarios = Path(local.workdir) / job.condition.name / "scenarios"
        scenarios.mkdir(parents=True)
        for name, data in files:
            (scenarios / Path(name).name).write_bytes(data)
        if files:
            local = dataclasses.replace(local, scenario=str(scenarios / Path(files[0][0]).name))
        entry = run_episode(local)
        logs = Path(local.workdir) / job.condition.name / "logs"
        kept = [*logs.glob("*.log"), *(root / "recordings").rglob("*.mcap")]
        made = {path.relative_to(root).as_posix(): path.read_bytes() for path in sorted(kept)}
    return Shipped(msgspec.structs.replace(entry, node=node), made, job.condition.name)


def run_on_ray(
    jobs: Sequence[EpisodeJob],
    workers: int,
    done: Callable[[EpisodeJob, EpisodeRecord], None],
    address: str | None = None,
) -> None:
    """Every job run as a Ray task (:func:`run_shipped`) on the cluster at ``address``
    (default ``RAY_ADDRESS``; none: a Ray started here); as each arrives, the files it made
    written into the output folder (the workdir's parent's) and ``done(job, entry)``.

    Raises:
        EvaluationStopped: a stop signal came (:mod:`.interrupt`): the tasks left are cancelled.
    """
    if not jobs:
        return
    out = Path(jobs[0].workdir).parent
    by_key = {(job.condition.name, job.index): job for job in jobs}

    def arrived(shipped: Shipped) -> Shipped:
        NODES.check()  # what arrives with a stop signal is not kept
        write_files(out, shipped.files)
        done(by_key[(shipped.condition, shipped.entry.index)], shipped.entry)
        return Shipped(shipped.entry, {}, shipped.condition)  # the files' bytes are not kept

    run_with_ray(
        run_shipped,
        jobs,
        workers,
        address=address,
        shipped=lambda job: scenario_files(job.scenario),
        arrived=arrived,
        check=NODES.check,
    )


def write_files(out: Path, files: dict[str, bytes]) -> None:
    """Write each file under ``out`` (a name that would leave it is refused).

    Raises:
        ValueError: a name is absolute or climbs out of ``out``."""
    for name, data in files.items():
        relative = PurePosixPath(name)
        if relative.is_absolute() or ".." in relative.parts:
            raise ValueError(f"an episode task sent back a file outside the output folder: {name!r}")
        target = out.joinpath(*relative.parts)
        target.parent.mkdir(parents=True, exist_ok=True)
        write_bytes(target, data)  # whole or not at all: a full disk is an OutputError
