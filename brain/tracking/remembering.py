"""A tracker's start from the memory of earlier days (:mod:`brain.memory`), and what it gives
the memory back: where the robot itself believes each item rests. Pure; no I/O."""

from __future__ import annotations

import logging
from collections.abc import Sequence

import numpy as np

from ..memory.priors import remembered, view_log_prior
from ..memory.snapshot import Distribution, Snapshot
from ..model.arrays import FloatArray
from ..model.estimates import OUT
from ..model.person.gradedperson import GradedModel
from ..model.person.personinterface import PersonModel
from ..model.person.remembered import Remembered
from ..model.world import WorldModel, location_of
from ..settings import ModelSettings
from .itemview import ItemView
from .worldview import WorldView

log = logging.getLogger("toyroom.brain")


def remembered_people(
    memory: Snapshot, person_model: PersonModel, people: Sequence[str], settings: ModelSettings
) -> dict[str, Remembered]:
    """Person -> what their model starts from, for the people of the scene the memory holds
    (graded models: the others start each day afresh, which is logged)."""
    if not isinstance(person_model, GradedModel):
        log.warning(
            "the %s model starts each day afresh: graded models read the memory", settings.belief_model
        )
        return {}
    model = person_model.model
    goals, utilities = [*model.items, OUT], person_model.policy.utilities
    return {
        p.person: remembered(
            p.preference, p.beliefs, goals, utilities, model.items, model.locations, settings.memory_drift
        )
        for p in memory.people
        if p.person in people
    }


def start_view(
    view: WorldView | ItemView, model: WorldModel, memory: Snapshot, settings: ModelSettings
) -> None:
    """Weigh an embodied robot's hypotheses of where items rest by where it remembers them
    (the factored view: each item's prior over its origins, :class:`.itemview.ItemView`)."""
    if not memory.items:
        return
    if isinstance(view, WorldView):
        view.log_prior = view_log_prior(
            view.rows, model.items, model.locations, memory.items, settings.memory_forget
        )
        return
    spots = np.arange(model.n_locations)[:, None]  # (L, 1): one row per origin of one item
    for k, item in enumerate(model.items):
        log_p = view_log_prior(spots, [item], model.locations, memory.items, settings.memory_forget)
        weighed = view.prior[k] * np.exp(log_p)
        if weighed.sum() > 0:
            view.prior[k] = weighed / weighed.sum()
    view.origin = view.prior.copy()


def robot_items(
    model: WorldModel,
    truth: tuple[int, ...],
    branch_truths: Sequence[tuple[int, ...]],
    weights: FloatArray | None,
) -> dict[str, Distribution]:
    """Item id -> where the robot believes it rests (location id -> probability): the truth it
    sees (``weights`` ``None``), or an embodied view's branches weighed by ``weights``; a
    carried item counts where its carrier's location is."""
    if weights is None:
        return {
            item: {model.locations[location_of(v)]: 1.0} for item, v in zip(model.items, truth, strict=False)
        }
    known: dict[str, Distribution] = {}
    for k, item in enumerate(model.items):
        where: Distribution = {}
        for values, w in zip(branch_truths, weights, strict=True):
            place = model.locations[location_of(values[k])]
            where[place] = where.get(place, 0.0) + float(w)
        known[item] = where
    return known
