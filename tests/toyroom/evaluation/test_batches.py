"""Episodes whose runs share their node processes (one engine, one brain per kind of run)
score exactly as each run alone does; an episode its batch did not finish is run again
alone, and says so; a batch whose engine dies ends at once; recorded runs and
planner-driven people never share."""

from __future__ import annotations

import dataclasses
import os
import signal
import threading
import time
from pathlib import Path
from typing import Any

import pytest

from toyroom.evaluation.batches import run_batch
from toyroom.evaluation.conditions import Condition
from toyroom.evaluation.episodes import EpisodeJob, batches, episode_specs, run_episode, run_episodes
from toyroom.evaluation.generation import generate_all
from toyroom.evaluation.records import EpisodeRecord

SEED, TICKS = 7, 80
TIMING = ("seconds", "run_seconds", "failed_runs")


def _jobs(tmp_path: Path, episodes: int) -> list[EpisodeJob]:
    condition = Condition()
    paths = generate_all(tmp_path / condition.name / "scenarios", episodes, SEED, condition.spec(TICKS))
    return [
        EpisodeJob(i, SEED, str(tmp_path), condition, max_ticks=TICKS, scenario=str(path))
        for i, path in enumerate(paths)
    ]


def _scores(entry: EpisodeRecord) -> dict[str, Any]:
    return {k: v for k, v in entry.to_builtins().items() if k not in TIMING}


@pytest.mark.sweep  # an evaluation batched and one a process pair a run: a minute (make test's budget)
def test_batched_episodes_score_as_each_alone(tmp_path: Path) -> None:
    jobs = _jobs(tmp_path, 3)
    together = run_episodes(jobs)
    alone = [run_episode(job) for job in jobs]
    assert [e.error for e in together] == [None] * 3, together
    assert [e.failed_runs for e in together] == [[], [], []], "no run failed, none ran twice"
    for shared, single in zip(together, alone, strict=True):
        assert _scores(shared) == _scores(single), (
            f"episode {single.index}: alone {_scores(single)}, in a batch {_scores(shared)}"
        )
    assert set(together[0].run_seconds or {}) == {"btom-observe", "btom-act-tom"}, together[0].run_seconds


def test_an_episode_its_batch_did_not_finish_runs_alone(tmp_path: Path) -> None:
    """The second scenario is broken: the batch's brains stop there; the first episode is
    scored from the batch, the second fails alone too, the third runs alone and says why."""
    jobs = _jobs(tmp_path, 3)
    Path(jobs[1].scenario).write_text('name = "broken"\nmap = 42\n')
    first, broken, third = run_episodes(jobs)
    assert first.failed_runs == [] and first.error is None, first
    assert "the engine failed" in (broken.error or ""), f"expected the engine's failure, got {broken}"
    logs = "".join(p.read_text() for p in tmp_path.rglob("batch-*.brain.log"))
    assert "map: expected a map name, got 42" in logs, f"the brain's log names what is wrong: {logs}"
    assert third.error is None, third
    assert third.failed_runs == ["episode 2: its batch did not finish it"], third.failed_runs
    assert _scores(third) == _scores(run_episode(jobs[2])), "run again alone, it scores as alone"


@pytest.mark.parametrize(
    ("episodes", "workers", "size", "expected"),
    [(8, 2, 10, [4, 4]), (25, 2, 10, [10, 10, 5]), (3, 2, 10, [2, 1]), (4, 1, 1, [1, 1, 1, 1])],
)
def test_batches_keep_every_worker_busy(episodes: int, workers: int, size: int, expected: list[int]) -> None:
    jobs = [EpisodeJob(i, SEED, "w") for i in range(episodes)]
    chunks = batches(jobs, workers, size)
    assert [len(c) for c in chunks] == expected, [len(c) for c in chunks]
    assert [job for c in chunks for job in c] == jobs, "every job once, in order"


def test_recorded_or_planned_episodes_never_share() -> None:
    recorded = [EpisodeJob(i, SEED, "w", record=True) for i in range(4)]
    assert [len(c) for c in batches(recorded, 2, 10)] == [1, 1, 1, 1]
    planned = [EpisodeJob(i, SEED, "w", Condition(minds="model")) for i in range(2)]
    plain = [dataclasses.replace(job, condition=Condition(), index=i) for i, job in enumerate(planned * 2)]
    assert [len(c) for c in batches([*planned, *plain], 2, 10)] == [1, 1, 2, 2]


def _engine_child() -> int | None:
    """The pid of this process's sim2d child, if one runs."""
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
            command = (entry / "cmdline").read_bytes()
        except OSError:
            continue
        if int(stat[stat.rindex(")") + 2 :].split()[1]) == os.getpid() and b"sim2d" in command:
            return int(entry.name)
    return None


def test_a_batch_whose_engine_dies_ends_at_once(tmp_path: Path) -> None:
    """The engine is killed while the first brain runs: the batch ends at once, starting no
    brain against a dead engine (and stopping one that waits for it to come back), with no
    episode finished."""
    jobs = _jobs(tmp_path, 2)
    specs = [episode_specs(job)[1] for job in jobs]
    logs = tmp_path / "logs"
    logs.mkdir()

    def kill_when_running() -> None:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline:
            pid = _engine_child()
            if pid is not None and any(logs.rglob("inputs.jsonl")):
                os.kill(pid, signal.SIGKILL)
                return
            time.sleep(0.05)

    killer = threading.Thread(target=kill_when_running, daemon=True)
    killer.start()
    started = time.monotonic()
    result = run_batch(specs, logs)
    took = time.monotonic() - started
    killer.join(timeout=1)
    assert result.scores == [None, None], f"no episode can be finished without its engine: {result}"
    assert took < 60, f"the batch waited {took:.0f} s for an engine that was gone"
    started_brains = sorted(p.name for p in logs.glob("*.brain.log"))
    assert len(started_brains) == 1, f"expected only the first kind's brain, got {started_brains}"
