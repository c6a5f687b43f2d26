"""The motion heuristic on the tiny corridor: the goal is where a person heads."""

from __future__ import annotations

from protocol import ItemPlace, Truth
from tests.scenes import corridor_scene, corridor_state, tiny_scene, tiny_state
from toyroom.evaluation.heuristic import MotionHeuristic, goal_distances, heading


def truth(tick: int) -> Truth:
    return Truth(episode=1, tick=tick, agents=(), items=(ItemPlace(item="ball", location="A"),))


def test_heading_is_the_goal_that_got_nearer() -> None:
    distances = goal_distances(tiny_scene())
    assert heading(distances, (3, 0), (1, 0)) == "A", "walking left approaches A"
    assert heading(distances, (1, 0), (3, 0)) == "out", "walking right approaches the outside most"
    assert heading(distances, (2, 0), (2, 0)) is None, "standing still approaches nothing"


def test_the_heuristic_wants_what_lies_ahead_and_believes_the_truth() -> None:
    heuristic = MotionHeuristic(tiny_scene())
    minds = [
        heuristic.mind(tiny_state(t, cell, "A"), truth(t)) for t, cell in enumerate([(3, 0), (2, 0), (1, 0)])
    ]
    last = minds[-1].agents[0]
    assert {p.id: p.p for p in last.preference} == {"ball": 1.0, "out": 0.0}, last.preference
    assert {p.id: p.p for p in last.beliefs[0].locations} == {"A": 1.0, "B": 0.0}
    assert last.false_beliefs == ()
    for t, cell in enumerate([(1, 0), (2, 0), (3, 0), (4, 0)], start=3):
        turned = heuristic.mind(tiny_state(t, cell, "A"), truth(t)).agents[0]
    assert {p.id: p.p for p in turned.preference}["out"] == 1.0, "turning back towards the outside"


def test_an_embodied_heuristic_knows_only_what_the_robot_saw() -> None:
    """The robot stands outside the corridor: it never saw the ball, so the heuristic's
    belief is uniform over the spots it does not see; once the robot walks in and sees the
    ball at B, it is a point there; once the person carries it off and puts it down at A
    out of the robot's sight, it is known at A (people are tracked)."""
    heuristic = MotionHeuristic(corridor_scene(), embodied=True)
    at_b = Truth(episode=1, tick=0, agents=(), items=(ItemPlace(item="ball", location="B"),))
    first = heuristic.mind(corridor_state(0, 5), at_b).agents[0]
    assert {p.id: p.p for p in first.beliefs[0].locations} == {"A": 0.5, "B": 0.5}
    seen = heuristic.mind(corridor_state(1, 5, robot=3), at_b).agents[0]
    assert {p.id: p.p for p in seen.beliefs[0].locations} == {"A": 0.0, "B": 1.0}
    carried = Truth(episode=1, tick=2, agents=(), items=(ItemPlace(item="ball", location="B", held_by="p"),))
    heuristic.mind(corridor_state(2, 7, robot=0, holding=True), carried)
    at_a = Truth(episode=1, tick=3, agents=(), items=(ItemPlace(item="ball", location="A"),))
    dropped = heuristic.mind(corridor_state(3, 2, robot=0, ball_at="A"), at_a).agents[0]
    assert {p.id: p.p for p in dropped.beliefs[0].locations} == {"A": 1.0, "B": 0.0}
    assert (
        MotionHeuristic(corridor_scene()).mind(corridor_state(0, 5), at_b).agents[0].beliefs[0].locations[1].p
        == 1.0
    )
