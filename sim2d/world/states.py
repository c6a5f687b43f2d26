"""The world's bodies as the protocol states ``engine/state`` carries (:class:`~protocol.AgentState`,
:class:`~protocol.ItemState`).

A body's state is kept from the last tick while all it is made of is unchanged (most bodies
stand still most ticks): the same object, so the same bytes on the wire, without building it
again.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from protocol import Activity, AgentState, Cell, ItemState, Pose, Vec2

if TYPE_CHECKING:
    from .world import Agent, Item, World


class BodyStates:
    """Every body's last state and what it was made of, for one :class:`~sim2d.world.world.World`."""

    def __init__(self, world: World) -> None:
        self.world = world
        self._agents: dict[str, tuple[object, bool, AgentState]] = {}
        self._items: dict[str, tuple[object, ItemState]] = {}

    def agents(self) -> tuple[AgentState, ...]:
        """Every agent's body now, each kept from the last tick while unchanged."""
        world = self.world
        out, at, moving = [], world.physics.position, world.physics.velocity
        for agent_id, agent in world.agents.items():
            made_of = (at(agent_id), moving(agent_id), agent.heading, agent.cell, agent.region, agent.holding)
            kept = self._agents.get(agent_id)
            if kept is None or kept[0] != made_of or kept[1] != agent.playing:
                kept = (made_of, agent.playing, self._agent_state(agent, *made_of[:2]))
                self._agents[agent_id] = kept
            out.append(kept[2])
        return tuple(out)

    def _agent_state(
        self, agent: Agent, position: tuple[float, float], velocity: tuple[float, float]
    ) -> AgentState:
        (x, y), (vx, vy) = position, velocity
        moving = abs(vx) + abs(vy) > 1e-6
        activity = Activity.PLAYING if agent.playing else Activity.MOVING if moving else Activity.IDLE
        return AgentState(
            id=agent.id,
            pose=Pose(round(x, 6), round(y, 6), round(agent.heading, 6)),
            velocity=Vec2(round(vx, 6), round(vy, 6)),
            cell=Cell(*agent.cell),
            region=agent.region,
            holding=agent.holding,
            activity=activity,
        )

    def items(self) -> tuple[ItemState, ...]:
        """Every item's body now (each kept from the last tick while unchanged, as agents')."""
        world = self.world
        out = []
        for item_id, item in world.items.items():
            holder = world.agents[item.holder] if item.holder is not None else None
            made_of = (
                world.physics.position(item_id),
                item.location,
                item.holder,
                holder.cell if holder is not None else None,
                holder.region if holder is not None else None,
            )
            kept = self._items.get(item_id)
            if kept is None or kept[0] != made_of:
                kept = (made_of, self._item_state(item, made_of[0]))
                self._items[item_id] = kept
            out.append(kept[1])
        return tuple(out)

    def _item_state(self, item: Item, position: tuple[float, float]) -> ItemState:
        world = self.world
        x, y = position
        cell = world.item_cell(item.id)
        holder = world.agents[item.holder] if item.holder is not None else None
        region = holder.region if holder is not None else world.locations[item.location or ""].region
        return ItemState(
            id=item.id,
            pose=Pose(round(x, 6), round(y, 6)),
            cell=Cell(*cell),
            region=region,
            location=item.location,
            held_by=item.holder,
        )
