"""What the tracker needs of a ``state`` before it takes it in: where every item is."""

from __future__ import annotations

from protocol import State

from ..errors import StateError
from ..model.world import ABSENT, WorldModel


def check_items(model: WorldModel, state: State) -> None:
    """Every item of the scene in ``state``, resting at a known location or held by an agent
    it lists (in a scene with an absent item, a missing one reads as absent instead).

    Raises:
        StateError: naming the item and what is wrong with it."""
    if ABSENT in model.locations:
        return
    items = {i.id: i for i in state.items}
    agents = {a.id for a in state.agents}
    for item in model.items:
        got = items.get(item)
        where = f"the state of episode {state.episode} tick {state.tick}"
        if got is None:
            raise StateError(
                f"{where} lists no item '{item}': every item of the scene must be in every state "
                "(mark one that is not there 'absent: true' in the scene)"
            )
        if got.held_by is not None and got.held_by not in agents:
            raise StateError(f"{where}: item '{item}' is held by '{got.held_by}', whom it does not list")
        if got.held_by is None and got.location not in model.locations:
            raise StateError(
                f"{where}: item '{item}' is neither held nor resting at a location of the scene "
                f"(location {got.location!r})"
            )
