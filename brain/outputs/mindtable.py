"""``mind.csv``: the online and smoothed estimates of every person at every tick.

Header ``tick,label,agent,quantity,item,value,p_online,p_smoothed``. Per tick and person:
one ``belief`` row per item and location (``value`` = the location id), then one
``preference`` row per item and one for ``out`` (``value`` empty), then one ``false_belief``
row per item (``value`` empty): the probability that the person's belief gives the item's
true location at that tick less than ``ModelSettings.false_belief_mass``, then the ``desire``
rows (:func:`_desire_rows`: expected utilities, pairwise preferences, the most probable
ranking), the ``world`` rows (:func:`_world_rows`), the ``nested_belief`` rows
(:func:`_nested_rows`: where the person believes each other person believes each item is,
``value`` = ``OTHER:location``) and one ``log_evidence`` row: the
marginal log-likelihood of the person's decisions up to that tick (``p_online``; natural
log, not a probability) and over the whole run (``p_smoothed``). ``label`` is the
scenario step the person completed at that tick, else empty. Between a person's steps the
last estimate is carried forward (false beliefs are read against each tick's truth); with an
embodied robot that is the branches' mixture as weighed at the step, where the live ``mind``
messages (:meth:`MindTracker.online`) re-weigh the branches every tick.
"""

from __future__ import annotations

import bisect
import csv
import io
import itertools
from dataclasses import dataclass
from pathlib import Path

from bridge.recording.atomic import write_text

from ..model.arrays import FloatArray
from ..model.desires import ranking_text
from ..model.estimates import OUT, Estimate, false_belief_probability, world_text
from ..model.nested import smoothed_nested
from ..tracking.tracker import MindTracker

HEADER = ("tick", "label", "agent", "quantity", "item", "value", "p_online", "p_smoothed")


@dataclass(frozen=True)
class MindRow:
    """One row of ``mind.csv``."""

    tick: int
    label: str
    agent: str
    quantity: str
    item: str
    value: str
    p_online: float
    p_smoothed: float

    def cells(self) -> tuple[str, ...]:
        return (
            str(self.tick),
            self.label,
            self.agent,
            self.quantity,
            self.item,
            self.value,
            f"{self.p_online:.6f}",
            f"{self.p_smoothed:.6f}",
        )


def mind_rows(tracker: MindTracker) -> list[MindRow]:
    """Every row, in tick order, for every person the tracker follows."""
    model = tracker.model
    smoothed = {person: tracker.smoothed(person) for person in tracker.people}
    nested_smooth = _smoothed_nested(tracker, smoothed)
    rows: list[MindRow] = []
    cursor = dict.fromkeys(tracker.people, -1)
    for tick in tracker.ticks:
        for person in tracker.people:
            track = tracker.tracks[person]
            i = cursor[person]
            while i + 1 < len(track.steps) and track.steps[i + 1].tick <= tick:
                i += 1
            cursor[person] = i
            if i < 0:
                continue
            online: Estimate = track.estimates[i]
            smooth: Estimate = smoothed[person][i]
            label = tracker.labels.get((tick, person), "")
            for k, item in enumerate(model.items):
                for li, location in enumerate(model.locations):
                    rows.append(
                        MindRow(
                            tick,
                            label,
                            person,
                            "belief",
                            item,
                            location,
                            float(online.beliefs[k, li]),
                            float(smooth.beliefs[k, li]),
                        )
                    )
            for d, name in enumerate((*model.items, OUT)):
                rows.append(
                    MindRow(
                        tick,
                        label,
                        person,
                        "preference",
                        name,
                        "",
                        float(online.preference[d]),
                        float(smooth.preference[d]),
                    )
                )
            rows += _false_belief_rows(tracker, tick, label, person, online, smooth)
            rows += _desire_rows(tracker, tick, label, person, online, smooth)
            rows += _world_rows(tracker, tick, label, person, online, smooth)
            rows += _nested_rows(tracker, tick, label, person, nested_smooth.get(tick))
            total = track.estimates[-1].log_evidence
            rows.append(MindRow(tick, label, person, "log_evidence", "", "", online.log_evidence, total))
    return rows


def _smoothed_nested(tracker: MindTracker, smoothed: dict[str, list[Estimate]]) -> dict[int, FloatArray]:
    """Tick -> the nested beliefs' backward pass, ``(P, K, L)`` (:func:`smoothed_nested`: their
    filter again, leaning on the smoothed first-order beliefs)."""
    steps = {p: [s.tick for s in tracker.tracks[p].steps] for p in tracker.people}

    def belief_at(n: int, person: str) -> FloatArray | None:
        i = bisect.bisect_right(steps.get(person, []), tracker.ticks[n]) - 1
        return smoothed[person][i].beliefs if i >= 0 else None

    if len(tracker.nested.inputs) != len(tracker.ticks):  # not fed tick by tick: no backward pass
        return {}
    return dict(zip(tracker.ticks, smoothed_nested(tracker.nested, belief_at), strict=True))


def _nested_rows(
    tracker: MindTracker, tick: int, label: str, person: str, smooth: FloatArray | None
) -> list[MindRow]:
    """``nested_belief`` rows: per other person B, item and location, where ``person``
    believes B believes the item is (``value`` = ``B:location``), online and smoothed
    (:func:`brain.model.nested.smoothed_nested`; online again where there is no backward pass)."""
    nested = tracker.nested_ticks.get(tick)
    if nested is None:
        return []
    after = smooth if smooth is not None else nested
    model, rows = tracker.model, []
    for n, (a, b) in enumerate(tracker.nested.pairs):
        if a != person:
            continue
        for k, item in enumerate(model.items):
            for li, location in enumerate(model.locations):
                p, q = float(nested[n, k, li]), float(after[n, k, li])
                rows.append(MindRow(tick, label, person, "nested_belief", item, f"{b}:{location}", p, q))
    return rows


def _world_rows(
    tracker: MindTracker, tick: int, label: str, person: str, online: Estimate, smooth: Estimate
) -> list[MindRow]:
    """``world`` rows: the online estimate's ``top_worlds`` most probable whole worlds of the
    person's belief (``item`` = rank from 1, ``value`` e.g. ``skate@S1;ball@P2``), each with its
    probability online and smoothed."""
    if smooth.worlds is None:
        return []
    return [
        MindRow(
            tick, label, person, "world", str(rank), world_text(tracker.model, w), p, float(smooth.worlds[w])
        )
        for rank, (w, p) in enumerate(online.top_worlds(tracker.settings.top_worlds), start=1)
    ]


def _desire_rows(
    tracker: MindTracker, tick: int, label: str, person: str, online: Estimate, smooth: Estimate
) -> list[MindRow]:
    """``desire`` rows: per goal its expected utility (``value = utility``; a utility, not a
    probability), per pair of goals ``a`` before ``b`` P(a preferred to b) (``value = b``),
    and the online estimate's most probable ranking (``item = ranking``, ``value`` e.g.
    ``ball>skate>out``) with its probability online and smoothed."""
    if online.desire is None or smooth.desire is None:
        return []
    goals = (*tracker.model.items, OUT)
    on, sm = online.desire, smooth.desire
    rows = [
        MindRow(tick, label, person, "desire", goal, "utility", float(on.utility[d]), float(sm.utility[d]))
        for d, goal in enumerate(goals)
    ]
    for a, b in itertools.combinations(range(len(goals)), 2):
        rows.append(
            MindRow(
                tick,
                label,
                person,
                "desire",
                goals[a],
                goals[b],
                float(on.preferred[a, b]),
                float(sm.preferred[a, b]),
            )
        )
    best = on.ranking
    rows.append(
        MindRow(
            tick,
            label,
            person,
            "desire",
            "ranking",
            ranking_text(best, goals),
            on.probability(best),
            sm.probability(best),
        )
    )
    return rows


def _false_belief_rows(
    tracker: MindTracker, tick: int, label: str, person: str, online: Estimate, smooth: Estimate
) -> list[MindRow]:
    """One ``false_belief`` row per item, read against the truth at ``tick``."""
    truth, mass = tracker.truths[tick], tracker.settings.false_belief_mass
    p_online = false_belief_probability(online, truth, mass)
    p_smooth = false_belief_probability(smooth, truth, mass)
    return [
        MindRow(tick, label, person, "false_belief", item, "", float(p_online[k]), float(p_smooth[k]))
        for k, item in enumerate(tracker.model.items)
    ]


def render_csv(rows: list[MindRow]) -> str:
    """The CSV text of ``rows`` with its header."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(HEADER)
    writer.writerows(row.cells() for row in rows)
    return buffer.getvalue()


def write_csv(rows: list[MindRow], path: Path) -> None:
    """Write ``mind.csv``, whole or not at all (a full disk leaves none half written).

    Raises:
        OutputError: it could not be written."""
    write_text(path, render_csv(rows))
