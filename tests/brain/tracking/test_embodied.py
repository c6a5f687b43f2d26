"""An embodied robot (``perception = "embodied"``) infers where an item rests from what a
person does, and sees what its own cell sees."""

from __future__ import annotations

import numpy as np
import pytest

from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Event, EventKind, Scene
from tests.scenes import corridor_scene, corridor_state


def branch_of(tracker: MindTracker, location: str) -> float:
    """The robot's probability that the ball rests at ``location``."""
    assert tracker.view is not None
    k = tracker.model.locations.index(location)
    weights = tracker.branch_weights()
    return float(weights[tracker.view.rows[:, 0] == k].sum())


def test_walking_away_from_the_door_says_the_ball_is_at_the_far_end() -> None:
    """The person sees both spots; the robot sees neither. Walking right, away from the door
    and from A, is what someone does who wants the ball and sees it at B: the branch with
    the ball at B gains, before anyone touches it."""
    tracker = MindTracker(corridor_scene(), ModelSettings(perception="embodied"))
    tracker.observe(corridor_state(0, 5), [])
    assert branch_of(tracker, "B") == pytest.approx(0.5), "at first the robot cannot tell"
    for tick, col in enumerate((6, 7), start=1):
        tracker.observe(corridor_state(tick, col), [])
    assert branch_of(tracker, "B") > 0.9, (
        f"expected the ball at B after walking right, got {branch_of(tracker, 'B')}"
    )
    estimate = tracker.online("p")
    assert estimate is not None
    b = tracker.model.locations.index("B")
    assert estimate.beliefs[0, b] > 0.9, "the person is believed to see the ball at B"
    assert estimate.preference[0] > 0.5, "and to want it"


def test_a_take_reveals_where_it_was_and_sight_settles_the_rest() -> None:
    tracker = MindTracker(corridor_scene(), ModelSettings(perception="embodied"))
    tracker.observe(corridor_state(0, 5), [])
    take = Event(episode=1, tick=1, time=0.7, kind=EventKind.TAKE, actor="p", item="ball", location="A")
    tracker.observe(corridor_state(1, 5, ball_at="A", holding=True), [take])
    assert tracker.view is not None and len(tracker.view.rows) == 1, (
        "only the branch with the ball at A is left"
    )
    assert tracker.truth == (2 * tracker.model.locations.index("A") + 1,), "carried, near A"
    tracker.observe(corridor_state(2, 8, ball_at="B"), [])  # put down at B, out of the robot's view
    assert branch_of(tracker, "B") == 1.0, "the robot saw where it was put down"
    seen = MindTracker(corridor_scene(), ModelSettings(perception="embodied"))
    seen.observe(
        corridor_state(0, 5, robot=3, ball_at="A"), []
    )  # the robot stands in the room: it sees A and B
    assert seen.view is not None and len(seen.view.rows) == 1 and branch_of(seen, "A") == 1.0
    unseen = corridor_state(3, 8, ball_at="A")  # the engine's state: the robot does not see this
    assert tracker.believed_state(unseen).items[0].location == "B", "the robot acts on what it believes"


def test_omniscient_is_one_branch_and_embodied_needs_a_robot() -> None:
    tracker = MindTracker(corridor_scene(), ModelSettings())
    tracker.observe(corridor_state(0, 5), [])
    assert tracker.view is None and np.allclose(tracker.branch_weights(), [1.0])
    scene = corridor_scene()
    no_robot = Scene(
        **{f: getattr(scene, f) for f in scene.__struct_fields__ if f != "agents"}, agents=scene.agents[:1]
    )
    with pytest.raises(ValueError, match="perception = embodied needs a robot in scene 'corridor'"):
        MindTracker(no_robot, ModelSettings(perception="embodied"))


def test_what_the_robot_sees_later_revises_a_still_persons_estimate_at_once() -> None:
    """The person looks at both spots, then stands still (no new step); when the robot then
    sees the ball at A, the person's online estimate says at once that they believe it at
    A, not the mixture over branches written at their last step (a bug until 2026-12: with
    one branch left, the stale mixture was read)."""
    tracker = MindTracker(corridor_scene(), ModelSettings(perception="embodied"))
    tracker.observe(corridor_state(0, 5, ball_at="A"), [])
    before = tracker.online("p")
    a = tracker.model.locations.index("A")
    assert before is not None and before.beliefs[0, a] == pytest.approx(0.5, abs=0.05), (
        f"expected the robot unsure where the person believes the ball, got {before.beliefs[0]}"
    )
    steps = len(tracker.tracks["p"].estimates)
    tracker.observe(corridor_state(1, 5, robot=3, ball_at="A"), [])  # the robot walks in and sees A
    assert tracker.view is not None and len(tracker.view.rows) == 1
    assert len(tracker.tracks["p"].estimates) == steps, "the person took no step"
    after = tracker.online("p")
    assert after is not None and after.beliefs[0, a] > 0.99, (
        f"expected the person believed to see the ball at A, got {after.beliefs[0]}"
    )
