"""One colour per person, the same on every page of a study and in the live view: the
``n``-th person of the scene's agents gets the live view's ``n``-th person colour
(:func:`toyroom.view.colours.person_colour`), on the play page as on the rating page (before
issue 55, A1 was orange on one and blue on the other)."""

from __future__ import annotations

from collections.abc import Sequence

from toyroom.view.colours import person_colour


def person_colours(people: Sequence[str]) -> dict[str, str]:
    """Person id -> its colour as ``#rrggbb`` (``people`` in the scene's order)."""
    return {person: f"#{person_colour(n):06x}" for n, person in enumerate(people)}
