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

from .driving import go, holding, shown, succeed
from .needs import need_acting_robot
from .probe import CheckFailed, CheckSkipped, Probe

TRIES = 4
"""Items (or places) tried when people take (or fill) them while the robot walks there."""
GIVE_TRIES = 4
"""Tries at handing an item to a person who may walk off meanwhile."""


def _reachable(probe: Probe) -> dict[GridCell, int]:
    """Walking distance from the robot to every cell it can reach."""
    assert probe.info is not None and probe.robot is not None
    return walking_distances(probe.info.scene.walkable(), [probe.cell_of(probe.robot)])


def _held(probe: Probe) -> dict[str, str]:
    """Item -> who holds it, by the items' ``held_by`` and the agents' ``holding``."""
    state = probe.latest()
    held = {a.holding: a.id for a in state.agents if a.holding is not None}
    return held | {i.id: i.held_by for i in state.items if i.held_by is not None}


def _free_items(probe: Probe) -> tuple[list[tuple[str, str, GridCell]], list[str]]:
    """Items free to pick (id, location, the location's cell), nearest first; and what
    the others are doing (``'car' held by bob``)."""
    assert probe.info is not None
    cells = {loc.id: (loc.cell.col, loc.cell.row) for loc in probe.info.scene.locations}
    distances, held = _reachable(probe), _held(probe)
    free: list[tuple[int, str, str, GridCell]] = []
    others: list[str] = []
    for item in probe.latest().items:
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


def _rests_at(probe: Probe, item: str, location: str) -> bool:
    return item not in _held(probe) and any(
        i.id == item and i.location == location for i in probe.latest().items
    )


def _pick_a_free_item(probe: Probe) -> tuple[str, str]:
    """Walk to a free item and pick it; ``(item, where it rested)``.

    Raises:
        CheckSkipped: no item is free, or each tried was taken before the robot got it.
        CheckFailed: the engine refused to pick an item that was free.
    """
    assert probe.robot is not None
    taken: list[str] = []
    for _ in range(TRIES):
        free, others = _free_items(probe)
        if not free:
            seen = "; ".join(taken + others) or "the scene has no items"
            raise CheckSkipped(f"no item rests free at a location the robot can reach ({seen})")
        item, source, cell = free[0]
        go(probe, cell, f"to pick '{item}'")
        if not _rests_at(probe, item, source):
            taken.append(f"'{item}' left {source} while the robot walked there")
            continue
        statuses = probe.command(Pick(item=item))
        if statuses[-1].state is CommandState.SUCCEEDED:
            return item, source
        if _rests_at(probe, item, source):
            raise CheckFailed(f"pick '{item}' at {source}: expected succeeded, got {shown(statuses)}")
        taken.append(f"'{item}' was taken from {source} as the robot picked it")
    raise CheckSkipped(f"no item stayed free long enough to pick ({'; '.join(taken)})")


def _places(probe: Probe, item_from: str) -> list[tuple[str, GridCell]]:
    """Locations with room for one more item (not ``item_from``, not a ``use`` spot) that
    the robot can reach, nearest first."""
    assert probe.info is not None
    held, distances = _held(probe), _reachable(probe)
    resting = [i.location for i in probe.latest().items if i.id not in held]
    found = []
    for loc in probe.info.scene.locations:
        cell = (loc.cell.col, loc.cell.row)
        room = loc.capacity is None or resting.count(loc.id) < loc.capacity
        if loc.id != item_from and room and not loc.use and cell in distances:
            found.append((distances[cell], loc.id, cell))
    return [(loc, cell) for _, loc, cell in sorted(found)]


def _place(probe: Probe, item: str, source: str) -> str:
    """Walk to a location with room and place ``item`` there; the location.

    Raises:
        CheckSkipped: no location with room the robot can reach, or each tried filled up.
        CheckFailed: the engine refused a place that had room, or the state disagrees.
    """
    filled: list[str] = []
    for _ in range(TRIES):
        places = _places(probe, source)
        if not places:
            seen = "; ".join(filled) or "every other location is full, a use spot or out of reach"
            raise CheckSkipped(f"picked '{item}', but found nowhere to place it ({seen})")
        target, there = places[0]
        go(probe, there, f"to place '{item}'")
        if not any(loc == target for loc, _ in _places(probe, source)):
            filled.append(f"{target} filled up while the robot walked there")
            continue
        succeed(probe, Place(location=target), f"place '{item}' at {target}")
        where = next((i for i in probe.latest().items if i.id == item), None)
        if where is None or where.location != target or where.held_by is not None:
            raise CheckFailed(f"place succeeded: expected '{item}' resting at {target}, got {where}")
        return target
    raise CheckSkipped(f"picked '{item}', but every place filled up ({'; '.join(filled)})")


def check_pick_place_give(probe: Probe) -> str:
    """Pick, place and give succeed, with the state showing each."""
    need_acting_robot(probe)
    assert probe.robot is not None
    already = holding(probe, probe.robot)  # from an earlier check: place that one
    item, source = (already, "the robot's hands") if already else _pick_a_free_item(probe)
    if holding(probe, probe.robot) != item:
        raise CheckFailed(
            f"pick succeeded: expected the robot to hold '{item}', got {holding(probe, probe.robot)}"
        )
    target = _place(probe, item, source)
    done = f"picked and placed '{item}' ({source} -> {target}); "
    again = probe.command(Pick(item=item))
    if again[-1].state is not CommandState.SUCCEEDED:
        if _rests_at(probe, item, target):
            raise CheckFailed(f"pick '{item}' again at {target}: expected succeeded, got {shown(again)}")
        return done + f"no give: '{item}' was taken from {target} before the robot picked it again"
    return done + _give(probe, item)


def _give(probe: Probe, item: str) -> str:
    assert probe.info is not None and probe.robot is not None
    people = [a.id for a in probe.info.scene.agents if a.kind is AgentKind.PERSON]
    reasons = []
    for _ in range(GIVE_TRIES):
        free = [
            p for p in people if any(a.id == p for a in probe.latest().agents) and holding(probe, p) is None
        ]
        if not free:
            probe.step(20)
            continue
        person = free[0]
        go(probe, probe.cell_of(person), f"to {person}")
        statuses = probe.command(Give(person=person))
        if statuses[-1].state is CommandState.SUCCEEDED:
            if holding(probe, person) != item:
                raise CheckFailed(
                    f"give succeeded: expected {person} to hold '{item}', got {holding(probe, person)}"
                )
            return f"gave it to {person}"
        reasons.append(shown(statuses)[-1])
    return f"no give succeeded in {GIVE_TRIES} tries ({'; '.join(reasons) or 'nobody had free hands'})"
