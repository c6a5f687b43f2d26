"""``report.md`` of ``toyroom eval``: per condition, the observers' metrics and the robot
policies' help as tables with bootstrap 95% intervals, a figure (``metrics-<condition>.png``),
and tables per map; the exact command at the top."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import msgspec

from bridge.recording.atomic import replacing
from protocol import PREFERENCE_THRESHOLD, Minds, Perception

from .aggregate import POLICY_NAMES
from .scores import MetricGroup, metric_names
from .summary import (
    CUTS,
    LOSSES,
    CauseRecall,
    ConditionSummary,
    Evaluation,
    Interval,
    Summary,
    TaskCounts,
    TickLosses,
)
from .summary import HELP as HELP_MEASURES

METRICS = metric_names(MetricGroup.BELIEFS)
BEHAVIOUR = metric_names(MetricGroup.BEHAVIOUR)
BEHAVIOUR_NOTE = (
    "False beliefs where they can be known: `knowable_false_belief_f1` counts as positives only "
    "the false beliefs caused by a move the robot perceived or revealed by a pursuit (from its "
    "first revealed tick); `revealed_detection`: the share of revealed stretches (a person after "
    "an item, heading for a place their belief gives it, where it is not) whose P(false belief) "
    "passed 0.5 before they reached the place, and the median lead in ticks; "
    "`revealed_detection_any` and its lead: the same, item-agnostic (P(they head for a place "
    "where they falsely believe some item they want rests) passed 0.5); `brier`, `log_loss` "
    "(lower is better) and `brier_skill` (1 - Brier / the base rate's; above 0 beats always "
    "answering the base rate) of P(false belief) over every person-item-tick."
)
NESTED = metric_names(MetricGroup.NESTED)
NESTED_NOTE = (
    "What each person believes the others believe, where it differs from what they believe "
    "(person-pair-item-ticks, both sure): `nested_belief_accuracy`, the share whose most "
    "probable location the observer's nested estimate gets right; "
    "`nested_first_order_accuracy`, the same answered with its estimate of the other's own "
    "belief (a baseline); `nested_gain`, the difference (same resamples: a paired interval)."
)
WANT = metric_names(MetricGroup.WANT)
WANT_NOTE = (
    "The want read where help matters: over the ticks from a person's false belief about the "
    "item they want to their first take of it (person-ticks; a stretch also ends when the want "
    "changes), `fb_want_p`: the mean P(the true want); `fb_want_confident`: the share of those "
    f"ticks at or above the robot's threshold ({PREFERENCE_THRESHOLD}); `fb_want_top`: the share "
    "where the true want is the most probable goal (a tie of n counts 1/n). "
    "`preference_accuracy` counts only ticks after a person's first take, most of them spent "
    "playing with the item they want."
)
HELP = ("success", *HELP_MEASURES)
"""The robot table's columns: the success rate, then each help measure of the aggregate."""
CUT_COLUMNS = tuple(f"{name}{suffix}" for suffix in CUTS.values() for name in ("cut", "share_of_oracle"))
"""The robot table's last columns: each policy's cut against ``none`` and its share of the oracle's."""
CUT_NOTE = (
    "`cut`: (`none`'s mean `ticks_to_goal_fb` - the policy's) / `none`'s; `share_of_oracle`: "
    "(`none`'s - the policy's) / (`none`'s - the oracle's), when the oracle ran and cut (the policy's "
    "reading of minds against reading them true; the oracle's own cut is what acting on true minds "
    "gains); `_any_fb`: the same on `ticks_to_goal_any_fb`. The oracle reads the simulated people's "
    "true minds: an upper bound, not a robot one could build."
)
ORACLE = (
    "With simple minds and an omniscient robot, `perceptonly` is an oracle of people's beliefs: "
    "the simulated people update on exactly the percepts it computes, from the same true world, "
    "so only their preferences are left to infer. The other conditions take that away."
)


def figure_name(condition: ConditionSummary) -> str:
    """The file name of a condition's metrics figure."""
    return f"metrics-{condition.name}.png"


def _cell(value: object) -> str:
    if isinstance(value, Interval):
        return _with_interval(value)
    return "-" if value is None else f"{value:.3f}"


def _with_interval(interval: Interval) -> str:
    mean = "-" if interval.mean is None else f"{interval.mean:.3f}"
    if interval.lo is None:
        return mean
    return f"{mean} [{interval.lo:.3f}, {interval.hi:.3f}]"


def _value(row: Mapping[str, object] | msgspec.Struct, column: str) -> object:
    """A table row's value in ``column``: a metric of a mapping by name, or a record's field."""
    return row.get(column) if isinstance(row, Mapping) else getattr(row, column, None)


def _rows(
    table: Mapping[str, Mapping[str, Any]] | Mapping[str, msgspec.Struct],
    columns: tuple[str, ...] | list[str],
    first: str,
    names: Mapping[str, str] | None = None,
) -> list[str]:
    """A table: a row per entry of ``table`` (named as ``names`` says, else by its key)."""
    lines = [f"| {first} | " + " | ".join(columns) + " |", "|---" * (len(columns) + 1) + "|"]
    for name, values in table.items():
        shown = (names or {}).get(name, name)
        lines.append(f"| {shown} | " + " | ".join(_cell(_value(values, c)) for c in columns) + " |")
    return lines


def _tables(metrics: Summary) -> list[str]:
    lines = _rows(metrics.observers, METRICS, "observer")
    differences = metrics.paired_differences
    if differences:
        names = [m for m in next(iter(differences.values())) if m not in (*BEHAVIOUR, *NESTED, *WANT)]
        lines += [
            "",
            "btom minus each other observer, paired by episode (an interval without 0 is a difference):",
            "",
            *_rows(differences, names, "observer"),
        ]
    stretches = metrics.revealed_stretches
    count = f" ({stretches} revealed stretches)" if stretches is not None else ""
    lines += ["", BEHAVIOUR_NOTE + count, "", *_rows(metrics.observers, BEHAVIOUR, "observer")]
    lines += _paired(differences, BEHAVIOUR)
    lines += _want(metrics, differences)
    nested = metrics.nested_pairs
    if nested:
        lines += ["", f"{NESTED_NOTE} ({nested} person-pair-item-ticks)", ""]
        lines += _rows(metrics.observers, NESTED, "observer")
    lines += _causes(metrics.false_belief_causes)
    if metrics.robot:
        lines += [
            "",
            "Robot policies (`ticks_to_goal_fb`: mean ticks until a person who had a false belief "
            "about what they wanted first had it, the episode's length when never; "
            "`ticks_to_goal_any_fb`: the same over the people who had one in any policy's run of "
            "the episode, the same people for every policy (a robot that spares someone a false "
            "belief is credited, one that causes one is charged); "
            "`ticks_from_false_belief`: the same as the first counted from the false belief's first tick; "
            "trips and interruptions per person). " + CUT_NOTE,
            "",
            *_rows(metrics.robot, (*HELP, *CUT_COLUMNS), "policy", POLICY_NAMES),
        ]
        if metrics.robot_differences:
            lines += ["", "tom minus each other policy, paired by episode:", ""]
            lines += _rows(metrics.robot_differences, list(HELP[1:]), "policy", POLICY_NAMES)
        lines += _losses(metrics.robot_losses)
        lines += _tasks(metrics.robot_tasks)
    return lines


def _want(metrics: Summary, differences: Mapping[str, Mapping[str, Interval]]) -> list[str]:
    """The table of the want read over false-belief stretches (none when there were none)."""
    ticks = metrics.want_ticks
    if not ticks:
        return []
    lines = ["", f"{WANT_NOTE} ({ticks} person-ticks)", "", *_rows(metrics.observers, WANT, "observer")]
    return lines + _paired(differences, WANT)


def _paired(differences: Mapping[str, Mapping[str, Interval]], group: tuple[str, ...]) -> list[str]:
    """btom minus each other observer on the metrics of ``group`` (none without differences)."""
    if not differences:
        return []
    names = [m for m in next(iter(differences.values())) if m in group]
    return [
        "",
        "btom minus each other observer, paired by episode:",
        "",
        *_rows(differences, names, "observer"),
    ]


LOSS_NOTE = (
    "Where the ticks go (mean ticks to the goal of the people with a false belief, split: "
    "before the false belief, from it to the robot's first act for them (`say`, `request`, "
    "`give` to them, or taking the item; to the goal when it never acted), from that act to "
    "the goal; and the share of them it acted for):"
)


def _losses(losses: Mapping[str, TickLosses]) -> list[str]:
    """The loss table (none when there is no robot)."""
    if not losses:
        return []
    names = ("before false belief", "before the robot acted", "after it acted", "acted for")
    lines = ["", LOSS_NOTE, "", "| policy | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for policy, row in losses.items():
        values = {name: getattr(row, name) for name in LOSSES}
        cells = [
            "-" if v is None else f"{v:.2f}" if name == "robot_acted" else f"{v:.1f}"
            for name, v in values.items()
        ]
        lines.append(f"| {POLICY_NAMES.get(policy, policy)} | " + " | ".join(cells) + " |")
    return lines


TASK_NOTE = (
    "The robot's tasks (an inform, a put-back, a swap, a look, a question), summed over the "
    "episodes: begun, done, dropped (no longer needed, most often: the person got there before "
    "the robot's word or put-back landed) and still running at the episode's end; `unfinished`: "
    "the share begun and not done:"
)


def _tasks(tasks: Mapping[str, TaskCounts]) -> list[str]:
    """The robot's begun and unfinished tasks per acting policy (none when there is no robot)."""
    if not tasks:
        return []
    names = TaskCounts.__struct_fields__
    lines = ["", TASK_NOTE, "", "| policy | begun | done | dropped | running at the end | unfinished |"]
    lines.append("|---" * (len(names) + 1) + "|")
    for policy, row in tasks.items():
        cells = [str(v) if isinstance(v := getattr(row, name), int) else _cell(v) for name in names]
        lines.append(f"| {POLICY_NAMES.get(policy, policy)} | " + " | ".join(cells) + " |")
    return lines


CAUSE_NOTE = (
    "False beliefs by how they arose (`start`: held from the person's first tick, a belief from "
    "before the episode; `moved`: the item changed place unseen; `unmoved`: the item stayed put "
    "and the belief left it: told, overlooked or forgotten). Share of false-belief ticks, and "
    "each observer's recall on them:"
)


def _causes(causes: Mapping[str, Mapping[str, CauseRecall]]) -> list[str]:
    """The table of false beliefs by cause (none when there were none)."""
    if not causes or not any(v.ticks for v in next(iter(causes.values())).values()):
        return []
    first = next(iter(causes.values()))
    names = [f"{cause} ({_cell(v.share)} of {v.ticks})" for cause, v in first.items()]
    lines = ["", CAUSE_NOTE, "", "| observer | " + " | ".join(names) + " |", "|---" * (len(names) + 1) + "|"]
    for observer, by_cause in causes.items():
        lines.append(f"| {observer} | " + " | ".join(_cell(v.recall) for v in by_cause.values()) + " |")
    return lines


def plot(condition: ConditionSummary, path: Path) -> None:
    """Bars (with 95% intervals) of the observers' metrics, and the policies' ticks to goal."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    shown = metric_names(MetricGroup.BELIEFS, interval=True)
    numbers = condition.numbers
    observers = list(numbers.observers)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 3.6), gridspec_kw={"width_ratios": [3, 1]})
    width = 0.8 / len(observers)
    for i, observer in enumerate(observers):
        values = [_interval_of(numbers.observers[observer][m]) for m in shown]
        means = [v.mean or 0.0 for v in values]
        errors = [
            [m - (v.lo if v.lo is not None else m) for m, v in zip(means, values, strict=True)],
            [(v.hi if v.hi is not None else m) - m for m, v in zip(means, values, strict=True)],
        ]
        xs = [j + (i - (len(observers) - 1) / 2) * width for j in range(len(shown))]
        left.bar(xs, means, width, yerr=errors, capsize=2, label=observer)
    left.set_xticks(range(len(shown)), list(shown), fontsize=8)
    left.set_ylim(0, 1)
    left.legend(fontsize=8)
    left.set_title(f"{condition.name}: {numbers.episodes} episodes (belief_tv: lower is better)", fontsize=9)
    robot = numbers.robot
    policies = list(robot)
    means = [robot[p].ticks_to_goal_fb.mean or 0.0 for p in policies]
    right.bar(policies, means, color="#55A868")
    right.set_title("ticks to goal after a false belief", fontsize=9)
    fig.tight_layout()
    try:
        with replacing(path) as partial:  # whole or not at all: a full disk leaves none
            fig.savefig(partial, dpi=110)
    finally:
        plt.close(fig)


def _interval_of(value: Interval | float | None) -> Interval:
    """A metric shown with an interval (one without, as its mean alone)."""
    return value if isinstance(value, Interval) else Interval(mean=value, lo=None, hi=None)


def _condition(summary: ConditionSummary, out: Path | None) -> list[str]:
    condition, numbers = summary.condition, summary.numbers
    lines = [
        f"## {summary.name}: perception {condition.perception}, minds {condition.minds}, "
        f"episodes {condition.kind} ({numbers.episodes} scored)",
        "",
    ]
    if condition.perception == Perception.OMNISCIENT and condition.minds == Minds.SIMPLE:
        lines += [ORACLE, ""]
    lines += [*_tables(numbers), ""]
    failed, retried = numbers.episodes_failed, numbers.failed_runs_retried
    if failed:
        lines += [
            f"**{failed} episode(s) failed** even after retries and are left out (`episodes.json`: `error`).",
            "",
        ]
    if retried:
        lines += [f"{retried} run(s) crashed and were run again (logs kept as `*.failed<N>.log`).", ""]
    if out is not None and numbers.episodes:
        plot(summary, out / figure_name(summary))
        lines += [f"![{summary.name}]({figure_name(summary)})", ""]
    for name, part in summary.by_map.items():
        if part.episodes:
            lines += [f"### Map `{name}`: {part.episodes} episodes", "", *_tables(part), ""]
    for name, part in (summary.by_task or {}).items():
        if part.episodes:
            lines += [f"### Task `{name}`: {part.episodes} episodes", "", *_tables(part), ""]
    return lines


def _timing(timing: Mapping[str, Any]) -> str:
    """The report's line on how long it took."""
    runs = ", ".join(f"`{name}` {seconds:.1f} s" for name, seconds in timing["run_seconds_mean"].items())
    own = timing.get("episode_seconds_mean")
    return (
        f"Took {timing['seconds']:.0f} s: **{timing['seconds_per_episode']:.2f} s per episode** with "
        f"{timing['workers']} at a time"
        + (f" (an episode's runs, one after the other: {own:.1f} s; each kind of run: {runs})" if own else "")
        + "."
        + _cpu(timing.get("cpu_seconds_per_episode"))
    )


def _cpu(cpu: Mapping[str, float] | None) -> str:
    """The report's sentence on the CPU an episode took (none with Ray)."""
    if not cpu:
        return ""
    return (
        f" CPU per episode: {sum(cpu.values()):.1f} s (the engine and brain processes "
        f"{cpu['nodes']:.1f} s, the evaluator {cpu['evaluator']:.1f} s)."
    )


def report(metrics: Evaluation, out: Path | None = None) -> str:
    """``report.md``'s text; with ``out``, also draws each condition's figure there."""
    lines = [
        f"# Evaluation: {metrics.episodes} episodes per condition, seed {metrics.seed}",
        "",
    ]
    if metrics.command:
        lines += ["```", metrics.command, "```", ""]
    if metrics.timing:
        lines += [_timing(metrics.timing), ""]
    lines += [
        "Online estimates against the simulated people's true minds (lower `belief_tv` is better; "
        "a false belief: the person's true belief gives the item's true location less than 0.1). "
        "In brackets: bootstrap 95% intervals over episodes. `majority`: always the most common "
        "true preference of these episodes (so fitted on them), never a false belief.",
        "",
    ]
    for condition in metrics.conditions:
        lines += _condition(condition, out)
    return "\n".join(lines)
