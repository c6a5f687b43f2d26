"""What an autonomous person is doing, read off their plan: the steps of a plan
(:class:`Primitive`), the pursuit they add up to (``engine/truth``'s ``pursuit``), and when a
change of belief makes a walk under way pointless (so the person decides again, after their
lag: :class:`Reconsider`)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from protocol import Pursuit

from ..world.world import World
from .belief import PersonBelief


@dataclass(frozen=True)
class Primitive:
    """One step of a plan: ``goto`` a cell, ``take`` / ``drop``, or ``play`` / ``wait`` for ticks."""

    do: str
    cell: tuple[int, int] | None = None
    item: str | None = None
    location: str | None = None
    ticks: int = 0
    errand: bool = False
    """Part of an errand: carried through even when told where the wanted item is."""


def pursuit_of(steps: Iterable[Primitive], world: World, here: tuple[int, int]) -> Pursuit | None:
    """The pursuit of a plan's ``steps`` (the step under way first) for a person at cell
    ``here``: the item of the plan's next take, if nothing is dropped before it, and the item
    location of its first walk (or of ``here``, when the next step is a take or a drop on the
    spot); ``None`` when there is neither (standing, playing, going outside)."""
    item: str | None = None
    location: str | None = None
    moving = True
    for step in steps:
        if step.do == "drop":
            location = location if not moving else step.location
            break
        if step.do == "take":
            item = step.item
            if moving:
                spot = world.location_at.get(here)
                location = spot.id if spot is not None else None
            break
        if step.do == "goto" and moving:
            spot = world.location_at.get(step.cell) if step.cell is not None else None
            location, moving = (spot.id if spot is not None else None), False
        elif step.do in ("wait", "play") and moving:
            return None
    if item is None and location is None:
        return None
    return Pursuit(item=item, location=location)


def pointless(pursuit: Pursuit | None, belief: PersonBelief) -> bool:
    """Whether the person's belief no longer sends them where they are heading for the item
    they are after: the place has less than half the probability of the likeliest one."""
    if pursuit is None or pursuit.item is None or pursuit.location is None:
        return False
    row = belief.of(pursuit.item)
    return bool(row[belief.locations.index(pursuit.location)] < 0.5 * row.max())


class Reconsider:
    """A person's lag between seeing that a walk is pointless and deciding again: drawn once
    (uniformly in ``bounds``, ticks) the first time it is needed."""

    def __init__(self, bounds: tuple[int, int]) -> None:
        self.bounds = bounds
        self.lag: int | None = None
        self.due: int | None = None
        """The tick the person decides again, while a reconsideration is pending."""

    def check(self, stale: bool, tick: int, rng: np.random.Generator) -> bool:
        """Note at ``tick`` whether the walk is pointless (``stale``); ``True`` when the lag
        since it became so has run out (the pending reconsideration is then done). A walk that
        is no longer pointless cancels it."""
        if not stale:
            self.due = None
            return False
        if self.due is None:
            if self.lag is None:
                self.lag = int(rng.integers(self.bounds[0], self.bounds[1] + 1))
            self.due = tick + self.lag
        if tick >= self.due:
            self.due = None
            return True
        return False
