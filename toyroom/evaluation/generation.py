"""The episodes of an evaluation: random scenarios (``python -m sim2d generate``) on the paper
map and two generated houses, written by one generator process per condition (a process
start is most of an episode's generation)."""

from __future__ import annotations

import logging
import subprocess
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from protocol import DEFAULT_EPISODE, EpisodeKind, EpisodeSpec
from protocol import MAPS as MAPS

from .conditions import Condition
from .interrupt import NODES

log = logging.getLogger("toyroom.eval")


def map_of(index: int) -> str:
    """The map episode ``index`` of a sweep is drawn on (they cycle through :data:`protocol.MAPS`)."""
    return MAPS[index % len(MAPS)]


def generate(directory: Path, index: int, seed: int, spec: EpisodeSpec = DEFAULT_EPISODE) -> Path:
    """Write episode ``index`` of a sweep with ``seed`` (on the map :func:`map_of` says),
    drawn as ``spec`` says (``spec.autonomy``: the generator's ``--autonomy``)."""
    return _generate(directory, [index], seed, spec)[0]


def generate_all(
    directory: Path, episodes: int, seed: int, spec: EpisodeSpec = DEFAULT_EPISODE
) -> list[Path]:
    """Write episodes ``0 .. episodes - 1`` of a sweep, as :func:`generate` does each, in one
    process (a process start is most of an episode's generation)."""
    return _generate(directory, range(episodes), seed, spec)


def generate_day(
    directory: Path,
    index: int,
    seed: int,
    spec: EpisodeSpec,
    day: int,
    morning: Path | None = None,
) -> Path:
    """Day ``day`` of the household of episode ``index`` of a sweep with ``seed``, drawn as
    ``spec`` says (``morning``: a JSON :class:`protocol.Morning` of the day before's end, for
    every day after the first; :mod:`sim2d.generation.households`)."""
    days = ["--day", str(day), *(["--morning", str(morning)] if morning is not None else [])]
    return _generate(directory, [index], seed, spec, days)[0]


def _generate(
    directory: Path, indices: Sequence[int], seed: int, spec: EpisodeSpec, more: Sequence[str] = ()
) -> list[Path]:
    """Episodes ``indices`` of a sweep, written by one ``python -m sim2d generate`` process
    (``more``: more of its options)."""
    if not indices:
        return []
    entries = [f"{map_of(i)}:{seed * 1000 + i}" for i in indices]
    drawn = ["--max-ticks", str(spec.max_ticks), "--minds", spec.minds, "--kind", spec.kind]
    result = NODES.run(
        [sys.executable, "-m", "sim2d", "generate", "--episodes", *entries, *drawn, "--out", str(directory)]
        + (["--tasks", ",".join(spec.tasks)] if spec.tasks and spec.kind == EpisodeKind.TASKS else [])
        + [arg for setting in spec.autonomy for arg in ("--autonomy", setting)]
        + list(more),
        timeout=120 + 10 * len(indices),
    )
    paths = [Path(line) for line in result.stdout.splitlines() if line.strip()]
    if result.returncode != 0 or len(paths) != len(indices):
        which = f"episode {indices[0]}" if len(indices) == 1 else f"{len(indices)} episodes"
        raise RuntimeError(f"generating {which}: {result.stderr.strip()}")
    return paths


def check_autonomy(autonomy: Sequence[str]) -> None:
    """Raise ``ValueError`` with the generator's words when ``autonomy`` (``NAME=VALUE``
    settings of the people's ``[autonomy]`` table) would not make valid episodes: checked by
    writing one throwaway episode with them, before an evaluation starts any run."""
    if not autonomy:
        return
    with tempfile.TemporaryDirectory(prefix="toyroom-autonomy-") as directory:
        try:
            _generate(Path(directory), [0], 0, EpisodeSpec(max_ticks=10, autonomy=tuple(autonomy)))
        except RuntimeError as err:
            reason = str(err).strip().splitlines()[-1].split("error: ", 1)[-1]
            raise ValueError(f"--autonomy: {reason.split('.toml: ', 1)[-1]}") from None


def scenarios_of(workdir: Path, episodes: int, seed: int, condition: Condition, max_ticks: int) -> list[str]:
    """The condition's episodes, generated in one process into its ``scenarios`` folder; where
    that fails, empty names (each job then generates its own, and fails alone)."""
    directory = workdir / condition.name / "scenarios"
    try:
        paths = generate_all(directory, episodes, seed, condition.spec(max_ticks))
    except (RuntimeError, OSError, subprocess.SubprocessError) as err:
        log.warning("%s; each episode is generated on its own", err)
        return [""] * episodes
    return [str(path) for path in paths]
