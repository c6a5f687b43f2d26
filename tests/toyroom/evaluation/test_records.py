"""An episode's record reads back from the JSON object it is written as, unchanged: a scored
episode, a failed one, and one a Ray task ran (``node``), the keys in the order they had
before the record was typed (so an ``episodes.jsonl`` written then resumes)."""

from __future__ import annotations

import json

import msgspec
import pytest

from toyroom.evaluation.helpfulness import PersonHelp
from toyroom.evaluation.metrics import Counts
from toyroom.evaluation.records import EpisodeRecord, RunScores


def _scored() -> EpisodeRecord:
    counts = Counts(tv_sum=1.5, tv_n=3, tp=1, pref_truth={"ball": 2}, leads=[4])
    run = RunScores(
        counts=counts,
        outcome={"A1": True},
        ticks_to_goal={"A1": None},
        episode_ticks=100,
        ticks=101,
        help={"A1": PersonHelp(false_belief=True, false_belief_tick=7)},
    )
    return EpisodeRecord(
        index=2,
        map="paper",
        scenario="gen-paper-s1002",
        run_seconds={"btom-observe": 1.25},
        runs={"btom": run, "robot-tom": run},
        failed_runs=[],
        seconds=2.5,
    )


def test_a_scored_episode_keeps_its_keys_in_order() -> None:
    data = _scored().to_builtins()
    assert list(data) == [
        "index",
        "map",
        "scenario",
        "run_seconds",
        "btom",
        "robot-tom",
        "failed_runs",
        "seconds",
    ]
    assert list(data["btom"]) == [
        "counts",
        "outcome",
        "ticks_to_goal",
        "episode_ticks",
        "ticks",
        "help",
        "tasks",
    ]
    assert list(data["btom"]["counts"])[:3] == ["tv_sum", "tv_n", "pref_hits"]


@pytest.mark.parametrize(
    "record",
    [
        _scored(),
        msgspec.structs.replace(_scored(), node="abc"),
        EpisodeRecord(index=1, map="house-a", scenario="episode-1", error="RuntimeError: no"),
        EpisodeRecord(index=1, map="house-a", scenario="episode-1", error="E", failed_runs=["again"]),
    ],
)
def test_a_record_reads_back_from_its_json(record: EpisodeRecord) -> None:
    line = json.dumps(record.to_builtins())
    again = EpisodeRecord.from_builtins(json.loads(line))
    assert again == record
    assert json.dumps(again.to_builtins()) == line


def test_a_failed_episode_has_only_its_keys() -> None:
    record = EpisodeRecord(index=1, map="house-a", scenario="episode-1", error="E", failed_runs=["again"])
    assert list(record.to_builtins()) == ["index", "map", "scenario", "error", "failed_runs"]


def test_what_is_no_record_is_refused() -> None:
    with pytest.raises(msgspec.ValidationError):
        EpisodeRecord.from_builtins({"index": "one", "map": "paper", "scenario": "s"})
