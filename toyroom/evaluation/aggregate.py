"""From every episode's results to one condition's numbers (pure functions): pooled metrics
per observer with bootstrap 95% intervals paired by episode, and per robot policy the help
people got (:mod:`toyroom.evaluation.helpfulness`), paired the same way, with its cut against
the robot observing and its share of the ``oracle``'s cut (:data:`CUTS`)."""

from __future__ import annotations

import dataclasses
from collections.abc import Collection, Mapping, Sequence

from protocol import OBSERVING, Observer, Policy

from .conditions import Condition
from .intervals import METRICS as INTERVAL_METRICS
from .intervals import cuts, intervals, pooled_means
from .metrics import Counts, EpisodeOutcome, majority_counts
from .records import EpisodeRecord, RunKey, RunScores
from .summary import (
    CUTS,
    HELP,
    LOSSES,
    NO_INTERVAL,
    HelpMeasures,
    Interval,
    ObserverScores,
    PolicyHelp,
    Summary,
    TaskCounts,
    TickLosses,
)

BTOM = Observer.BTOM.value
MAJORITY = "majority"
"""A majority-class baseline scored on the same ticks: always the most common true preference
(of the episodes scored: it is fitted on them), never a false belief, no belief."""
NONE = OBSERVING
ORACLE = Policy.ORACLE.value
"""The policy that reads the simulated people's true minds: the upper bound of the cuts."""
POLICY_NAMES = {ORACLE: f"{ORACLE} (reads true minds)"}
"""How the reports' robot tables name a policy (by its key otherwise): the oracle marked as one."""


def mistaken(episode: EpisodeRecord, keys: Sequence[str]) -> set[str]:
    """The people who had a false belief about what they wanted in any of the runs ``keys``
    of ``episode``: one population for every policy (:func:`_help_sums`)."""
    return {a for key in keys for a, h in episode.runs[key].help.items() if h.false_belief}


def _help_sums(run: RunScores, anyone: Collection[str] = ()) -> dict[str, tuple[float, int]]:
    """One run's ``(sum, count)`` of each help measure: ticks to goal over the people who had
    a false belief in this run (until they first played with the item it was about, from then
    on; the episode's length when never), counted from the episode's start and from the false
    belief's first tick (the part a robot can shorten: an errand before it cannot be); ticks to
    goal over ``anyone``, the people with a false belief in any policy's run of the episode
    (the same people for every policy, so a robot that spares someone a false belief is
    credited and one that causes one is charged, which ``ticks_to_goal_fb``, over each run's
    own people, does not do); and wasted trips and interruptions over every person."""
    helped = run.help
    fb = [h for h in helped.values() if h.false_belief]
    ticks = [h.goal_tick if h.goal_tick is not None else run.episode_ticks for h in fb]
    onsets = [h.false_belief_tick for h in fb]
    since = [t - onset for t, onset in zip(ticks, onsets, strict=True) if onset is not None]
    reached = run.ticks_to_goal
    every = [_or(reached.get(a), run.episode_ticks) for a in sorted(anyone)]
    return {
        "ticks_to_goal_fb": (float(sum(ticks)), len(ticks)),
        "ticks_to_goal_any_fb": (float(sum(every)), len(every)),
        "ticks_from_false_belief": (float(sum(since)), len(since)),
        "wasted_trips": (float(sum(h.wasted_trips for h in helped.values())), len(helped)),
        "interruptions": (float(sum(h.interruptions for h in helped.values())), len(helped)),
    }


def _or(tick: int | None, otherwise: int) -> int:
    return otherwise if tick is None else tick


def policies_of(episode: EpisodeRecord) -> dict[str, str]:
    """Robot policy -> the key of the run it is measured on, acting policies first (``tom``
    first of them), then ``none`` (the robot observing)."""
    acting = [key for key in map(RunKey.parse, episode.runs) if key.policy is not None]
    acting.sort(key=lambda key: key.label != Policy.TOM)
    return {key.label: str(key) for key in acting} | {NONE: BTOM}


def robot_losses(episodes: Sequence[EpisodeRecord]) -> dict[str, TickLosses]:
    """Per policy, where the ticks to the goal of the people with a false belief went (means
    over them, ticks from the episode's start): before the false belief, from it to the robot's
    first act for them (to the goal when it never acted), from that act to the goal; and the
    share of them the robot acted for."""
    table: dict[str, TickLosses] = {}
    for policy, key in policies_of(episodes[0]).items():
        parts: list[tuple[float, float, float, float]] = []
        for episode in episodes:
            run = episode.runs[key]
            for h in run.help.values():
                if not h.false_belief or h.false_belief_tick is None:
                    continue
                goal = _or(h.goal_tick, run.episode_ticks)
                onset = h.false_belief_tick
                acted = goal if h.acted_tick is None else min(h.acted_tick, goal)
                parts.append((onset, acted - onset, goal - acted, float(h.acted_tick is not None)))
        n = len(parts)
        means = {name: (sum(p[i] for p in parts) / n if n else None) for i, name in enumerate(LOSSES)}
        table[policy] = TickLosses(**means)
    return table


def robot_tasks(episodes: Sequence[EpisodeRecord]) -> dict[str, TaskCounts]:
    """Per acting policy, the robot tasks of its runs (:mod:`.robottasks`): how many were
    begun, done, dropped and still running at the end, summed over episodes, and the share
    begun and not finished (``None`` when none was begun)."""
    table: dict[str, TaskCounts] = {}
    for policy, key in policies_of(episodes[0]).items():
        if policy == NONE:
            continue
        tallies = [e.runs[key].tasks for e in episodes]
        begun, unfinished = sum(t.begun for t in tallies), sum(t.unfinished for t in tallies)
        table[policy] = TaskCounts(
            begun=begun,
            done=sum(t.done for t in tallies),
            dropped=sum(t.dropped for t in tallies),
            running=sum(t.running for t in tallies),
            unfinished_share=unfinished / begun if begun else None,
        )
    return table


def robot_metrics(
    episodes: Sequence[EpisodeRecord], seed: int
) -> tuple[dict[str, PolicyHelp], dict[str, HelpMeasures]]:
    """``(per policy, the first policy minus each other)``: success rate, each of :data:`HELP`,
    and the cuts of :data:`CUTS`, each an :class:`Interval` (the cuts ``None`` for ``none``)."""
    policies = policies_of(episodes[0])
    per_policy: dict[str, dict[str, Interval | float | None]] = {p: {} for p in policies}
    differences: dict[str, dict[str, Interval]] = {p: {} for p in list(policies)[1:]}
    people = [mistaken(e, list(policies.values())) for e in episodes]
    sums = {
        policy: [_help_sums(e.runs[key], p) for e, p in zip(episodes, people, strict=True)]
        for policy, key in policies.items()
    }
    for measure in HELP:
        bounds, diffs = pooled_means({p: [s[measure] for s in sums[p]] for p in policies}, seed)
        for policy in policies:
            per_policy[policy][measure] = Interval.of(bounds[policy]) if policy in bounds else NO_INTERVAL
        for other, interval in diffs.items():
            differences[other][measure] = Interval.of(interval)
    oracle = ORACLE if ORACLE in policies else None
    for measure, suffix in CUTS.items():
        cut = cuts({p: [s[measure] for s in sums[p]] for p in policies}, seed, NONE, oracle)
        for policy in policies:
            for name in ("cut", "share_of_oracle"):
                per_policy[policy][name + suffix] = Interval.of(cut[policy][name]) if policy in cut else None
    for policy, key in policies.items():
        outcome = EpisodeOutcome()
        for episode in episodes:
            for ok in episode.runs[key].outcome.values():
                outcome.people += 1
                outcome.successes += bool(ok)
        per_policy[policy]["success"] = outcome.rate
    help_of = {policy: PolicyHelp(**values) for policy, values in per_policy.items()}  # type: ignore[arg-type]
    return help_of, {other: HelpMeasures(**values) for other, values in differences.items()}


def _with_intervals(pooled: Mapping[str, float | None], bounds: Mapping[str, Interval]) -> ObserverScores:
    """Each metric of :data:`~toyroom.evaluation.intervals.METRICS` as an :class:`Interval`,
    the others (precision, recall) as plain numbers."""
    return {
        m: bounds.get(m, Interval(mean=v, lo=None, hi=None)) if m in INTERVAL_METRICS else v
        for m, v in pooled.items()
    }


def _bounds(
    table: Mapping[str, Mapping[str, Mapping[str, float | None]]],
) -> dict[str, dict[str, Interval]]:
    """:func:`~.intervals.intervals`' ``{mean, lo, hi}`` mappings as :class:`Interval` values."""
    return {name: {m: Interval.of(v) for m, v in row.items()} for name, row in table.items()}


def aggregate(episodes: Sequence[EpisodeRecord], seed: int, observers: Sequence[str]) -> Summary:
    """One condition's numbers from its episodes' results (failed episodes are counted in
    ``episodes_failed`` and left out of the scores)."""
    failed = [e for e in episodes if e.failed]
    episodes = [e for e in episodes if not e.failed]
    totals = {observer: Counts() for observer in observers}
    per_episode: dict[str, list[Counts]] = {observer: [] for observer in (*observers, MAJORITY)}
    for episode in episodes:
        for observer in observers:
            counts = dataclasses.replace(episode.runs[observer].counts)  # a copy: the sums add into totals
            totals[observer].add(counts)
            per_episode[observer].append(counts)
    goal = max(totals[BTOM].pref_truth, key=lambda g: (totals[BTOM].pref_truth[g], g), default="")
    per_episode[MAJORITY] = [majority_counts(c, goal) for c in per_episode[BTOM]]
    pooled = {observer: totals[observer].metrics() for observer in observers}
    pooled[MAJORITY] = majority_counts(totals[BTOM], goal).metrics()
    bounds, differences = (_bounds(table) for table in intervals(per_episode, seed))
    robot, robot_differences = robot_metrics(episodes, seed) if episodes else ({}, {})
    losses = robot_losses(episodes) if episodes and robot else {}
    tasks = robot_tasks(episodes) if episodes and robot else {}
    return Summary(
        episodes=len(episodes),
        episodes_failed=len(failed),
        failed_runs_retried=sum(len(e.failed_runs or []) for e in episodes),
        observers={name: _with_intervals(pooled[name], bounds.get(name, {})) for name in pooled},
        paired_differences=differences,
        revealed_stretches=totals[BTOM].stretches if BTOM in totals else None,
        nested_pairs=totals[BTOM].nested_n if BTOM in totals else None,
        want_ticks=totals[BTOM].want_n if BTOM in totals else None,
        false_belief_causes={
            name: counts.recall_by_cause()
            for name, counts in {**totals, MAJORITY: majority_counts(totals[BTOM], goal)}.items()
        },
        robot=robot,
        robot_differences=robot_differences,
        robot_losses=losses,
        robot_tasks=tasks,
    )


def by_task(
    condition: Condition, episodes: Sequence[EpisodeRecord], seed: int, observers: Sequence[str]
) -> dict[str, Summary]:
    """A ``tasks`` condition's numbers per task kind (episode ``i`` of a sweep has the seed
    ``1000 seed + i``, which picks its kind: :meth:`Condition.task_of`)."""
    kinds: dict[str, list[EpisodeRecord]] = {}
    for result in episodes:
        kinds.setdefault(condition.task_of(seed * 1000 + result.index) or "", []).append(result)
    return {kind: aggregate(results, seed, observers) for kind, results in sorted(kinds.items())}
