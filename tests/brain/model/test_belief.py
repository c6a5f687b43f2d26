"""The belief update on hand-built cases: visibility, unseen moves, speech, and the roles of
r and delta."""

from __future__ import annotations

import numpy as np
from scenes import tiny_scene

from brain.model.belief import NOT_IN_VIEW, BeliefModel, percept, told
from brain.model.world import build_world_model

MODEL = build_world_model(tiny_scene())
A, B = 0, 1  # location indices
REST_A, HELD_A, REST_B, HELD_B = 0, 1, 2, 3  # item values 2 * location + held
ROOM, DOOR, OUT = MODEL.cell_index[(1, 0)], MODEL.cell_index[(3, 0)], MODEL.cell_index[(4, 0)]


def test_percepts_follow_visibility() -> None:
    assert percept(MODEL, ROOM, (REST_B,), None).seen == (REST_B,)
    assert percept(MODEL, OUT, (REST_B,), None).seen == (NOT_IN_VIEW,), "nothing is visible from outside"
    assert percept(MODEL, DOOR, (REST_A,), None).seen == (REST_A,), "the door sees the room"
    carried = percept(MODEL, OUT, (REST_B,), 0).seen
    assert carried == (2 * int(MODEL.nearest[OUT]) + 1,), "a carried item is always seen"


def test_a_carried_item_is_seen_where_its_carrier_is_seen() -> None:
    """On the paper map the entrance E has no location: a ball carried there counts at the
    nearest of all (S1 or S2), yet only E and its doors see the carrier; in S1 the carrier is
    seen from wherever S1's spot is (P1 and S1)."""
    from sim2d.engine import Engine

    paper = build_world_model(Engine("paper-1").scene())
    at = paper.cell_index
    hall, store, play = at[(5, 5)], at[(5, 8)], at[(1, 9)]  # E, S1, P1
    s1 = paper.locations.index("S1")
    assert paper.nearest[hall] == s1 and paper.sees[play, s1]
    viewers = np.array([hall, at[(9, 5)], at[(5, 7)], at[(7, 3)], store, play, at[(13, 9)]])
    seen_from_e = paper.sees_carrier(hall, viewers)  # a person in E, carriers on those cells
    assert seen_from_e.tolist() == [True, True, True, True, False, False, False]
    assert [bool(paper.sees_carrier(v, np.array(hall))) for v in (play, store)] == [False, False]
    seen_in_s1 = [bool(paper.sees_carrier(v, np.array(store))) for v in (play, hall, at[(13, 9)])]
    assert seen_in_s1 == [True, False, False], "from P1 only"
    ball = (2 * s1 + 1,)
    assert percept(paper, play, ball, None, carriers=(hall,)).seen == (NOT_IN_VIEW,)
    assert percept(paper, at[(9, 5)], ball, None, carriers=(hall,)).seen == ball, "E sees E"
    assert percept(paper, play, ball, None, carriers=(store,)).seen == ball


def test_unseen_moves_leave_the_belief_where_it_was() -> None:
    beliefs = BeliefModel(MODEL, r=8.0, delta=1e-4)
    t = beliefs.transition(percept(MODEL, OUT, (REST_A,), None))  # the ball moved to A, unseen
    believed_b = np.eye(4)[REST_B]
    after = t @ believed_b
    assert after[REST_B] == 1.0, f"an unseen move must not change the belief, got {after}"


def test_seeing_the_item_moves_the_belief() -> None:
    beliefs = BeliefModel(MODEL, r=8.0, delta=1e-4)
    t = beliefs.transition(percept(MODEL, ROOM, (REST_A,), None))
    after = t @ np.eye(4)[REST_B]
    assert after[REST_A] > 0.99, after
    assert np.allclose(t.sum(axis=0), 1.0)


def test_speech_replaces_the_belief_about_the_item() -> None:
    beliefs = BeliefModel(MODEL, r=8.0, delta=1e-4)
    outside = percept(MODEL, OUT, (REST_A,), None)
    t = beliefs.transition(told(outside, 0, REST_A))
    assert (t @ np.eye(4)[REST_B])[REST_A] > 0.99


def test_r_matters_only_with_perceptual_noise() -> None:
    seen = percept(MODEL, ROOM, (REST_A,), None)
    exact = [BeliefModel(MODEL, r=r, delta=0.0).transition(seen) for r in (1.0, 8.0)]
    assert np.allclose(exact[0], exact[1]), "with delta = 0, r has no effect"
    noisy = [BeliefModel(MODEL, r=r, delta=1e-2).transition(seen) for r in (1.0, 8.0)]
    assert not np.allclose(noisy[0], noisy[1])
    # r amplifies leakage into worlds the percept contradicts: a person who believes what
    # they see keeps a share of about delta * r * (|PW| - 1) on the other worlds
    leak = [1.0 - t[REST_A, REST_A] for t in noisy]
    assert leak[1] > 5 * leak[0], leak
