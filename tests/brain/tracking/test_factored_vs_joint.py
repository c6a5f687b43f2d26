"""Issue 66, item 3: where the joint branches fit, the factored unseen world gives the same
beliefs to within a mean total-variation distance of 0.02: the robot's P(each item rests at
each location) and each person's believed locations, over every tick of an embodied episode
(the paper map, Sally-Anne, a generated ``house-a`` task episode with rich minds)."""

from __future__ import annotations

from pathlib import Path
from typing import cast

import numpy as np
import pytest

from brain.settings import ModelSettings, UnseenWorld
from brain.tracking.itemworld import ItemWorld
from brain.tracking.jointworld import JointWorld
from brain.tracking.tracker import MindTracker
from protocol import EpisodeKind, EpisodeSpec, Event, Minds, RobotMode
from sim2d.engine import Engine
from sim2d.generation import write_episode
from sim2d.scenario import load_scenario

TICKS = 200
MAX_TV = 0.02


def engine_of(name: str, directory: Path) -> Engine:
    """The bundled scenario ``name``, or ``MAP:SEED`` a generated task episode with rich minds."""
    if ":" in name:
        map_name, seed = name.split(":")
        spec = EpisodeSpec(minds=Minds.RICH, kind=EpisodeKind.TASKS)
        name = str(write_episode(directory, map_name, int(seed), spec))
        return Engine(load_scenario(name), robot=RobotMode.OBSERVE)
    return Engine(name, robot=RobotMode.OBSERVE)


def tv(a: np.ndarray, b: np.ndarray) -> float:
    """The mean over items (rows) of the total-variation distance between ``(K, L)`` beliefs."""
    return float(0.5 * np.abs(a - b).sum(axis=-1).mean())


@pytest.mark.sweep  # three scenes tracked twice over 200 ticks: about a minute of CPU
@pytest.mark.parametrize("name", ["paper-1", "sally-anne", "house-a:4"])
def test_factored_beliefs_are_within_002_of_the_joint_ones(name: str, tmp_path: Path) -> None:
    engine = engine_of(name, tmp_path)
    worlds = (UnseenWorld.JOINT, UnseenWorld.FACTORED)
    trackers = [
        MindTracker(engine.scene(), ModelSettings(perception="embodied", unseen_world=w)) for w in worlds
    ]
    joint, factored = trackers
    robot: list[float] = []
    people: dict[str, list[float]] = {p: [] for p in joint.people}
    state, events = engine.state(), cast(tuple[Event, ...], ())
    for _ in range(TICKS):
        for tracker in trackers:
            tracker.observe(state, events)
        robot.append(tv(joint.where(), factored.where()))  # type: ignore[arg-type]
        for person in joint.people:
            a, b = joint.online(person), factored.online(person)
            if a is not None and b is not None:
                people[person].append(tv(a.beliefs, b.beliefs))
        if engine.done:
            break
        out = engine.step()
        state, events = out.state, out.events
    assert isinstance(joint.world, JointWorld) and isinstance(factored.world, ItemWorld)
    means = {"robot": float(np.mean(robot))} | {p: float(np.mean(v)) for p, v in people.items() if v}
    assert all(m <= MAX_TV for m in means.values()), f"{name}: mean TV factored vs joint {means}"
