"""The ``oracle`` robot's minds: each simulated person's estimate read off the engine's truth
(``engine/truth``), not inferred (pure functions).

The ``oracle`` policy (:class:`protocol.Policy`) reads the simulated people's true minds: an
upper bound, not a robot one could build. It ticks ``tom``'s tree on these estimates, so that
``tom`` against ``oracle`` measures what reading minds loses and ``oracle`` against the robot
observing what acting on them gains. Per person of the truth:

- ``beliefs``: their true belief (``TrueMind.beliefs``, over the model's locations);
- ``preference``: one-hot on their true want (an item, else ``out``);
- ``false_belief``: 1 for each item their belief holds falsely by the one rule
  (:func:`protocol.believes_falsely`, against where the truth says the item is), else 0;
- ``intention``: what they are after now: their pursuit's item and location when the engine
  tells it (``(None, None, 1)``: after no item), else the likeliest place of the item they
  want (``(None, None, 1)`` for ``out``), as the inferred estimates read it.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from protocol import FALSE_BELIEF_MASS, TrueMind, Truth, believes_falsely

from ..model.arrays import first_max
from ..model.estimates import Estimate
from ..model.world import WorldModel


def oracle_estimates(truth: Truth, model: WorldModel, mass: float = FALSE_BELIEF_MASS) -> dict[str, Estimate]:
    """Person id -> their :class:`~brain.model.estimates.Estimate` read off ``truth`` (every
    person the truth tells of; ``mass``: the false-belief rule's, the evaluation's by default)."""
    where = {place.item: place.location for place in truth.items}
    return {mind.agent: true_estimate(mind, where, model, mass) for mind in truth.agents}


def true_estimate(
    mind: TrueMind, where: Mapping[str, str], model: WorldModel, mass: float = FALSE_BELIEF_MASS
) -> Estimate:
    """One person's estimate from their true mind (see the module); ``where``: item id -> the
    location it truly is at (an item missing from it counts no false belief)."""
    K, L = model.n_items, model.n_locations
    beliefs = np.zeros((K, L))
    false_belief = np.zeros(K)
    column = {location: index for index, location in enumerate(model.locations)}
    for belief in mind.beliefs:
        if belief.item not in model.items:
            continue
        k = model.items.index(belief.item)
        for prob in belief.locations:
            if prob.id in column:
                beliefs[k, column[prob.id]] += prob.p
        held = {prob.id: prob.p for prob in belief.locations}
        if belief.item in where and held and believes_falsely(held, where[belief.item], mass):
            false_belief[k] = 1.0
    preference = np.zeros(K + 1)
    wanted = model.items.index(mind.preference) if mind.preference in model.items else None
    preference[K if wanted is None else wanted] = 1.0
    return Estimate(
        beliefs=beliefs,
        preference=preference,
        intention=_intention(mind, wanted, beliefs, model),
        false_belief=false_belief,
    )


def _intention(
    mind: TrueMind, wanted: int | None, beliefs: np.ndarray, model: WorldModel
) -> tuple[int | None, int | None, float]:
    """What the person is after: their pursuit when the engine tells it, else the likeliest
    believed place of what they want (``Estimate.intention``'s form)."""
    pursuit = mind.pursuit
    if pursuit is not None:
        if pursuit.item is None or pursuit.item not in model.items:
            return None, None, 1.0
        location = model.locations.index(pursuit.location) if pursuit.location in model.locations else None
        return model.items.index(pursuit.item), location, 1.0
    if wanted is None:
        return None, None, 1.0
    location = first_max(beliefs[wanted])
    return wanted, location, float(beliefs[wanted, location])
