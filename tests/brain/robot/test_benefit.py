"""Each candidate's expected benefit on hand-built situations of the paper scene (rooms P1, S1,
S2, P2 in a row along row 9, the entrance below, outside at the bottom): informing beats
putting back for a person heading to the wrong room; nothing is put back for a person who saw
the move; looking beats guessing when the robot cannot rule out an unseen room; asking what a
person is looking for beats a guess at even odds, and is not done when the answer is known."""

from __future__ import annotations

import dataclasses

import msgspec
import numpy as np
import pytest

from brain.model.answers import open_answers
from brain.model.estimates import Estimate
from brain.model.world import build_world_model
from brain.robot.benefit import cell_distances, inform_worth, lasting_preference, look_or_guess
from brain.robot.choice import candidates, chosen, questions
from brain.robot.situation import AskWhat, Inform, Look, PutBack, Situation, put_back_tasks
from brain.settings import RobotSettings
from protocol import Cell
from sim2d.engine import Engine

LOCATIONS = ("P1", "S1", "S2", "P2")
BALL = 1


@pytest.fixture(scope="module")
def world():
    engine = Engine("paper-robot")
    scene = engine.scene()
    return scene, build_world_model(scene), engine.state()


def believes(place: str, p_ball: float = 0.9) -> Estimate:
    """A1 wants the ball (``p_ball``) and is sure it is at ``place``."""
    beliefs = np.zeros((2, 4))
    beliefs[:, LOCATIONS.index(place)] = 1.0
    preference = np.array([(1 - p_ball) / 2, p_ball, (1 - p_ball) / 2])
    return Estimate(beliefs, preference, (BALL, LOCATIONS.index(place), p_ball), np.zeros(2))


def snapshot(world, cells: dict[str, tuple[int, int]], ball: str, a1: Estimate, **kw) -> Situation:
    """A2 holds the skate (so only A1 may need the ball); the ball rests at ``ball``."""
    scene, model, state = world
    agents = tuple(
        msgspec.structs.replace(a, cell=Cell(*cells[a.id]), holding="skate" if a.id == "A2" else None)
        for a in state.agents
    )
    items = tuple(
        msgspec.structs.replace(i, location=ball, held_by=None)
        if i.id == "ball"
        else msgspec.structs.replace(i, location=None, held_by="A2")
        for i in state.items
    )
    now = msgspec.structs.replace(state, agents=agents, items=items)
    estimates = {"A1": a1, "A2": believes("P2", 0.05)}
    return Situation(
        scene,
        model,
        now,
        estimates,
        kw.get("owners", {}),
        {},
        kw.get("moves", {}),
        robot="robot",
        where=kw.get("where"),
    )


def best(snap: Situation, kind: type) -> float:
    """The best net worth of a candidate of ``kind`` for A1's ball (``-inf``: none)."""
    nets = [
        s.worth.net
        for s in candidates(snap, RobotSettings())
        if isinstance(s.task, kind) and s.task.item == "ball"
    ]
    return max(nets, default=-np.inf)


def test_a_person_heading_to_the_wrong_room_is_told_rather_than_the_item_carried(world) -> None:
    # A1 in P2's room believes the ball is at P1, across the house; it is at S2, on their way
    snap = snapshot(world, {"A1": (13, 9), "A2": (14, 10), "robot": (9, 8)}, "S2", believes("P1"))
    inform, put_back = best(snap, Inform), best(snap, PutBack)
    assert inform > 0, f"telling A1 should be worth doing, got net {inform:.2f} steps"
    assert inform > put_back, f"telling ({inform:.2f}) should beat carrying the ball to P1 ({put_back:.2f})"
    assert [s.task for s in chosen(snap, RobotSettings())] == [Inform("A1", "ball", "S2")]


def test_no_put_back_for_a_person_who_saw_the_move(world) -> None:
    moved = {"ball": ("P1", "S2", "A2")}
    cells = {"A1": (7, 1), "A2": (14, 10), "robot": (8, 9)}  # A1 outside, far from P1
    saw = snapshot(world, cells, "S2", believes("S2"), owners={"ball": "A1"}, moves=moved)
    assert best(saw, PutBack) == -np.inf, "A1 saw the ball go to S2: putting it back would mislead"
    assert chosen(saw, RobotSettings()) == [], "A1 knows where the ball is: nothing is worth doing"
    unseen = snapshot(world, cells, "S2", believes("P1"), owners={"ball": "A1"}, moves=moved)
    assert best(unseen, PutBack) > 0, (
        f"A1 did not see the move and the robot lands the ball at P1 first: a put-back should be "
        f"worth doing, got net {best(unseen, PutBack):.2f}"
    )


def test_looking_beats_guessing_when_an_unseen_room_cannot_be_ruled_out(world) -> None:
    # the ball is at P1 or at P2, rooms the robot (in the corridor by S1 and S2) cannot see;
    # A1, in S1's room, believes it at S2: a wrong guess sends them across the house
    where = np.zeros((2, 4))
    where[BALL, [0, 3]] = 0.5
    where[0, 1] = 1.0
    cells = {"A1": (5, 9), "A2": (14, 10), "robot": (7, 9)}
    snap = snapshot(world, cells, "P1", believes("S2"), where=where)
    look, guess = best(snap, Look), best(snap, Inform)
    assert look > 0, f"looking should be worth doing, got net {look:.2f} steps"
    assert look > guess, f"looking first ({look:.2f}) should beat telling the likelier half ({guess:.2f})"
    assert [s.task for s in chosen(snap, RobotSettings())] == [Look("ball", "P1", "A1")]


def test_inform_saves_nothing_for_someone_who_already_knows(world) -> None:
    _, model, _ = world
    person = model.cell_index[(13, 9)]
    knows = inform_worth(model, believes("S2"), BALL, person, LOCATIONS.index("S2"), 3.0, RobotSettings())
    assert knows.saved == 0.0 and knows.net < 0, f"expected nothing saved and a cost, got {knows}"
    wrong = inform_worth(model, believes("P1"), BALL, person, LOCATIONS.index("S2"), 3.0, RobotSettings())
    later = inform_worth(model, believes("P1"), BALL, person, LOCATIONS.index("S2"), 9.0, RobotSettings())
    assert wrong.saved > later.saved > 0, f"a word heard later saves less: {wrong.saved} then {later.saved}"


def test_a_certain_place_makes_looking_worthless(world) -> None:
    _, model, _ = world
    where = np.array([0.0, 0.0, 1.0, 0.0])
    person = model.cell_index[(13, 9)]
    look, guess = look_or_guess(model, believes("P1"), BALL, person, where, 3.0, 4.0, RobotSettings())
    assert guess.net > look.net, (
        f"with the place known, guessing ({guess}) is telling, and beats a look ({look})"
    )


def both_resting(world, a1: Estimate, places: dict[str, str]) -> Situation:
    """A1 on P2's side of the house, A2 far away and sure where both items rest, the robot in
    the corridor; the skate and the ball rest at ``places``."""
    scene, model, state = world
    cells = {"A1": (13, 9), "A2": (1, 1), "robot": (9, 8)}
    agents = tuple(msgspec.structs.replace(a, cell=Cell(*cells[a.id]), holding=None) for a in state.agents)
    items = tuple(msgspec.structs.replace(i, location=places[i.id], held_by=None) for i in state.items)
    now = msgspec.structs.replace(state, agents=agents, items=items)
    a2 = Estimate(
        np.eye(4)[[LOCATIONS.index(places["skate"]), LOCATIONS.index(places["ball"])]],
        np.array([0.5, 0.5, 0.0]),
        (0, 0, 0.5),
        np.zeros(2),
    )
    return Situation(scene, model, now, {"A1": a1, "A2": a2}, {}, {}, {}, robot="robot")


def undecided(skate: str, ball: str) -> Estimate:
    """A1 wants the skate or the ball, even odds, and is sure of where each is."""
    beliefs = np.zeros((2, 4))
    beliefs[0, LOCATIONS.index(skate)] = beliefs[1, LOCATIONS.index(ball)] = 1.0
    return Estimate(beliefs, np.array([0.5, 0.5, 0.0]), (BALL, LOCATIONS.index(ball), 0.5), np.zeros(2))


def test_one_tell_names_every_item_a_person_may_want_and_believes_wrongly(world) -> None:
    # A1 believes both at P1, across the house; the robot cannot say which one they are after
    snap = both_resting(world, undecided("P1", "P1"), {"skate": "S1", "ball": "S2"})
    settings = RobotSettings()
    tells = [s for s in chosen(snap, settings) if isinstance(s.task, Inform)]
    assert [(s.task.person, s.task.item, s.task.location, s.task.also) for s in tells] == [
        ("A1", "ball", "S2", (("skate", "S1"),))
    ], f"expected one tell of both items to A1, got {tells}"
    _, model, _ = world
    person = model.cell_index[(13, 9)]
    walk = float(cell_distances(model)[model.cell_index[(9, 8)], person]) - 1.0  # into earshot
    singles = [
        inform_worth(model, undecided("P1", "P1"), k, person, LOCATIONS.index(at), walk, settings)
        for k, at in ((0, "S1"), (1, "S2"))
    ]
    assert tells[0].worth.saved == pytest.approx(sum(w.saved for w in singles)), (
        f"a tell saves what each item's word would: expected the sum of {[w.saved for w in singles]}, "
        f"got {tells[0].worth}"
    )
    assert all(0 < w.saved < tells[0].worth.saved for w in singles), (
        f"each item's word saves part of the tell's {tells[0].worth.saved:.2f} steps, got {singles}"
    )
    # with an interruption worth more than either word alone, only the tell of both is worth it
    dear = RobotSettings(interruption_cost=max(w.saved for w in singles))
    tells = [s for s in chosen(snap, dear) if isinstance(s.task, Inform)]
    assert len(tells) == 1 and tells[0].task.also and tells[0].worth.net > 0, (
        f"expected the tell of both to stay worth doing at interruption cost "
        f"{dear.interruption_cost:.2f}, got {tells}"
    )


def test_an_item_the_person_knows_where_is_not_named(world) -> None:
    snap = both_resting(world, undecided("S1", "P1"), {"skate": "S1", "ball": "S2"})
    tells = [s.task for s in chosen(snap, RobotSettings()) if isinstance(s.task, Inform)]
    assert tells == [Inform("A1", "ball", "S2")] and tells[0].also == (), (
        f"A1 knows the skate is at S1: expected a tell of the ball alone, got {tells}"
    )


def ball_unseen(world, a1: Estimate, asked: dict[str, tuple[int, float]] | None = None) -> Situation:
    """A1 (in S1's room) believes both items at S2; the skate rests at S1, in the robot's
    sight, and the ball at P1 or at P2, rooms the robot (in the corridor) cannot see: a wrong
    word about the ball sends A1 across the house."""
    where = np.zeros((2, 4))
    where[0, LOCATIONS.index("S1")] = 1.0
    where[BALL, [LOCATIONS.index("P1"), LOCATIONS.index("P2")]] = 0.5
    snap = both_resting(world, a1, {"skate": "S1", "ball": "P1"})
    cells = {"A1": (5, 9), "A2": (1, 1), "robot": (7, 9)}
    agents = tuple(msgspec.structs.replace(a, cell=Cell(*cells[a.id])) for a in snap.state.agents)
    state = msgspec.structs.replace(snap.state, agents=agents)
    return dataclasses.replace(snap, state=state, where=where, asked=asked or {})


def wanting(p_ball: float, p_skate: float) -> Estimate:
    """A1 believes both items at S2 and wants the ball with ``p_ball``, the skate with
    ``p_skate`` (the rest: going out)."""
    beliefs = np.zeros((2, 4))
    beliefs[:, LOCATIONS.index("S2")] = 1.0
    preference = np.array([p_skate, p_ball, 1.0 - p_ball - p_skate])
    return Estimate(beliefs, preference, (BALL, LOCATIONS.index("S2"), p_ball), np.zeros(2))


def question_net(snap: Situation, settings: RobotSettings | None = None) -> float:
    """The net worth of asking A1 what they are looking for (``-inf``: not a candidate)."""
    nets = [s.worth.net for s in questions(snap, settings or RobotSettings()) if s.task.person == "A1"]
    return max(nets, default=-np.inf)


def test_open_answers_are_the_odds_of_each_answer_and_what_it_leaves() -> None:
    preference = np.array([0.5, 0.3, 0.2])
    odds, after = open_answers(preference, 0.9)
    assert odds.sum() == pytest.approx(1.0) and odds[0] > odds[1] > odds[2], f"odds {odds}"
    assert np.allclose(odds @ after, preference), "the answers' posteriors average back to the prior"
    assert after[0, 0] > 0.9 and after[1, 1] > 0.8, f"an answer moves the preference towards it: {after}"
    assert after[0].sum() == pytest.approx(1.0) and after[2].sum() == pytest.approx(1.0)


def test_asking_beats_a_guess_when_two_items_are_equally_likely_wanted(world) -> None:
    snap = ball_unseen(world, wanting(0.5, 0.5))
    settings = RobotSettings()
    guess = max(
        (s.worth.net for s in candidates(snap, settings) if s.task == Inform("A1", "ball", "P1")),
        default=-np.inf,
    )
    asked = question_net(snap)
    assert asked > 0, f"asking A1 what they are looking for should be worth doing, got net {asked:.2f}"
    assert asked > guess, (
        f"asking ({asked:.2f}) should beat telling A1 the ball's likelier room ({guess:.2f})"
    )
    assert AskWhat("A1") in [s.task for s in chosen(snap, settings)], "expected the question to be chosen"
    # with the odds uneven, what the answer can teach is worth less
    assert question_net(ball_unseen(world, wanting(0.8, 0.2))) < asked


@pytest.mark.parametrize("p_ball", [0.91, 0.95, 0.99])
def test_no_question_when_the_desire_is_already_known(world, p_ball: float) -> None:
    snap = ball_unseen(world, wanting(p_ball, 1.0 - p_ball))
    asked = question_net(snap)
    assert asked <= 0, f"A1 wants the ball with p = {p_ball}: asking should not pay, got net {asked:.2f}"
    assert not any(isinstance(s.task, AskWhat) for s in chosen(snap, RobotSettings()))


def test_a_person_is_not_asked_twice_within_ask_again_after(world) -> None:
    settings = RobotSettings(ask_again_after=60.0)
    now = ball_unseen(world, wanting(0.5, 0.5)).state.time
    recently = ball_unseen(world, wanting(0.5, 0.5), {"A1": (1, now - 59.0)})
    assert question_net(recently, settings) == -np.inf, "A1 was asked 59 s ago: no question yet"
    later = ball_unseen(world, wanting(0.5, 0.5), {"A1": (1, now - 61.0)})
    questions_now = [s.task for s in questions(later, settings) if s.task.person == "A1"]
    assert questions_now == [AskWhat("A1", 1)], (
        f"61 s later the robot may ask again, as its second question: got {questions_now}"
    )


def test_an_errand_out_ends_in_the_want_the_person_set_out_with() -> None:
    # out 0.9 while on an errand; before setting out they wanted the ball (items: skate, ball)
    preference = np.array([0.05, 0.05, 0.9])
    lasting = lasting_preference(preference, np.array([0.1, 0.9]))
    assert lasting == pytest.approx([0.05 + 0.09, 0.05 + 0.81, 0.0]), lasting
    even = lasting_preference(preference, None)
    assert even == pytest.approx([0.5, 0.5, 0.0]), f"no want before: the items' own shares, got {even}"


def mistaken(place: str) -> Estimate:
    """A1 wants the ball, is sure it is at ``place``, and that is a false belief."""
    est = believes(place, 0.98)
    return dataclasses.replace(est, false_belief=np.array([0.0, 1.0]))


@pytest.mark.parametrize(
    ("believed", "expected"),
    [("S2", []), ("P1", [PutBack("ball", "P1", "A1", why="where A1 left it")])],
)
def test_an_item_is_put_back_only_where_that_shortens_its_owners_way(world, believed, expected) -> None:
    """Issue 65: the robot's put-backs made people slower (seed 51, day 1: `tom` +15.6 ticks
    [2.5, 33.9] against no robot), carrying items off their owner's way and away from where
    they use them. A1, outside, left the ball at ``believed``; A2 moved it to P2, where people
    play. Believing S2, A1 would see it at P2 from there and play with it where it lies:
    carrying it back lengthens their way, so it stays. Believing P1 (at the far end), the ball
    goes back."""
    snap = snapshot(
        world,
        {"A1": (7, 1), "A2": (14, 10), "robot": (9, 8)},
        "P2",
        mistaken(believed),
        owners={"ball": "A1"},
        moves={"ball": (believed, "P2", "A2")},
    )
    settings = RobotSettings(put_back_harm=1.0)
    assert list(put_back_tasks(snap, settings)) == expected, f"A1 believing the ball at {believed}"
    net = best(snap, PutBack)
    if not expected:
        assert net <= 0, f"under `benefit` the put-back should not be worth doing, got net {net:.2f} steps"
