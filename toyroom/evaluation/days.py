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

LATER = 3
"""Days from this one on are pooled: by then the brain has met its people on earlier days."""
HELP_METRIC = "ticks_to_goal_any_fb"


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
    records: Sequence[EpisodeRecord], days: int, seed: int, observers: Sequence[str]
) -> dict[str, Any]:
    """``{"by_day": {day: aggregate}, "later": aggregate of days LATER.. by household}``."""
    out: dict[str, Any] = {"by_day": {}}
    for day in range(1, days + 1):
        chunk = [r for r in records if r.day == day]
        out["by_day"][str(day)] = aggregate(chunk, seed, observers)
    households: dict[int, list[EpisodeRecord]] = {}
    for record in records:
        if record.day is not None and record.day >= LATER:
            households.setdefault(record.index, []).append(record)
    whole = [
        merged(sorted(days_of, key=lambda r: r.day or 0))
        for days_of in households.values()
        if not any(r.failed for r in days_of)
    ]
    if whole:
        out["later"] = aggregate(whole, seed, observers)
    return out


def _interval(entry: Mapping[str, Any] | None) -> str:
    if not entry or entry.get("mean") is None:
        return "-"
    lo, hi = entry.get("lo"), entry.get("hi")
    bounds = f" [{lo:.1f}, {hi:.1f}]" if lo is not None and hi is not None else ""
    return f"{entry['mean']:.1f}{bounds}"


def table(summary: Mapping[str, Any], observers: Sequence[str]) -> list[str]:
    """The report's table by day: ticks to the goal of the people with a false belief (any run)
    per policy, the first policy's paired differences, and revealed detection per observer."""
    rows = list(summary["by_day"].items())
    if "later" in summary:
        rows.append((f"{LATER}+", summary["later"]))
    if not rows:
        return []
    policies = list(rows[0][1]["robot"])
    differences = list(rows[0][1]["robot_differences"])
    head = ["day", *(f"{POLICY_NAMES.get(p, p)}: {HELP_METRIC}" for p in policies)]
    head += [f"{policies[0]} - {POLICY_NAMES.get(d, d)}" for d in differences]
    head += [f"detection {o}" for o in observers]
    lines = ["| " + " | ".join(head) + " |", "|" + " --- |" * len(head)]
    for day, numbers in rows:
        cells = [day, *(_interval(numbers["robot"][p].get(HELP_METRIC)) for p in policies)]
        cells += [_interval(numbers["robot_differences"][d].get(HELP_METRIC)) for d in differences]
        for observer in observers:
            detection = numbers["observers"].get(observer, {}).get("revealed_detection")
            cells.append(_interval(_scaled(detection)))
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def _scaled(entry: Any) -> dict[str, Any] | None:
    """A share as a percentage interval (one decimal then reads well)."""
    if not isinstance(entry, Mapping) or entry.get("mean") is None:
        return None
    return {k: (None if v is None else 100 * v) for k, v in entry.items()}


def plot(summary: Mapping[str, Any], path: Path) -> Path:
    """Help by day, one line per policy (mean and its interval), as ``path`` (PNG)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    days = sorted(summary["by_day"], key=int)
    figure, axes = plt.subplots(figsize=(6.5, 4))
    policies = list(summary["by_day"][days[0]]["robot"])
    for policy in policies:
        means, lows, highs = [], [], []
        for day in days:
            entry = summary["by_day"][day]["robot"][policy].get(HELP_METRIC) or {}
            means.append(entry.get("mean"))
            lows.append(entry.get("lo"))
            highs.append(entry.get("hi"))
        xs = [int(d) for d, m in zip(days, means, strict=True) if m is not None]
        ys = [m for m in means if m is not None]
        axes.plot(xs, ys, marker="o", label=POLICY_NAMES.get(policy, policy))
        band = [
            (int(d), lo, hi)
            for d, lo, hi in zip(days, lows, highs, strict=True)
            if lo is not None and hi is not None
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


def days_report(metrics: Mapping[str, Any], out: Path) -> str:
    """``report.md`` of a households evaluation, each condition's plot drawn into ``out``."""
    lines = [
        f"# Households: {metrics['households']} per condition, {metrics['days']} days each, "
        f"seed {metrics['seed']}",
        "",
    ]
    if metrics.get("command"):
        lines += ["```", metrics["command"], "```", ""]
    lines += [
        f"Per day: `{HELP_METRIC}` (ticks from the day's start to the goal of the people with a false "
        "belief about what they wanted in any run of the day; lower is better) per robot policy "
        "(`none`: the robot observing; `-fresh`: a brain with no memory, a first day every day), "
        "the first policy minus each other (paired on the same people), and the share of revealed "
        "false beliefs each observer flagged before the person reached the place (%). In brackets: "
        f"bootstrap 95% intervals. `{LATER}+`: days {LATER} on, households resampled as wholes.",
        "",
    ]
    for condition in metrics["conditions"]:
        picture = plot(condition, out / f"days-{condition['name']}.png")
        lines += [f"## {condition['name']}", "", *table(condition, metrics["observers"]), ""]
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
) -> dict[str, Any]:
    """``metrics.json`` of the households' records ``found``, with every day's record under
    ``episodes`` (by condition, for ``episodes.json``)."""
    observers = (*OBSERVERS, f"{Observer.BTOM.value}-{FRESH}")
    summaries, kept = [], {}
    for condition in conditions:
        records = [r for i in range(households) for r in found[(condition.name, i)]]
        kept[condition.name] = [r.to_builtins() for r in records]
        summary = {**dataclasses.asdict(condition), "name": condition.name}
        summary |= by_day(records, days, seed, observers)
        summaries.append(summary)
    return {
        "households": households,
        "days": days,
        "seed": seed,
        "brain_args": list(brain_args),
        "policies": [*policies, OBSERVING],
        "command": command,
        "observers": list(observers),
        "conditions": summaries,
        "episodes": kept,
    }
