"""A households evaluation's numbers by day (``toyroom eval --days N``): per day, and pooled over
days :data:`LATER` on with each household one cluster (its days merged into one record, so the
bootstrap resamples households, not days of the same people); the table of ``report.md`` and
the plot of help by day (matplotlib, one line per policy)."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from bridge.recording.atomic import replacing
from protocol import OBSERVING, Observer, Policy

from .aggregate import POLICY_NAMES, aggregate
from .conditions import Condition
from .episodes import OBSERVERS
from .metrics import Counts
from .records import FRESH, EpisodeRecord, RunScores
from .summary import HelpMeasures, HouseholdEvaluation, HouseholdSummary, Interval

LATER = 3
"""Days from this one on are pooled: by then the brain has met its people on earlier days."""
HELP_METRIC = "ticks_to_goal_any_fb"
"""The help measure the days are compared on (:func:`_help` reads it)."""
DETECTION = "revealed_detection"
"""The metric of each observer's column: its share of revealed false beliefs flagged in time."""


def merged(days: Sequence[EpisodeRecord]) -> EpisodeRecord:
    """One household's ``days`` as one record: each run's counts added, its people named
    ``<person>@d<day>`` (an unreached goal counted at that day's last tick, as on one day)."""
    runs: dict[str, RunScores] = {}
    for record in days:
        for key, run in record.runs.items():
            into = runs.setdefault(
                key, RunScores(counts=Counts(), outcome={}, ticks_to_goal={}, episode_ticks=0, ticks=0)
            )
            into.counts.add(run.counts)
            into.ticks += run.ticks
            for person, ok in run.outcome.items():
                into.outcome[f"{person}@d{record.day}"] = ok
            for person, tick in run.ticks_to_goal.items():
                into.ticks_to_goal[f"{person}@d{record.day}"] = run.episode_ticks if tick is None else tick
            for person, helped in run.help.items():
                goal = run.episode_ticks if helped.goal_tick is None else helped.goal_tick
                into.help[f"{person}@d{record.day}"] = dataclasses.replace(helped, goal_tick=goal)
    first = days[0]
    return EpisodeRecord(index=first.index, map=first.map, scenario=first.scenario, runs=runs, day=LATER)


def by_day(
    condition: Condition, records: Sequence[EpisodeRecord], days: int, seed: int, observers: Sequence[str]
) -> HouseholdSummary:
    """``condition``'s numbers per day (every household's record of that day) and over days
    :data:`LATER` on, each household's later days merged into one record (:func:`merged`)."""
    numbers = {}
    for day in range(1, days + 1):
        chunk = [r for r in records if r.day == day]
        numbers[str(day)] = aggregate(chunk, seed, observers)
    households: dict[int, list[EpisodeRecord]] = {}
    for record in records:
        if record.day is not None and record.day >= LATER:
            households.setdefault(record.index, []).append(record)
    whole = [
        merged(sorted(days_of, key=lambda r: r.day or 0))
        for days_of in households.values()
        if not any(r.failed for r in days_of)
    ]
    later = aggregate(whole, seed, observers) if whole else None
    return HouseholdSummary(condition=condition, by_day=numbers, later=later)


def _help(policy: HelpMeasures) -> Interval:
    """The help measure the days are compared on (:data:`HELP_METRIC`)."""
    return policy.ticks_to_goal_any_fb


def _interval(entry: Interval | None) -> str:
    if entry is None or entry.mean is None:
        return "-"
    lo, hi = entry.lo, entry.hi
    bounds = f" [{lo:.1f}, {hi:.1f}]" if lo is not None and hi is not None else ""
    return f"{entry.mean:.1f}{bounds}"


def table(summary: HouseholdSummary, observers: Sequence[str]) -> list[str]:
    """The report's table by day: ticks to the goal of the people with a false belief (any run)
    per policy, the first policy's paired differences, and revealed detection per observer."""
    rows = list(summary.by_day.items())
    if summary.later is not None:
        rows.append((f"{LATER}+", summary.later))
    if not rows:
        return []
    policies = list(rows[0][1].robot)
    differences = list(rows[0][1].robot_differences)
    head = ["day", *(f"{POLICY_NAMES.get(p, p)}: {HELP_METRIC}" for p in policies)]
    head += [f"{policies[0]} - {POLICY_NAMES.get(d, d)}" for d in differences]
    head += [f"detection {o}" for o in observers]
    lines = ["| " + " | ".join(head) + " |", "|" + " --- |" * len(head)]
    for day, numbers in rows:
        cells = [day, *(_interval(_help(numbers.robot[p])) for p in policies)]
        cells += [_interval(_help(numbers.robot_differences[d])) for d in differences]
        for observer in observers:
            detection = numbers.observers.get(observer, {}).get(DETECTION)
            cells.append(_interval(_scaled(detection)))
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def _scaled(entry: Interval | float | None) -> Interval | None:
    """A share as a percentage interval (one decimal then reads well)."""
    if not isinstance(entry, Interval) or entry.mean is None:
        return None
    return Interval(
        mean=100 * entry.mean,
        lo=None if entry.lo is None else 100 * entry.lo,
        hi=None if entry.hi is None else 100 * entry.hi,
    )


def plot(summary: HouseholdSummary, path: Path) -> Path:
    """Help by day, one line per policy (mean and its interval), as ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    days = sorted(summary.by_day, key=int)
    figure, axes = plt.subplots(figsize=(6.5, 4))
    policies = list(summary.by_day[days[0]].robot)
    for policy in policies:
        entries = [_help(summary.by_day[day].robot[policy]) for day in days]
        means = [entry.mean for entry in entries]
        xs = [int(d) for d, m in zip(days, means, strict=True) if m is not None]
        ys = [m for m in means if m is not None]
        axes.plot(xs, ys, marker="o", label=POLICY_NAMES.get(policy, policy))
        band = [
            (int(d), entry.lo, entry.hi)
            for d, entry in zip(days, entries, strict=True)
            if entry.lo is not None and entry.hi is not None
        ]
        if band:
            axes.fill_between([b[0] for b in band], [b[1] for b in band], [b[2] for b in band], alpha=0.12)
    axes.set_xlabel("day of the household")
    axes.set_ylabel(f"{HELP_METRIC} (ticks, lower is better)")
    axes.set_xticks([int(d) for d in days])
    axes.legend(fontsize=8)
    figure.tight_layout()
    try:
        with replacing(path) as partial:  # whole or not at all: a full disk leaves none
            figure.savefig(partial, dpi=110)
    finally:
        plt.close(figure)
    return path


def days_report(metrics: HouseholdEvaluation, out: Path) -> str:
    """``report.md`` of a households evaluation, each condition's plot drawn into ``out``."""
    lines = [
        f"# Households: {metrics.households} per condition, {metrics.days} days each, seed {metrics.seed}",
        "",
    ]
    if metrics.command:
        lines += ["```", metrics.command, "```", ""]
    lines += [
        f"Per day: `{HELP_METRIC}` (ticks from the day's start to the goal of the people with a false "
        "belief about what they wanted in any run of the day; lower is better) per robot policy "
        "(`none`: the robot observing; `-fresh`: a brain with no memory, a first day every day), "
        "the first policy minus each other (paired on the same people), and the share of revealed "
        "false beliefs each observer flagged before the person reached the place (%). In brackets: "
        f"bootstrap 95% intervals. `{LATER}+`: days {LATER} on, households resampled as wholes.",
        "",
    ]
    for condition in metrics.conditions:
        picture = plot(condition, out / f"days-{condition.name}.png")
        lines += [f"## {condition.name}", "", *table(condition, metrics.observers), ""]
        lines += [f"![help by day]({picture.name})", ""]
    return "\n".join(lines)


def day_metrics(
    households: int,
    days: int,
    seed: int,
    conditions: Sequence[Condition],
    found: Mapping[tuple[str, int], list[EpisodeRecord]],
    brain_args: tuple[str, ...],
    command: str,
    policies: Sequence[Policy],
) -> tuple[HouseholdEvaluation, dict[str, list[dict[str, Any]]]]:
    """The numbers of the households' records ``found`` (``metrics.json``), and every day's
    record by condition (``episodes.json``)."""
    observers = (*OBSERVERS, f"{Observer.BTOM.value}-{FRESH}")
    summaries, kept = [], {}
    for condition in conditions:
        records = [r for i in range(households) for r in found[(condition.name, i)]]
        kept[condition.name] = [r.to_builtins() for r in records]
        summaries.append(by_day(condition, records, days, seed, observers))
    evaluation = HouseholdEvaluation(
        households=households,
        days=days,
        seed=seed,
        brain_args=list(brain_args),
        policies=[*policies, OBSERVING],
        command=command,
        observers=list(observers),
        conditions=summaries,
    )
    return evaluation, kept
