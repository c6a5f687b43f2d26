"""The ``benefit`` robot asks in a real run (sim2d and the brain as processes over loopback
Zenoh): on a generated task episode of the paper house with rich minds and an embodied robot
(``gen-paper-s7003`` of ``toyroom eval --seed 7 --kind tasks --minds rich``), it cannot tell
what either person wants at the start, asks each what they are looking for, and each answers
(sim2d's people answer truthfully when free), and asks each of them once."""

from __future__ import annotations

import csv
from pathlib import Path

from protocol import EpisodeKind, EpisodeSpec, Minds
from sim2d.generation.episodes import write_episode
from tests.support import toyroom_run

TASKS = ["moved", "hidden", "contested", "seen", "told", "overlooked", "stale"]


def test_the_benefit_robot_asks_each_person_and_hears_their_answer(tmp_path: Path) -> None:
    scenario = write_episode(
        tmp_path / "episode", "paper", 7003, EpisodeSpec(Minds.RICH, EpisodeKind.TASKS, 1000, TASKS)
    )
    out = toyroom_run(
        tmp_path / "run", str(scenario), "--set", "policy=benefit", "--set", "perception=embodied"
    )
    with (out / "events.csv").open(encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    asks = [(int(r["tick"]), r["target"]) for r in rows if r["kind"] == "ask" and r["actor"] == "robot"]
    answers = {r["actor"]: r for r in rows if r["kind"] == "answer"}
    assert sorted(t for _, t in asks) == ["A1", "A2"], f"expected one question to each person, got {asks}"
    for tick, person in asks:
        answer = answers.get(person)
        assert answer is not None and answer["target"] == "robot" and int(answer["tick"]) > tick, (
            f"{person} was asked at tick {tick} and should have answered the robot, got {answer}"
        )
        assert answer["item"], f"{person} wants an item in this episode and should have named it: {answer}"
