"""What a household's day starts from: the night before, as the engine's truth left it.

A household (``Scene.household``) is the same map, people and items lived over days. The
generator of a day (``python -m sim2d generate --day D --morning FILE``) reads a
:class:`Morning` (JSON): where each item rests, what each person is sure of and what each
wants most, at the end of the day before; it then applies the night's changes and the day's
jobs. An evaluator makes one from the last ``engine/truth`` of a day (:func:`morning_of`).
"""

from __future__ import annotations

import msgspec

from .truth import Truth

MAX_DAYS = 99
"""The most days a household is lived (a generator keeps each day's seed apart from every
other household's while days stay below 100)."""
SURE = 0.5
"""A person is carried into the next day sure of an item's place when their belief gives it
more than this (else they start the day not knowing where it is)."""


class Morning(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """The end of a household's day, to start the next from.

    Attributes:
        items: item id -> the location id it rests at (a carried item: where it counts).
        beliefs: person id -> item id -> the location they are sure of (items they are not
            sure of are left out).
        favourites: person id -> the goal they want most (an item id, or ``out``).
        household: the household's id (``Scene.household.id``), and ``map`` its map's name:
            a generator refuses a morning of another household or map (and one that names
            neither: a morning written before they were required).
    """

    items: dict[str, str]
    beliefs: dict[str, dict[str, str]] = {}
    favourites: dict[str, str] = {}
    household: str | None = None
    map: str | None = None


def morning_of(truth: Truth) -> Morning:
    """The :class:`Morning` after the last ``truth`` of a day."""
    beliefs = {
        mind.agent: {
            b.item: best.id
            for b in mind.beliefs
            if b.locations and (best := max(b.locations, key=lambda p: p.p)).p > SURE
        }
        for mind in truth.agents
    }
    return Morning(
        items={place.item: place.location for place in truth.items},
        beliefs=beliefs,
        favourites={mind.agent: mind.preference for mind in truth.agents},
    )
