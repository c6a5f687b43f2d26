"""Writing a run's results: ``mind.csv``, the figures and ``report.md``, and the ``mind``
message the brain publishes every tick."""

from __future__ import annotations

import itertools
import weakref
from collections.abc import Sequence
from pathlib import Path

import msgspec
import numpy as np

from protocol import (
    AgentMind,
    Desire,
    GoalUtility,
    Intention,
    ItemBelief,
    Mind,
    NestedBelief,
    Placement,
    Preferred,
    Prob,
    RobotActivity,
    State,
    WorldBelief,
)

from ..model.arrays import FloatArray
from ..model.desires import DesireSummary
from ..model.estimates import OUT, Estimate
from ..model.modes import MODE_NAMES, on_the_wire
from ..model.nested import NestedBeliefs
from ..model.world import WorldModel, is_held, location_of
from ..tracking.tracker import MindTracker
from .finite import check_estimate, check_rows
from .groundtruth import load_ground_truth
from .mindtable import mind_rows, write_csv
from .report import write_report

MindCache = dict[str, tuple[Estimate, AgentMind]]
"""Person -> their last estimate and its part of the message (reused while the tracker hands
out the same estimate: on most ticks nobody stepped and nothing moved)."""


def mind_message(
    tracker: MindTracker, state: State, robot: RobotActivity | None = None, cache: MindCache | None = None
) -> Mind:
    """The online estimates of every person (and what the robot does), as a ``mind`` message
    (``cache``: the caller's, kept between ticks).

    Raises:
        NonFiniteError: a person's estimate holds NaN or an infinity (naming them, the
            quantity and the tick): the brain fails rather than publish a message that every
            subscriber would drop.
    """
    agents = []
    nested_of = nested_messages(tracker)
    for person in tracker.people:
        est = tracker.online(person)
        if est is None:
            continue
        kept = cache.get(person) if cache is not None else None
        nested = nested_of.get(person, ())
        if kept is not None and kept[0] is est:  # the same estimate: at most the nested part is new
            if kept[1].nested_beliefs != nested:
                kept = (est, msgspec.structs.replace(kept[1], nested_beliefs=nested))
                cache[person] = kept  # type: ignore[index]
            agents.append(kept[1])
            continue
        check_estimate(tracker.model, person, state.tick, est)  # NaN is never published
        agents.append(agent_mind(tracker, person, est, nested))
        if cache is not None:
            cache[person] = (est, agents[-1])
    robots = (robot,) if robot is not None else ()
    return Mind(episode=state.episode, tick=state.tick, agents=tuple(agents), robots=robots)


_nested_kept: weakref.WeakKeyDictionary[NestedBeliefs, tuple[bytes, dict[str, tuple[NestedBelief, ...]]]] = (
    weakref.WeakKeyDictionary()
)
"""Per nested-belief filter, its last rounded ``(P, K, L)`` array (as bytes) and the messages
built of it: most ticks the rounded numbers are the tick before's, and so are the messages."""


def nested_messages(tracker: MindTracker) -> dict[str, tuple[NestedBelief, ...]]:
    """Per person, where they believe each other person believes each item is, at the last
    tick (empty before the first). The result is shared between ticks: do not change it."""
    nested = tracker.nested
    if nested.values is None:
        return {}
    rounded = np.round(nested.all_locations(), 6)
    key = rounded.tobytes()
    kept = _nested_kept.get(nested)
    if kept is not None and kept[0] == key:
        return kept[1]
    out: dict[str, list[NestedBelief]] = {}
    for (a, b), rows in zip(nested.pairs, rounded.tolist(), strict=True):
        out.setdefault(a, []).append(NestedBelief(agent=b, beliefs=item_beliefs(tracker.model, rows)))
    messages = {person: tuple(beliefs) for person, beliefs in out.items()}
    _nested_kept[nested] = (key, messages)
    return messages


def item_beliefs(model: WorldModel, rows: list[list[float]]) -> tuple[ItemBelief, ...]:
    """``(K, L)`` rows of probabilities (already rounded) as the protocol's ``ItemBelief`` list."""
    return tuple(
        ItemBelief(item=item, locations=tuple(map(Prob, model.locations, row)))
        for item, row in zip(model.items, rows, strict=True)
    )


def agent_mind(
    tracker: MindTracker, person: str, est: Estimate, nested: tuple[NestedBelief, ...] = ()
) -> AgentMind:
    """One person's part of the ``mind`` message (``nested``: its entry of :func:`nested_messages`)."""
    model = tracker.model
    # rounded as arrays, then read as Python floats: a round() per number is most of the cost
    beliefs = item_beliefs(model, np.round(np.asarray(est.beliefs, dtype=np.float64), 6).tolist())
    preference = tuple(map(Prob, (*model.items, OUT), np.round(est.preference, 6).tolist()))
    item_index, location_index, p = est.intention
    intention = Intention(
        item=model.items[item_index] if item_index is not None else None,
        location=model.locations[location_index] if location_index is not None else None,
        p=round(min(max(p, 0.0), 1.0), 6),
    )
    return AgentMind(
        agent=person,
        beliefs=beliefs,
        preference=preference,
        intention=intention,
        false_beliefs=tuple(model.items[k] for k in est.false_beliefs),
        false_belief=tuple(map(Prob, model.items, np.round(np.clip(est.false_belief, 0.0, 1.0), 6).tolist())),
        desire=desire_message(est.desire, (*model.items, OUT)),
        worlds=tuple(
            WorldBelief(
                items=tuple(
                    Placement(item, model.locations[location_of(v)], bool(is_held(v)))
                    for item, v in zip(model.items, model.worlds[w], strict=True)
                ),
                p=round(min(max(p, 0.0), 1.0), 6),
            )
            for w, p in est.top_worlds(tracker.settings.top_worlds)
        ),
        nested_beliefs=nested,
        **_modes(model.items, est.mode),
    )


def _modes(items: Sequence[str], mode: FloatArray | None) -> dict[str, tuple[Prob, ...]]:
    """The ``mode`` and ``carry`` fields of a person's mind (none without modes)."""
    if mode is None:
        return {}
    modes, carry = on_the_wire(mode)
    return {
        "mode": tuple(map(Prob, MODE_NAMES, np.round(modes, 6).tolist())),
        "carry": tuple(map(Prob, items, np.round(carry, 6).tolist())),
    }


def desire_message(summary: DesireSummary | None, goals: Sequence[str]) -> Desire | None:
    """The ``desire`` field of a person's mind (``None`` without a summary)."""
    if summary is None:
        return None
    best = summary.ranking

    def p(value: float) -> float:
        return round(min(max(float(value), 0.0), 1.0), 6)

    return Desire(
        utility=tuple(
            GoalUtility(goal, round(float(u), 6)) for goal, u in zip(goals, summary.utility, strict=True)
        ),
        preferred=tuple(
            Preferred(goals[a], goals[b], p(summary.preferred[a, b]))
            for a, b in itertools.combinations(range(len(goals)), 2)
        ),
        ranking=tuple(tuple(goals[d] for d in group) for group in best),
        p=p(summary.probability(best)),
    )


def write_outputs(tracker: MindTracker, scenario: str, out: Path, recording_note: str = "") -> Path:
    """Write ``mind.csv``, ``beliefs.png``, ``preferences.png`` and ``report.md`` into ``out``
    (``recording_note``: the report's first paragraph when the recording was not whole)."""
    out.mkdir(parents=True, exist_ok=True)
    rows = mind_rows(tracker)
    check_rows((r.tick, r.agent, r.quantity, r.item, r.p_online, r.p_smoothed) for r in rows)
    write_csv(rows, out / "mind.csv")
    write_report(
        rows,
        scenario,
        tracker.observer.value,
        load_ground_truth(scenario),
        out,
        exact=tracker.exact,
        recording_note=recording_note,
    )
    return out / "mind.csv"
