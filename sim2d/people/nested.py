"""What a simulated person believes the others believe (nested beliefs, for ``engine/truth``).

Person A keeps, for each other person B, a :class:`~sim2d.people.belief.PersonBelief` of what
B believes: while A sees B (the protocol's "who sees whom": where A would see an item B
carries, :class:`protocol.carry.CarrierSight`), it takes in what B sees, as B's own belief
does; while A does not, it stays as it was. It starts as B's own belief at A's first tick (A
knows what B knew before the episode). B's lapses (an item overlooked, a word heard) are
B's own: A's model of B does not have them.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from ..world.world import World
from .belief import PersonBelief


class NestedMinds:
    """One person's beliefs about the beliefs of ``others``."""

    def __init__(
        self, me: str, others: Sequence[str], items: Sequence[str], locations: Sequence[str]
    ) -> None:
        self.me = me
        self.beliefs = {other: PersonBelief(items, locations) for other in others}
        self.started = False

    def observe(self, world: World, belief_of: Callable[[str], np.ndarray | None]) -> None:
        """One tick: take in what each other person sees while this one sees them
        (``belief_of(other)``: their own belief ``(K, L)``, read at the first tick)."""
        if not self.started:
            self.started = True
            for other, model in self.beliefs.items():
                own = belief_of(other)
                if own is not None:
                    model.p = own.copy()
        cell, visible = world.agents[self.me].cell, world.percept(self.me)[0]
        for other, model in self.beliefs.items():
            if world.sight.sees(cell, visible, world.agents[other].cell):
                their_visible, their_seen = world.percept(other)
                model.perceive(their_visible, their_seen)
