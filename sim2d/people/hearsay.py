"""Hearsay: simulated people who meet tell each other where things are.

Each tick, for every pair of autonomous people in one region, with probability
``Autonomy.hearsay_per_tick`` one of them (at random) tells the other where they believe an item is,
chosen at random among the items the two place differently (most probable location) that
the teller is sure of (at least :data:`SURE` there) and surer of than the listener is of
their own most probable place. The listener takes it as the robot's ``inform`` is taken:
the belief about that item is replaced (so a teller sure of a wrong place spreads a false
belief). Nothing is published: the robot does not hear it.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np

from ..world.world import World
from .autonomous import AutonomousPerson

SURE = 0.5
"""How sure a teller must be of where an item is to tell it."""


def exchange(people: Sequence[AutonomousPerson], world: World, rng: np.random.Generator, rate: float) -> None:
    """One tick of hearsay among ``people`` (nothing happens, and nothing is drawn, at rate 0)."""
    if rate <= 0:
        return
    for a, b in itertools.combinations(people, 2):
        if world.agents[a.id].region != world.agents[b.id].region or rng.random() >= rate:
            continue
        teller, listener = (a, b) if rng.random() < 0.5 else (b, a)
        differ = [
            item
            for item in teller.belief.items
            if teller.belief.most_likely(item) != listener.belief.most_likely(item)
            and teller.belief.sureness(item) >= max(SURE, listener.belief.sureness(item) + 1e-9)
        ]
        if not differ:
            continue
        item = differ[int(rng.integers(len(differ)))]
        location = teller.belief.most_likely(item)
        assert location is not None
        listener.on_informed(world, item, location)


def tell_jobs(people: Sequence[AutonomousPerson], world: World) -> None:
    """The tellings a task episode scripts (:attr:`~sim2d.scenario.jobs.Jobs.tells`): from its
    ``tell_after`` tick on, once both are in one region, the teller tells the listener where
    they believe the item is (unheard by the robot, as hearsay is)."""
    by_id = {person.id: person for person in people}
    for teller in people:
        if teller.tells is None or world.tick < teller.tell_after:
            continue
        name, item = teller.tells
        listener, where = by_id.get(name), teller.belief.most_likely(item)
        if listener is None or where is None or world.agents[name].region != world.agents[teller.id].region:
            continue
        teller.tells = None
        listener.on_informed(world, item, where)
