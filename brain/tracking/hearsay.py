"""Hearsay: what a person may have heard of where items are from the others in their region
(``ModelSettings.hearsay``), as rumours the lapses model takes in as speech (pure)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from protocol import State

from ..model.estimates import Estimate
from ..model.world import value_of


def rumours(
    state: State, person: str, estimate_of: Callable[[str], Estimate | None], rate: float, seconds: float
) -> tuple[tuple[int, int, float], ...]:
    """What the others in ``person``'s region probably believe (more likely than not) of
    each item, and the chance one of them told ``person`` in the last ``seconds``: ``rate``
    per second per pair, one item and one direction at a time. ``estimate_of``: the online
    estimate of another person (``None``: not tracked). Returns ``(item, value, chance)``."""
    region = next((a.region for a in state.agents if a.id == person), None)
    if rate <= 0 or region is None:
        return ()
    heard = []
    for other in state.agents:
        if other.id == person or other.region != region or (est := estimate_of(other.id)) is None:
            continue
        places = np.argmax(est.beliefs, axis=1)
        heard += [
            (k, value_of(int(places[k]))) for k in range(len(places)) if est.beliefs[k, places[k]] > 0.5
        ]
    chance = (1.0 - np.exp(-rate * max(seconds, 0.0))) / (2 * max(len(heard), 1))
    return tuple((k, value, float(chance)) for k, value in heard)
