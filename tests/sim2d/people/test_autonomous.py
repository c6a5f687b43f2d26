"""Autonomous simulated people: true beliefs that follow the visibility rule exactly, and
their true minds on the truth channel."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from sim2d.engine import Engine
from sim2d.people.belief import PersonBelief

LOCS = ["P1", "S1", "S2", "P2"]


def test_seen_items_are_where_they_are_seen() -> None:
    belief = PersonBelief(["ball"], LOCS)
    belief.perceive({"P1", "S1"}, {"ball": "S1"})
    assert belief.of("ball").tolist() == [0, 1, 0, 0]


def test_an_item_not_in_view_is_not_at_a_visible_location() -> None:
    belief = PersonBelief(["ball"], LOCS)
    belief.perceive({"P1", "S1"}, {})
    assert belief.of("ball").tolist() == [0, 0, 0.5, 0.5]


def test_unseen_moves_leave_the_belief_alone() -> None:
    belief = PersonBelief(["ball"], LOCS)
    belief.perceive({"P1", "S1"}, {"ball": "S1"})
    belief.perceive(set(), {})  # outside: the ball is moved to S2 unseen
    assert belief.of("ball").tolist() == [0, 1, 0, 0], "people assume unseen things stay put"
    belief.perceive({"P1", "S1"}, {})  # back: the ball is not in S1 any more
    assert belief.of("ball").tolist() == [0, 0, 0.5, 0.5]


def test_being_told_replaces_the_belief() -> None:
    belief = PersonBelief(["ball"], LOCS)
    belief.perceive({"P1", "S1"}, {"ball": "S1"})
    belief.told("ball", "P2")
    assert belief.most_likely("ball") == "P2"


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_beliefs_follow_visibility_through_an_episode(seed: int) -> None:
    """Each tick, for every autonomous person: an item in view is believed where it is, and
    no probability rests on a visible location that holds nothing of the item."""
    engine = Engine("paper-auto", seed=seed)
    world = engine.world
    checked = 0
    while not engine.done and world.tick < 800:
        result = engine.step()
        assert result.truth is not None
        for mind in result.truth.agents:
            visible, seen = world.percept(mind.agent)
            for belief in mind.beliefs:
                probs = {p.id: p.p for p in belief.locations}
                assert abs(sum(probs.values()) - 1) < 1e-5  # probabilities travel rounded to 6 digits
                if belief.item in seen:
                    assert probs[seen[belief.item]] == pytest.approx(1.0), (world.tick, mind.agent, belief)
                else:
                    assert all(probs[loc] == 0 for loc in visible), (world.tick, mind.agent, belief, visible)
                checked += 1
    assert checked > 1000
    kinds = {p.preference for p in engine.truth().agents}  # type: ignore[union-attr]
    assert kinds <= {"skate", "ball", "out"}


def test_same_seed_same_minds_other_seed_other_story() -> None:
    def story(seed: int) -> list[tuple[str, str]]:
        engine = Engine("paper-auto", seed=seed)
        out = []
        while not engine.done and engine.world.tick < 600:
            out += [(e.kind.value, e.actor) for e in engine.step().events]
        return out

    assert story(4) == story(4)
    assert story(4) != story(5)
    assert np.isfinite(len(story(6)))


def test_an_item_carried_off_out_of_sight_may_be_anywhere_out_of_view() -> None:
    belief = PersonBelief(["ball"], LOCS)
    belief.perceive({"P1", "S1"}, {"ball": "S1"})  # someone carries it in S1
    belief.perceive({"P1", "S1"}, {}, carried_off={"ball"})  # ... and walks out of sight with it
    assert belief.of("ball").tolist() == [0, 0, 0.5, 0.5], "it went with its carrier: anywhere out of view"
    belief.perceive({"P1"}, {"ball": "P1"})
    belief.perceive(set(), {}, carried_off={"ball"})  # from outside nothing is in view: evenly anywhere
    assert belief.of("ball").tolist() == [0.25] * 4, f"expected even odds, got {belief.of('ball')}"


@pytest.mark.parametrize("seed", [0, 1, 4, 6])  # seeds where someone sees it happen
def test_people_who_see_an_item_carried_off_do_not_believe_it_where_it_passed(seed: int) -> None:
    """Each tick, for every autonomous person who saw someone else carry an item at the tick
    before and sees it no more because the carrier moved: they believe it evenly anywhere out
    of view, not at the location it counted at when they last saw it."""
    engine = Engine("paper-auto", seed=seed)
    world = engine.world
    carried: dict[str, dict[str, tuple[str, tuple[int, int]]]] = {}
    checked = 0
    while not engine.done and world.tick < 1500:
        result = engine.step()
        assert result.truth is not None
        for mind in result.truth.agents:
            visible, seen = world.percept(mind.agent)
            for item, (holder, cell) in carried.get(mind.agent, {}).items():
                moved = world.items[item].holder != holder or world.agents[holder].cell != cell
                if item in seen or not moved:
                    continue
                probs = {p.id: p.p for b in mind.beliefs if b.item == item for p in b.locations}
                hidden = [loc for loc in LOCS if loc not in visible]
                expected = {loc: (1 / len(hidden) if loc in hidden else 0.0) for loc in LOCS}
                assert probs == pytest.approx(expected, abs=1e-5), (world.tick, mind.agent, item, probs)
                checked += 1
            carried[mind.agent] = {
                item: (holder, world.agents[holder].cell)
                for item in seen
                if (holder := world.items[item].holder) is not None and holder != mind.agent
            }
    assert checked > 0, "no one saw an item carried off out of sight: the test exercised nothing"


def test_a_person_answers_what_they_want_truthfully_when_free_and_may_not_when_busy() -> None:
    engine = Engine("paper-auto", seed=0)
    person = next(p for p in engine.people.values() if hasattr(p, "autonomy"))
    person.preference = "ball"
    person.autonomy = dataclasses.replace(person.autonomy, silent=1.0)
    world = engine.world
    agent = world.agents[person.id]
    assert agent.holding is None and not agent.playing, "the person should start free"
    person.current, person.plan = None, type(person.plan)()
    assert person.says_wanted(world, None) == ("ball", True)
    assert person.says_wanted(world, "skate") == ("skate", False)
    person.preference = "out"
    assert person.says_wanted(world, None) == (None, False), "wanting nothing: no item, and no"
    agent.playing = True
    assert person.says_wanted(world, None) is None, "busy playing, with silent = 1: no answer"
