"""What a person answered the robot (protocol 1.6's ``answer`` events), as the likelihood
the tracker hands their filter (:func:`brain.model.answers.answer_likelihood`)."""

from __future__ import annotations

from collections.abc import Sequence

from protocol import Event, EventKind

from ..model.answers import answer_likelihood
from ..model.arrays import FloatArray
from ..settings import ModelSettings


def answered(
    items: Sequence[str],
    person: str,
    robot: str | None,
    events: Sequence[Event],
    settings: ModelSettings,
    said: FloatArray | None = None,
) -> FloatArray | None:
    """``said`` (``(D,)``, what ``person`` answered before, or ``None``) times the likelihood of
    everything they answered ``robot`` in ``events``, over their favourite goal (``items``
    then ``out``; ``settings.answer_reliability``); ``None`` when there is nothing. An answer
    about an item the scene does not have is no evidence."""
    reliability = settings.answer_reliability
    for event in events:
        if event.kind != EventKind.ANSWER or event.actor != person or event.target != robot:
            continue
        if event.item is not None and event.item not in items:
            continue
        item = None if event.item is None else list(items).index(event.item)
        one = answer_likelihood(len(items) + 1, item, bool(event.answer), reliability)
        said = one if said is None else said * one
    return said
