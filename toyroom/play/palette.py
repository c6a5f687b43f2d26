"""One colour per person, the same on every page of a study (``toyroom play`` and ``toyroom
rate``): the ``n``-th person of the scene's agents gets the ``n``-th colour."""

from __future__ import annotations

from collections.abc import Sequence

PEOPLE = ("#d9480f", "#1c7ed6", "#7048e8", "#2b8a3e", "#c2255c", "#0b7285", "#5f3dc4", "#e67700")
"""Colours for people, in the scene's order (wrapping round after eight)."""
ROBOT = "#495057"


def person_colours(people: Sequence[str]) -> dict[str, str]:
    """Person id -> its colour (``people`` in the scene's order)."""
    return {person: PEOPLE[n % len(PEOPLE)] for n, person in enumerate(people)}
