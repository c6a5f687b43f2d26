"""A begun task is carried through, or dropped with its reason; its text names the right item,
place and person (on the paper scene, with finders that call for what each test says)."""

from __future__ import annotations

import uuid

import msgspec
import py_trees
import pytest
from py_trees.common import Access, Status

from brain.model.world import build_world_model
from brain.robot.behaviours import describe
from brain.robot.branches import inform_branch
from brain.robot.commands import CommandBook
from brain.robot.context import RobotContext
from brain.robot.controller import RobotBrain
from brain.robot.situation import Inform, PutBack, Situation, _believed_why, put_back_tasks, why_unneeded
from brain.settings import RobotSettings
from brain.tracking.tracker import MindTracker
from protocol import Cell, TaskEnd, TaskOutcome
from sim2d.engine import Engine

TELL = Inform(person="A1", item="ball", location="P2")


@pytest.fixture(scope="module")
def world():
    engine = Engine("paper-robot")
    scene = engine.scene()
    return scene, build_world_model(scene), engine.state()


def snapshot(world, seconds: float, a1_holds: str | None, a1_cell: tuple[int, int], **kw) -> Situation:
    """The paper scene at ``seconds``: the ball resting at P2, the skate at S1, A2's hands empty."""
    scene, model, state = world
    items = tuple(
        msgspec.structs.replace(i, location={"ball": "P2", "skate": "S1"}[i.id], held_by=None)
        for i in state.items
    )
    if a1_holds:
        items = tuple(
            msgspec.structs.replace(i, location=None, held_by="A1") if i.id == a1_holds else i for i in items
        )
    agents = tuple(
        msgspec.structs.replace(
            a, holding=a1_holds if a.id == "A1" else None, cell=Cell(*a1_cell) if a.id == "A1" else a.cell
        )
        for a in state.agents
    )
    now = msgspec.structs.replace(state, time=seconds, agents=agents, items=items)
    return Situation(scene, model, now, {}, kw.get("owners", {}), {}, kw.get("moves", {}))


def test_a_put_back_says_whose_belief_it_serves(world) -> None:
    left = snapshot(world, 0.0, None, (1, 9), owners={"ball": "A1"}, moves={"ball": ("S2", "P2", "A2")})
    assert (
        describe(PutBack("ball", "S2", "A1", why="where A1 left it"))
        == "put the ball back at S2, where A1 left it"
    )
    assert _believed_why(left, "ball", "A1", "S2") == "where A1 left it"
    placed = snapshot(world, 0.0, None, (1, 9), moves={"ball": ("S2", "P2", "A2")})
    assert _believed_why(placed, "ball", "A1", "S2") == "where A1 believes it is", (
        "the scene placed the ball: A1 never left it anywhere"
    )
    elsewhere = snapshot(world, 0.0, None, (1, 9), owners={"ball": "A1"}, moves={"ball": ("S1", "P2", "A2")})
    assert _believed_why(elsewhere, "ball", "A1", "S2") == "where A1 believes it is", (
        "A1 left the ball at S1, not at S2"
    )


def test_put_back_tasks_name_the_right_place_and_person_without_estimates(world) -> None:
    snap = snapshot(world, 0.0, None, (1, 9), owners={"ball": "A1"}, moves={"ball": ("S2", "P2", "A2")})
    assert list(put_back_tasks(snap, RobotSettings())) == [], "no estimates: no belief to serve"


def test_why_unneeded_names_what_changed(world) -> None:
    settings = RobotSettings()
    assert why_unneeded(TELL, snapshot(world, 0.0, "skate", (1, 9)), settings) == "A1 is carrying the skate"
    assert why_unneeded(TELL, snapshot(world, 0.0, "ball", (1, 9)), settings) == "A1 took the ball"
    moved = Inform(person="A1", item="ball", location="S2")
    assert why_unneeded(moved, snapshot(world, 0.0, None, (1, 9)), settings) == "the ball is no longer at S2"


def test_a_dropped_task_says_why_and_a_finished_one_is_done(world) -> None:
    calls = {"tell": True}

    def finder(snap, settings):
        if calls["tell"]:
            yield TELL

    namespace = f"/t_{uuid.uuid4().hex[:8]}"
    ctx = RobotContext(
        robot="robot", home=(7, 5), settings=RobotSettings(confirm_seconds=0.5), book=CommandBook("robot")
    )
    writer = py_trees.blackboard.Client(name="test", namespace=namespace)
    writer.register_key(key="context", access=Access.WRITE)
    writer.context = ctx
    branch = inform_branch(namespace, finder)
    branch.setup_with_descendants()
    for seconds in (0.0, 0.6):
        ctx.snapshot = snapshot(world, seconds, None, (1, 9))
        branch.tick_once()
    assert ctx.task == TELL and branch.status is Status.RUNNING, f"the robot walks to A1: {branch.status}"
    calls["tell"] = False  # A1 now holds the skate: nothing to tell them
    for seconds in (0.7, 1.0, 1.3):
        ctx.snapshot = snapshot(world, seconds, "skate", (1, 9))
        branch.tick_once()
    assert branch.status is Status.FAILURE, (
        f"expected the task dropped after confirm_seconds, got {branch.status}"
    )
    ended = ctx.ended
    assert ended is not None and ended.outcome is TaskOutcome.DROPPED, f"expected a dropped task, got {ended}"
    assert ended.detail == "tell A1 the ball is at P2", ended.detail
    assert ended.reason == "go to the person: no longer needed (A1 is carrying the skate)", ended.reason


def test_the_activity_tells_an_ended_task_once(world) -> None:
    scene, _, _ = world
    robot = RobotBrain(MindTracker(scene), "robot")
    robot.tree.context.ended = TaskEnd("inform", "tell A1 the ball is at P2", TaskOutcome.DONE)
    assert robot.activity().ended == TaskEnd("inform", "tell A1 the ball is at P2", TaskOutcome.DONE)
    assert robot.activity().ended is None, "an ended task is told at one tick only"
