"""Issue 66: the factored unseen world (``unseen_world = factored``). The robot keeps one
belief per item (:class:`~brain.tracking.itemview.ItemView`), and each person the rows their
percepts told apart (:class:`~brain.tracking.personrows.PersonRows`); on the corridor it
infers what the joint branches infer, and it updates by sight as they do."""

from __future__ import annotations

import numpy as np
import pytest

from brain.model.world import build_world_model
from brain.settings import ModelSettings, UnseenWorld
from brain.tracking.itemview import CARRIED, UNKNOWN, ItemView
from brain.tracking.itemworld import ItemWorld
from brain.tracking.personrows import PersonRows
from brain.tracking.tracker import MindTracker
from protocol import Event, EventKind
from tests.scenes import corridor_scene, corridor_state

FACTORED = ModelSettings(perception="embodied", unseen_world=UnseenWorld.FACTORED)
JOINT = ModelSettings(perception="embodied", unseen_world=UnseenWorld.JOINT)


def at(tracker: MindTracker, location: str) -> float:
    """The robot's probability that the ball rests at ``location``."""
    where = tracker.where()
    assert where is not None
    return float(where[0, tracker.model.locations.index(location)])


def test_the_factored_world_infers_what_the_joint_branches_infer() -> None:
    """The person sees both spots, the robot neither: walking right, away from A, raises B
    in both worlds alike (one person, one item: the rows are the branches)."""
    trackers = {w: MindTracker(corridor_scene(), s) for w, s in (("joint", JOINT), ("factored", FACTORED))}
    assert isinstance(trackers["factored"].world, ItemWorld)
    for tick, col in enumerate((5, 6, 7)):
        for tracker in trackers.values():
            tracker.observe(corridor_state(tick, col), [])
    joint, factored = trackers["joint"], trackers["factored"]
    assert at(factored, "B") > 0.9 and at(factored, "B") == pytest.approx(at(joint, "B"), abs=1e-9)
    j, f = joint.online("p"), factored.online("p")
    assert j is not None and f is not None
    np.testing.assert_allclose(f.beliefs, j.beliefs, atol=1e-9)
    np.testing.assert_allclose(f.preference, j.preference, atol=1e-9)
    assert len(factored.tracks["p"].chains) == 2, "one row with the ball at A, one at B"


def test_sight_takes_and_put_downs_update_each_item_on_its_own() -> None:
    model = build_world_model(corridor_scene())
    view = ItemView(model)
    a, b = model.locations.index("A"), model.locations.index("B")
    view.observe(corridor_state(0, 5), 0, [])  # the robot outside sees neither spot
    assert view.known[0] == UNKNOWN and view.origin[0, a] == pytest.approx(0.5)
    take = Event(episode=1, tick=1, time=0.7, kind=EventKind.TAKE, actor="p", item="ball", location="A")
    view.observe(corridor_state(1, 5, ball_at="A", holding=True), 0, [take])
    assert view.known[0] == CARRIED and view.origin[0, a] == 1.0, "a take fixes where it rested"
    view.observe(corridor_state(2, 8, ball_at="B"), 0, [])  # put down at B, out of view
    assert view.known[0] == b, "a put-down by someone tracked makes its place known"
    seen = ItemView(model)
    seen.observe(corridor_state(0, 5, robot=3, ball_at="A"), model.cell_index[(3, 0)], [])
    assert seen.known[0] == a and seen.origin[0, a] == 1.0, "a sighting collapses it"


def test_rows_split_on_what_a_person_sees_and_carry_their_evidence() -> None:
    """Three spots, two items: a person who sees spot 0 splits each item's origin into
    "there" and "not there"; the message of their decisions favours the rows they made
    likelier, and a spot the robot rules out drops the rows that held it."""
    q = np.full((2, 3), 1 / 3)
    rows = PersonRows(np.ones((2, 3), dtype=bool), cap=8)
    source = rows.split(np.array([True, False, False]), q, np.array([True, True]), np.zeros(1))
    assert len(rows) == 4 and source.tolist() == [0, 0, 0, 0]
    assert rows.weights(q, np.zeros(4)).sum() == pytest.approx(1.0)
    evidence = np.where(rows.sets[:, 0, 0], 0.0, -np.log(4.0))  # item 0 at spot 0: 4 times likelier
    lam = rows.message(q, evidence)
    assert lam[0, 0] == pytest.approx(1.0) and lam[0, 1] == pytest.approx(0.25)
    np.testing.assert_allclose(lam[1], 1.0, err_msg="item 1 is not what the evidence is about")
    kept = rows.restrict(np.array([[0.0, 0.5, 0.5], [1 / 3, 1 / 3, 1 / 3]]))
    assert len(kept) == 2 and not rows.sets[:, 0, 0].any()


def test_the_cap_keeps_the_heaviest_rows() -> None:
    q = np.full((3, 4), 0.25)
    rows = PersonRows(np.ones((3, 4), dtype=bool), cap=3)
    rows.split(np.array([True, False, False, False]), q, np.ones(3, dtype=bool), np.zeros(1))
    assert len(rows) == 3
    at_spot = rows.sets[:, :, 0].sum(axis=1)  # (R,) items a row puts at the spot
    assert sorted(at_spot.tolist()) == [0, 1, 1], "no item at the spot, then single items (27 in all)"
