"""The conformance check of handling items: pick, place and give, each succeeding with the
state showing it.

The check chooses what it exercises from the state it sees, as a brain would: an item that
rests at a location the robot can walk to and that nobody holds, and a location with room
for it. People keep moving, so it looks again on arrival: an item taken meanwhile is not
the engine's fault, and another is tried. When there is nothing to pick (or nowhere to put
it) the check is skipped, saying what it saw.
"""

from __future__ import annotations

from protocol import AgentKind, CommandState, Give, GridCell, Pick, Place
from protocol.carry import walking_distances

from .commands import CommandChecks, shown
from .probe import CheckFailed, CheckSkipped

TRIES = 4
"""Items (or places) tried when people take (or fill) them while the robot walks there."""
GIVE_TRIES = 4
"""Tries at handing an item to a person who may walk off meanwhile."""


class ItemChecks(CommandChecks):
    """The item-handling check (``check_pick_place_give``) and what it stands on."""

    def _reachable(self) -> dict[GridCell, int]:
        """Walking distance from the robot to every cell it can reach."""
        assert self.info is not None and self.robot is not None
        return walking_distances(self.info.scene.walkable(), [self.cell_of(self.robot)])

    def _held(self) -> dict[str, str]:
        """Item -> who holds it, by the items' ``held_by`` and the agents' ``holding``."""
        state = self.latest()
        held = {a.holding: a.id for a in state.agents if a.holding is not None}
        return held | {i.id: i.held_by for i in state.items if i.held_by is not None}

    def _free_items(self) -> tuple[list[tuple[str, str, GridCell]], list[str]]:
        """Items free to pick (id, location, the location's cell), nearest first; and what
        the others are doing (``'car' held by bob``)."""
        assert self.info is not None
        cells = {loc.id: (loc.cell.col, loc.cell.row) for loc in self.info.scene.locations}
        distances, held = self._reachable(), self._held()
        free: list[tuple[int, str, str, GridCell]] = []
        others: list[str] = []
        for item in self.latest().items:
            if item.id in held:
                others.append(f"'{item.id}' held by {held[item.id]}")
            elif item.location is None or item.location not in cells:
                others.append(f"'{item.id}' at no location")
            elif cells[item.location] not in distances:
                others.append(f"'{item.id}' at {item.location}, which the robot cannot reach")
            else:
                cell = cells[item.location]
                free.append((distances[cell], item.id, item.location, cell))
        return [(i, loc, cell) for _, i, loc, cell in sorted(free)], others

    def _rests_at(self, item: str, location: str) -> bool:
        return item not in self._held() and any(
            i.id == item and i.location == location for i in self.latest().items
        )

    def _pick_a_free_item(self) -> tuple[str, str]:
        """Walk to a free item and pick it; ``(item, where it rested)``.

        Raises:
            CheckSkipped: no item is free, or each tried was taken before the robot got it.
            CheckFailed: the engine refused to pick an item that was free.
        """
        assert self.robot is not None
        taken: list[str] = []
        for _ in range(TRIES):
            free, others = self._free_items()
            if not free:
                seen = "; ".join(taken + others) or "the scene has no items"
                raise CheckSkipped(f"no item rests free at a location the robot can reach ({seen})")
            item, source, cell = free[0]
            self._go(cell, f"to pick '{item}'")
            if not self._rests_at(item, source):
                taken.append(f"'{item}' left {source} while the robot walked there")
                continue
            statuses = self.command(Pick(item=item))
            if statuses[-1].state is CommandState.SUCCEEDED:
                return item, source
            if self._rests_at(item, source):
                raise CheckFailed(f"pick '{item}' at {source}: expected succeeded, got {shown(statuses)}")
            taken.append(f"'{item}' was taken from {source} as the robot picked it")
        raise CheckSkipped(f"no item stayed free long enough to pick ({'; '.join(taken)})")

    def _places(self, item_from: str) -> list[tuple[str, GridCell]]:
        """Locations with room for one more item (not ``item_from``, not a ``use`` spot) that
        the robot can reach, nearest first."""
        assert self.info is not None
        held, distances = self._held(), self._reachable()
        resting = [i.location for i in self.latest().items if i.id not in held]
        found = []
        for loc in self.info.scene.locations:
            cell = (loc.cell.col, loc.cell.row)
            room = loc.capacity is None or resting.count(loc.id) < loc.capacity
            if loc.id != item_from and room and not loc.use and cell in distances:
                found.append((distances[cell], loc.id, cell))
        return [(loc, cell) for _, loc, cell in sorted(found)]

    def _place(self, item: str, source: str) -> str:
        """Walk to a location with room and place ``item`` there; the location.

        Raises:
            CheckSkipped: no location with room the robot can reach, or each tried filled up.
            CheckFailed: the engine refused a place that had room, or the state disagrees.
        """
        filled: list[str] = []
        for _ in range(TRIES):
            places = self._places(source)
            if not places:
                seen = "; ".join(filled) or "every other location is full, a use spot or out of reach"
                raise CheckSkipped(f"picked '{item}', but found nowhere to place it ({seen})")
            target, there = places[0]
            self._go(there, f"to place '{item}'")
            if not any(loc == target for loc, _ in self._places(source)):
                filled.append(f"{target} filled up while the robot walked there")
                continue
            self._succeed(Place(location=target), f"place '{item}' at {target}")
            where = next((i for i in self.latest().items if i.id == item), None)
            if where is None or where.location != target or where.held_by is not None:
                raise CheckFailed(f"place succeeded: expected '{item}' resting at {target}, got {where}")
            return target
        raise CheckSkipped(f"picked '{item}', but every place filled up ({'; '.join(filled)})")

    def check_pick_place_give(self) -> str:
        self._need_acting_robot()
        assert self.robot is not None
        already = self._holding(self.robot)  # from an earlier check: place that one
        item, source = (already, "the robot's hands") if already else self._pick_a_free_item()
        if self._holding(self.robot) != item:
            raise CheckFailed(
                f"pick succeeded: expected the robot to hold '{item}', got {self._holding(self.robot)}"
            )
        target = self._place(item, source)
        done = f"picked and placed '{item}' ({source} -> {target}); "
        again = self.command(Pick(item=item))
        if again[-1].state is not CommandState.SUCCEEDED:
            if self._rests_at(item, target):
                raise CheckFailed(f"pick '{item}' again at {target}: expected succeeded, got {shown(again)}")
            return done + f"no give: '{item}' was taken from {target} before the robot picked it again"
        return done + self._give(item)

    def _give(self, item: str) -> str:
        assert self.info is not None and self.robot is not None
        people = [a.id for a in self.info.scene.agents if a.kind is AgentKind.PERSON]
        reasons = []
        for _ in range(GIVE_TRIES):
            free = [
                p for p in people if any(a.id == p for a in self.latest().agents) and self._holding(p) is None
            ]
            if not free:
                self.step(20)
                continue
            person = free[0]
            self._go(self.cell_of(person), f"to {person}")
            statuses = self.command(Give(person=person))
            if statuses[-1].state is CommandState.SUCCEEDED:
                if self._holding(person) != item:
                    raise CheckFailed(
                        f"give succeeded: expected {person} to hold '{item}', got {self._holding(person)}"
                    )
                return f"gave it to {person}"
            reasons.append(shown(statuses)[-1])
        return f"no give succeeded in {GIVE_TRIES} tries ({'; '.join(reasons) or 'nobody had free hands'})"
