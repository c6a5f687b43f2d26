"""Second-order false beliefs, asserted from ``mind.csv`` of real runs (engine and brain as
processes over loopback Zenoh) against the scenarios' ground truth (``brain/groundtruth/``):
in ``sally-anne-window`` Sally watches Anne move her marble through a window, unseen, and Anne
thinks Sally thinks the basket until she sees her back; in ``paper-1`` A2 does not think A1
knows the skate went to P2 until A2 sees A1 in S2 (the first-order beliefs of ``paper-1`` are
the Section V tests')."""

from __future__ import annotations

import pytest
from support import MindCsv, toyroom_run

from brain.outputs.groundtruth import load_ground_truth
from bridge.recording.trace import trace_records
from protocol import Mind

SCENARIO = "sally-anne-window"


@pytest.fixture(scope="module", params=["sim2d", "grid"])
def mind(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> MindCsv:
    out = toyroom_run(tmp_path_factory.mktemp(request.param), SCENARIO, "--engine", request.param)
    return MindCsv(out / "mind.csv")


@pytest.fixture(scope="module", params=["sim2d", "grid"])
def paper(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> MindCsv:
    args = ("--engine", request.param, "--robot", "observe")
    return MindCsv(toyroom_run(tmp_path_factory.mktemp(request.param), "paper-1", *args) / "mind.csv")


@pytest.mark.parametrize("column", ["p_online", "p_smoothed"])
def test_the_ground_truth_holds_at_every_labelled_step(mind: MindCsv, column: str) -> None:
    assert wrong_steps(mind, SCENARIO, column, first_order=True) == []


@pytest.mark.parametrize("column", ["p_online", "p_smoothed"])
def test_paper_1_at_second_order(paper: MindCsv, column: str) -> None:
    assert wrong_steps(paper, "paper-1", column, first_order=False) == []


def wrong_steps(mind: MindCsv, scenario: str, column: str, first_order: bool) -> list[str]:
    """Each labelled step's departure from the ground truth by more than 0.2 (the nested
    beliefs, and with ``first_order`` the agent's own)."""
    truth = load_ground_truth(scenario)
    assert truth is not None and any(step.believed_by for step in truth.steps), "no nested ground truth"
    wrong = []
    for step in truth.steps:
        tick = mind.tick(truth.agent, step.label)
        for item, where in step.belief.items() if first_order else ():
            for location, p in where.items():
                got = mind.belief(truth.agent, tick, item, location, column)
                if abs(got - p) > 0.2:
                    wrong.append(f"{step.label}: {truth.agent} {item}@{location} {got:.3f}, expected {p}")
        for person, items in step.believed_by.items():
            for item, where in items.items():
                for location, p in where.items():
                    got = mind.nested(person, tick, truth.agent, item, location, column)
                    if abs(got - p) > 0.2:
                        wrong.append(
                            f"{step.label}: {person} thinks {truth.agent} thinks {item}@{location} "
                            f"{got:.3f}, expected {p}"
                        )
    return wrong


def test_nested_differs_from_first_order_while_sally_is_unseen(mind: MindCsv) -> None:
    """What separates the nested estimate from the robot's own: at `peeked` the robot knows
    Sally saw the box; Anne's model of Sally does not."""
    tick = mind.tick("sally", "peeked")
    first = mind.belief("sally", tick, "marble", "box", "p_online")
    nested = mind.nested("anne", tick, "sally", "marble", "box")
    assert first > 0.9 and nested < 0.1, f"P(sally: box) {first:.3f}, P(anne thinks sally: box) {nested:.3f}"


def test_the_mind_message_carries_the_nested_beliefs(mind: MindCsv) -> None:
    """On the wire (protocol 1.3): anne's ``nested_beliefs`` about sally, at `peeked`."""
    tick = mind.tick("sally", "peeked")
    minds = [
        m
        for _, _, m in trace_records(mind.path.parent / "trace.jsonl")
        if isinstance(m, Mind) and m.tick == tick
    ]
    assert minds, f"no mind message at tick {tick}"
    anne = next(a for a in minds[-1].agents if a.agent == "anne")
    (about_sally,) = [n for n in anne.nested_beliefs if n.agent == "sally"]
    marble = {p.id: p.p for b in about_sally.beliefs if b.item == "marble" for p in b.locations}
    assert marble["basket"] > 0.9, f"anne thinks sally thinks the marble is at {marble}, expected the basket"
