"""Nested beliefs scored against simulated people's own (pure): what person A believes person
B believes, where it differs from what B believes.

Over every tick, person A, other person B and item whose truth says A is sure (most probable
location above 0.5) that B believes the item at one place while B (sure too) believes it
elsewhere, an observer's nested estimate is right when its most probable location is A's;
the first-order baseline answers with the observer's estimate of B's own belief, so it is
right only when it misreads B. Persons without a true mind (scripted ones) are not scored.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from protocol import Mind, Truth

from .metrics import Counts
from .scoredminds import ScoredMind

SURE = 0.5
"""A belief is definite when its most probable location has more than this."""


def _sure(locations: Mapping[str, float]) -> str | None:
    best = max(locations, key=lambda loc: (locations[loc], loc), default=None)
    return best if best is not None and locations[best] > SURE else None


def _argmax(locations: Sequence[tuple[str, float]]) -> str | None:
    return max(locations, key=lambda pair: pair[1])[0] if locations else None


def score_nested(mind: Mind | ScoredMind, truth: Truth, counts: Counts) -> None:
    """Add one tick's ``nested_n``, ``nested_right`` and ``nested_first_right`` to ``counts``."""
    own = {
        person.agent: {b.item: {p.id: p.p for p in b.locations} for b in person.beliefs}
        for person in truth.agents
    }
    estimates = {a.agent: a for a in mind.agents}
    for person in truth.agents:
        est = estimates.get(person.agent)
        for about in person.nested:
            theirs = own.get(about.agent)
            other = estimates.get(about.agent)
            if est is None or theirs is None or other is None:
                continue
            guesses = {n.agent: n.beliefs for n in est.nested_beliefs}.get(about.agent, ())
            nested = {b.item: [(p.id, p.p) for p in b.locations] for b in guesses}
            first = {b.item: [(p.id, p.p) for p in b.locations] for b in other.beliefs}
            for belief in about.beliefs:
                said = _sure({p.id: p.p for p in belief.locations})
                actual = _sure(theirs.get(belief.item, {}))
                if said is None or actual is None or said == actual:
                    continue
                counts.nested_n += 1
                counts.nested_right += _argmax(nested.get(belief.item, [])) == said
                counts.nested_first_right += _argmax(first.get(belief.item, [])) == said
