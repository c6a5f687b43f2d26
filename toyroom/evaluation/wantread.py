"""Reading the want where help matters: an observer's P(a person's true want) over the
stretches in which that person is after an item they believe falsely about (pure functions).

``preference_accuracy`` (:mod:`.metrics`) counts only the ticks after a person's first take,
most of them a person playing with the very item they want, where an observer with no theory
of mind scores as well. The robot's help matters earlier: from the first tick a person holds a
false belief (:func:`protocol.believes_falsely`) about the item they want (their true
preference, an item, not ``out``) to their first take of that item. A stretch also ends when
the want changes to another item (a new one may then start, if they believe falsely about the
new one) and at the episode's end; a person may have several stretches.

Per person-tick of a stretch three things are scored:

- ``p``: the observer's P(the person's true want);
- ``confident``: whether ``p`` is at least :data:`protocol.PREFERENCE_THRESHOLD`, the
  probability at which the robot acts on a read want;
- ``top``: whether the true want is the observer's most probable goal, a tie of ``n`` goals
  counting ``1/n``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from protocol import PREFERENCE_THRESHOLD, Mind, Truth, believes_falsely

from .scoredminds import ScoredMind


@dataclass(frozen=True)
class WantScore:
    """One person-tick's reading of the want."""

    p: float
    """P(the true want), 0 to 1 (0 where the observer gives the want no probability)."""
    confident: bool
    """``p`` >= :data:`protocol.PREFERENCE_THRESHOLD`."""
    top: float
    """1/n when the true want is among the observer's ``n`` most probable goals, else 0."""


def _false_belief_about(truth: Truth, person: str, item: str, where: Mapping[str, str]) -> bool:
    place = where.get(item)
    for agent in truth.agents:
        if agent.agent != person:
            continue
        for belief in agent.beliefs:
            if belief.item == item and place is not None:
                return believes_falsely({p.id: p.p for p in belief.locations}, place)
    return False


def want_stretches(
    truths: Mapping[int, Truth], takes: Iterable[tuple[int, str, str]]
) -> dict[int, frozenset[str]]:
    """Tick -> the people in a want stretch then (see the module's docstring).

    Args:
        truths: the people's true minds by tick.
        takes: ``(tick, person, item)`` of every take, in any order.
    """
    took = {(tick, person, item) for tick, person, item in takes}
    after: dict[str, str] = {}
    """Per person in a stretch, the item it is about."""
    out: dict[int, frozenset[str]] = {}
    for tick in sorted(truths):
        truth = truths[tick]
        items = {place.item for place in truth.items}
        where = {place.item: place.location for place in truth.items}
        for agent in truth.agents:
            item = after.get(agent.agent)
            if item is not None and (item != agent.preference or (tick, agent.agent, item) in took):
                del after[agent.agent]
            want = agent.preference
            if agent.agent not in after and want in items and (tick, agent.agent, want) not in took:
                if _false_belief_about(truth, agent.agent, want, where):
                    after[agent.agent] = want
        out[tick] = frozenset(after)
    return out


def score_want(mind: Mind | ScoredMind, truth: Truth, people: frozenset[str]) -> list[WantScore]:
    """The observer's reading of the want of each person of ``people`` at this tick (people
    the observer does not estimate are left out)."""
    wants = {agent.agent: agent.preference for agent in truth.agents if agent.agent in people}
    scores = []
    for estimate in mind.agents:
        want = wants.get(estimate.agent)
        if want is None:
            continue
        chances = {p.id: p.p for p in estimate.preference}
        p = chances.get(want, 0.0)
        best = max(chances.values(), default=0.0)
        tied = [goal for goal, q in chances.items() if q == best]
        top = 1.0 / len(tied) if chances and want in tied else 0.0
        scores.append(WantScore(p=p, confident=p >= PREFERENCE_THRESHOLD, top=top))
    return scores
