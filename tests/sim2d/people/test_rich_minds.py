"""Rich simulated minds (``Autonomy.forget_per_tick / miss / hearsay_per_tick / search / wander / replan /
knows / stale``), each
knob on a hand-built case, and the guarantee that simple minds are unchanged."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from protocol import EpisodeSpec, Minds
from sim2d.engine import Engine
from sim2d.generation.episodes import episode, rich_autonomy
from sim2d.people.autonomous import AutonomousPerson
from sim2d.people.belief import PersonBelief
from sim2d.people.hearsay import exchange
from sim2d.scenario.autonomy import Autonomy
from sim2d.scenario.maps import SCENARIO_DIR
from sim2d.scenario.scenario import Scenario, load_scenario
from sim2d.world.world import World

LOCS = ["P1", "S1", "S2", "P2"]


def engine_with(seed: int = 0, **knobs: object) -> Engine:
    """``paper-auto`` with its people's knobs replaced."""
    scenario = load_scenario("paper-auto")
    return Engine(
        dataclasses.replace(scenario, autonomy=dataclasses.replace(scenario.autonomy, **knobs)), seed=seed
    )


def person(engine: Engine, agent: str) -> AutonomousPerson:
    found = engine.people[agent]
    assert isinstance(found, AutonomousPerson)
    return found


def test_forgetting_drifts_toward_uniform_and_perception_puts_it_right() -> None:
    belief = PersonBelief(["ball"], LOCS)
    belief.told("ball", "S1")
    belief.forget(0.2)
    assert belief.of("ball").tolist() == pytest.approx([0.05, 0.85, 0.05, 0.05])
    belief.perceive({"S1"}, {"ball": "S1"})
    assert belief.of("ball").tolist() == [0, 1, 0, 0], "an item in view is believed where it is seen"


def test_a_forgetful_person_grows_unsure_of_what_is_out_of_view() -> None:
    engine = engine_with(forget_per_tick=0.01, mischief=0.0)
    for _ in range(200):
        engine.step()
    world = engine.world
    for agent in ("A1", "A2"):
        visible, seen = world.percept(agent)
        who = person(engine, agent)
        for item in who.belief.items:
            row = who.belief.of(item)
            if item in seen:
                assert row.max() == pytest.approx(1.0), f"{agent} sees {item}: expected certainty, got {row}"
            else:
                assert row.max() < 0.99, (
                    f"{agent} has not seen {item}: expected doubt after 200 ticks, got {row}"
                )


def test_an_overlooked_item_leaves_the_belief_alone() -> None:
    belief = PersonBelief(["ball", "skate"], LOCS)
    belief.told("ball", "P2")
    belief.perceive({"P1", "S1"}, {"ball": "S1", "skate": "P1"}, missed={"ball"})
    assert belief.of("ball").tolist() == [0, 0, 0, 1], "the ball was missed: still believed in P2"
    assert belief.of("skate").tolist() == [1, 0, 0, 0]


@pytest.mark.parametrize(("miss", "certain"), [(0.0, True), (1.0, False)])
def test_miss_is_drawn_per_sight(miss: float, certain: bool) -> None:
    engine = engine_with(miss=miss)
    engine.step()
    world = engine.world
    for agent in ("A1", "A2"):
        _, seen = world.percept(agent)
        for item in seen:
            if world.items[item].holder == agent:
                continue
            row = person(engine, agent).belief.of(item)
            assert bool(row.max() == pytest.approx(1.0)) is certain, (
                f"miss={miss}: {agent}'s belief of {item}: {row}"
            )
    kept = dict(person(engine, "A1").attention)
    person(engine, "A1").perceive(world)
    assert person(engine, "A1").attention == kept


def met() -> tuple[AutonomousPerson, AutonomousPerson, World]:
    """``paper-auto``'s two people, put in one region."""
    engine = engine_with()
    world = engine.world
    world.agents["A2"].region = world.agents["A1"].region
    return person(engine, "A1"), person(engine, "A2"), world


def test_hearsay_replaces_the_listeners_belief_with_the_tellers() -> None:
    a1, a2, world = met()
    a1.belief.told("ball", "P1")
    a2.belief.p[a2.belief.items.index("ball")] = [0.0, 0.4, 0.6, 0.0]  # unsure: S2 or S1
    a1.belief.told("skate", "S1")
    a2.belief.told("skate", "S1")
    exchange([a1, a2], world, np.random.default_rng(3), rate=1.0)
    assert a2.belief.most_likely("ball") == "P1", "the sure one should have told the unsure one"
    assert a1.belief.most_likely("ball") == "P1", "the unsure one has nothing to tell"
    assert a1.belief.most_likely("skate") == "S1" == a2.belief.most_likely("skate")


def test_hearsay_needs_a_teller_surer_than_the_listener() -> None:
    a1, a2, world = met()
    a1.belief.told("ball", "P1")
    a2.belief.told("ball", "P2")  # both sure, of different places: nobody takes the other's word
    a1.belief.p[a1.belief.items.index("skate")] = [0.3, 0.3, 0.4, 0.0]  # too unsure to tell
    exchange([a1, a2], world, np.random.default_rng(3), rate=1.0)
    assert (a1.belief.most_likely("ball"), a2.belief.most_likely("ball")) == ("P1", "P2")
    skate = a2.belief.of("skate")
    assert a2.belief.sureness("skate") == 0.25, f"a teller unsure of S2 should tell nothing, got {skate}"


def test_people_may_start_knowing_or_sure_of_a_place_the_item_left() -> None:
    knowing = engine_with(knows=1.0)
    for agent in ("A1", "A2"):
        for item in ("ball", "skate"):
            where = knowing.world.items[item].location
            assert person(knowing, agent).belief.of(item)[LOCS.index(where)] == 1.0, (agent, item)
    stale = engine_with(stale=1.0)
    for item in ("ball", "skate"):
        where = stale.world.items[item].location
        belief = person(stale, "A1").belief
        assert belief.sureness(item) == 1.0 and belief.most_likely(item) != where, belief.of(item)
    ignorant = engine_with()
    assert np.allclose(person(ignorant, "A1").belief.p, 0.25), "by default people start not knowing"
    with pytest.raises(ValueError, match="knows \\+ stale"):
        Autonomy(knows=0.7, stale=0.5)


def test_no_hearsay_across_rooms_or_at_rate_zero() -> None:
    engine = engine_with()
    a1, a2 = person(engine, "A1"), person(engine, "A2")
    world = engine.world
    a1.belief.told("ball", "P1")
    a2.belief.told("ball", "P2")
    world.agents["A2"].region = "elsewhere"
    exchange([a1, a2], world, np.random.default_rng(3), rate=1.0)
    world.agents["A2"].region = world.agents["A1"].region
    exchange([a1, a2], world, np.random.default_rng(3), rate=0.0)
    assert (a1.belief.most_likely("ball"), a2.belief.most_likely("ball")) == ("P1", "P2")


def test_nearest_search_looks_where_it_is_near_first() -> None:
    engine = engine_with(search="nearest")
    who = person(engine, "A1")
    world = engine.world
    col, row = world.agents["A1"].cell

    def distance(loc: str) -> int:
        return abs(world.locations[loc].cell.col - col) + abs(world.locations[loc].cell.row - row)

    near, far = sorted(("S1", "P2"), key=distance)
    assert distance(near) < distance(far)
    ball = np.zeros(len(who.belief.locations))
    ball[who.belief.locations.index(near)] = 0.4  # at least half as likely as the best
    ball[who.belief.locations.index(far)] = 0.6
    who.belief.p[who.belief.items.index("ball")] = ball
    assert who._where_to_look(world, "ball") == near
    who.autonomy = dataclasses.replace(who.autonomy, search="likely")
    assert who._where_to_look(world, "ball") == far


def test_a_wanderer_walks_somewhere_first_and_a_replanner_drops_walks() -> None:
    engine = engine_with(wander=1.0, mischief=0.0)
    who = person(engine, "A1")
    world = engine.world
    who.preference = "ball"
    who._decide(world)
    steps = [step.do for step in who.plan]
    assert steps == ["goto", "goto", "take"], f"expected a detour, a walk and a take, got {steps}"
    replanner = engine_with(replan=1.0, mischief=0.0, switch=0.0)
    busy = person(replanner, "A1")
    busy.preference = "ball"
    replanner.step()
    first = busy.current
    replanner.step()
    assert busy.current is not first or busy.current is None, "a walk under way was dropped and decided again"


def test_simple_minds_are_the_same_draw_for_draw() -> None:
    simple = episode("e", "paper", SCENARIO_DIR / "paper.map.toml", 2, 7)
    rich = episode("e", "paper", SCENARIO_DIR / "paper.map.toml", 2, 7, EpisodeSpec(minds=Minds.RICH))
    assert [line for line in rich.splitlines() if line not in rich_autonomy(7)] == simple.splitlines()

    def story(engine: Engine) -> list[tuple[int, str, str]]:
        out = []
        while not engine.done and engine.world.tick < 400:
            out += [(e.tick, e.kind.value, e.actor) for e in engine.step().events]
        return out

    scenario = load_scenario("paper-auto")
    explicit = dataclasses.replace(
        scenario,
        autonomy=dataclasses.replace(
            scenario.autonomy, forget_per_tick=0.0, miss=0.0, hearsay_per_tick=0.0, wander=0.0, replan=0.0
        ),
    )
    assert story(Engine(scenario, seed=2)) == story(Engine(explicit, seed=2))
    assert story(engine_with(seed=2, miss=0.3, hearsay_per_tick=0.05)) != story(Engine(scenario, seed=2))


def test_bad_knobs_are_named() -> None:
    with pytest.raises(ValueError, match="miss = 1.5"):
        Autonomy(miss=1.5)
    with pytest.raises(ValueError, match="search must be one of likely, nearest"):
        Autonomy(search="random")
    assert isinstance(load_scenario("paper-auto"), Scenario)
