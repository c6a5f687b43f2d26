"""The robot's hysteresis (``RobotSettings.confirm_seconds``), on the paper scene with a
finder that calls for what each test says."""

from __future__ import annotations

import msgspec
import pytest

from brain.model.world import build_world_model
from brain.robot.commands import CommandBook
from brain.robot.context import RobotContext
from brain.robot.situation import Inform, Situation, Task
from brain.settings import RobotSettings
from protocol import Cell
from sim2d.engine import Engine

TELL = Inform(person="A1", item="ball", location="P2")


@pytest.fixture(scope="module")
def world():
    engine = Engine("paper-robot")
    scene = engine.scene()
    return scene, build_world_model(scene), engine.state()


def context(confirm: float) -> RobotContext:
    return RobotContext(
        robot="robot", home=(7, 5), settings=RobotSettings(confirm_seconds=confirm), book=CommandBook("robot")
    )


def at(
    world, ctx: RobotContext, seconds: float, holding: str | None = None, **cells: tuple[int, int]
) -> None:
    """The context's snapshot at engine time ``seconds`` (the robot holding ``holding``;
    agents moved to ``cells``)."""
    scene, model, state = world
    agents = tuple(
        msgspec.structs.replace(
            a,
            holding=holding if a.id == "robot" else a.holding,
            cell=Cell(*cells[a.id]) if a.id in cells else a.cell,
        )
        for a in state.agents
    )
    now = msgspec.structs.replace(state, time=seconds, agents=agents)
    ctx.snapshot = Situation(scene, model, now, {}, {}, {})


def calling(*tasks: Task):
    def finder(snap, settings):
        yield from tasks

    return finder


def test_a_task_starts_only_once_called_for_confirm_seconds_in_a_row(world) -> None:
    ctx = context(confirm=0.5)
    finder = calling(TELL)
    for seconds, young in ((0.0, True), (0.3, True), (0.5, False)):
        at(world, ctx, seconds)
        assert (ctx.ready("inform", finder) is None) is young, f"at {seconds} s"
    at(world, ctx, 0.6)
    ctx.ready("inform", calling())  # a tick without it: the count starts again
    at(world, ctx, 0.7)
    assert ctx.ready("inform", finder) is None, "a gap restarts the wait"


def test_no_hysteresis_when_confirm_seconds_is_zero(world) -> None:
    ctx = context(confirm=0.0)
    at(world, ctx, 0.0)
    assert ctx.ready("inform", calling(TELL)) == TELL


def test_a_task_is_given_up_only_after_confirm_seconds_without_it(world) -> None:
    ctx = context(confirm=0.5)
    ctx.task, ctx.finder = TELL, calling(TELL)
    at(world, ctx, 1.0)
    assert not ctx.give_up()
    ctx.finder = calling()  # no longer called for
    for seconds, gone in ((1.1, False), (1.4, False), (1.6, True)):
        at(world, ctx, seconds)
        assert ctx.give_up() is gone, f"at {seconds} s"
