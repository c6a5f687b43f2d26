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
        physics = world.physics
        fresh_agents = tuple(
            world._agent_state(a, physics.position(a.id), physics.velocity(a.id))
            for a in world.agents.values()
        )
        fresh_items = tuple(world._item_state(i, physics.position(i.id)) for i in world.items.values())
        assert agents == fresh_agents, f"{scenario} tick {world.tick}: kept {agents}, afresh {fresh_agents}"
        assert items == fresh_items, f"{scenario} tick {world.tick}: kept {items}, afresh {fresh_items}"
        now = {id(s) for s in (*agents, *items)}
        kept += len(now & last)
        last = now
    assert kept > 0, "no state was ever kept from the tick before"
