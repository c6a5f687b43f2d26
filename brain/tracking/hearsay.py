"""Hearsay: what a person may have heard of where items are from the others in their region
(``ModelSettings.hearsay_per_s``), as rumours the lapses model takes in as speech (pure). The
rule is sim2d's (:mod:`sim2d.people.hearsay`, whose ``hearsay_per_tick`` is this rate per
tick), read with the robot's estimates of the two people's beliefs."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from protocol import State

from ..model.arrays import FloatArray
from ..model.estimates import Estimate
from ..model.world import value_of


def rumours(
    state: State, person: str, estimate_of: Callable[[str], Estimate | None], rate: float, seconds: float
) -> tuple[tuple[int, int, float], ...]:
    """What ``person`` may have been told in the last ``seconds`` by the others in their region,
    by sim2d's rule (:mod:`sim2d.people.hearsay`, per second here): each pair talks at ``rate``
    per second; one of the two, at random, tells the other one item, drawn evenly from those
    the teller places elsewhere than the listener and is surer of (at least 0.5, and more than
    the listener is of their own place). Beliefs are the robot's online estimates
    (``estimate_of``; ``None``: not tracked, that person tells nothing; a listener not yet
    estimated is told what the teller is sure of). Returns ``(item, value, chance)``."""
    region = next((a.region for a in state.agents if a.id == person), None)
    if rate <= 0 or region is None:
        return ()
    mine = estimate_of(person)
    talk = 1.0 - np.exp(-rate * max(seconds, 0.0))
    heard = []
    for other in state.agents:
        if other.id == person or other.region != region or (est := estimate_of(other.id)) is None:
            continue
        told = tellable(est.beliefs, mine.beliefs if mine is not None else None)
        heard += [(k, value, float(talk / (2 * len(told)))) for k, value in told]
    return tuple(heard)


def tellable(teller: FloatArray, listener: FloatArray | None) -> list[tuple[int, int]]:
    """``(item, value)`` a teller with ``(K, L)`` beliefs ``teller`` may tell a listener with
    ``listener``: items the teller is sure of (at least 0.5) where the listener's likeliest
    place differs and the listener is less sure of it (sim2d's rule)."""
    places, sure = np.argmax(teller, axis=1), teller.max(axis=1)
    told = []
    for k in range(teller.shape[0]):
        if sure[k] < 0.5:
            continue
        if listener is not None and (np.argmax(listener[k]) == places[k] or listener[k].max() >= sure[k]):
            continue
        told.append((k, value_of(int(places[k]))))
    return told
