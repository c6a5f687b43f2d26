"""A body's state is kept from tick to tick while what it is made of is unchanged: every kept
state equals the one built afresh, over whole episodes where people walk, take, carry,
put down, give and play."""

from __future__ import annotations

import pytest

from sim2d.engine import Engine


@pytest.mark.parametrize("scenario", ["paper-auto", "paper-3", "sally-anne", "food-trucks"])
def test_kept_body_states_are_those_built_afresh(scenario: str) -> None:
    engine = Engine(scenario)
    world = engine.world
    kept, last = 0, set()
    for _ in range(600):
        engine.step()
        agents, items = world.agent_states(), world.item_states()
        physics, states = world.physics, world._states
        fresh_agents = tuple(
            states._agent_state(a, physics.position(a.id), physics.velocity(a.id))
            for a in world.agents.values()
        )
        fresh_items = tuple(states._item_state(i, physics.position(i.id)) for i in world.items.values())
        assert agents == fresh_agents, f"{scenario} tick {world.tick}: kept {agents}, afresh {fresh_agents}"
        assert items == fresh_items, f"{scenario} tick {world.tick}: kept {items}, afresh {fresh_items}"
        now = {id(s) for s in (*agents, *items)}
        kept += len(now & last)
        last = now
    assert kept > 0, "no state was ever kept from the tick before"


def test_a_carried_item_is_seen_only_where_its_carrier_is_seen() -> None:
    """The entrance E has no item location, so an item carried there counts at the nearest of
    all (S1); A1, in P1, sees S1 but not E, and must not perceive the ball (she did, at S1);
    the robot, in E, sees it carried; once the carrier is in S1, A1 sees it there."""
    world = Engine("paper-auto").world
    carrier, ball = world.agents["A2"], world.items["ball"]
    carrier.cell, carrier.region, carrier.holding = (5, 5), "E", "ball"
    ball.holder, ball.location = "A2", None
    assert world.item_location("ball") == "S1" and "S1" in world.percept("A1")[0]
    assert "ball" not in world.percept("A1")[1], "A1 in P1 cannot see A2 in the entrance"
    assert world.percept("robot")[1].get("ball") == "S1", "the robot in the entrance sees A2 carry it"
    assert world.percept("A2")[1].get("ball") == "S1", "the carrier sees what they carry"
    carrier.cell, carrier.region = (5, 8), "S1"
    assert world.percept("A1")[1].get("ball") == "S1", "in S1, A2 is in A1's view"
