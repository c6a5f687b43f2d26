"""``report.md`` and ``metrics.png`` of ``toyroom eval``: the metrics as tables (all
episodes, then per map) and bars of each metric per observer."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

METRICS = (
    "belief_tv",
    "preference_accuracy",
    "false_belief_precision",
    "false_belief_recall",
    "false_belief_f1",
)
FIGURE = "metrics.png"


def _cell(value: object) -> str:
    return "-" if value is None else f"{value:.3f}"


def _with_interval(value: object, interval: Mapping[str, Any] | None) -> str:
    if interval is None or interval.get("lo") is None:
        return _cell(value)
    return f"{_cell(value)} [{interval['lo']:.3f}, {interval['hi']:.3f}]"


def _table(metrics: Mapping[str, Any]) -> list[str]:
    lines = ["| observer | " + " | ".join(METRICS) + " |", "|---" * (len(METRICS) + 1) + "|"]
    bounds = metrics.get("intervals", {})
    for observer, values in metrics["observers"].items():
        cells = [_with_interval(values[n], bounds.get(observer, {}).get(n)) for n in METRICS]
        lines.append(f"| {observer} | " + " | ".join(cells) + " |")
    differences = metrics.get("paired_differences")
    if differences:
        names = list(next(iter(differences.values())))
        lines += [
            "",
            "btom minus each other observer, paired by episode (bootstrap 95% intervals; an "
            "interval that excludes 0 is a difference):",
            "",
            "| observer | " + " | ".join(names) + " |",
            "|---" * (len(names) + 1) + "|",
        ]
        for observer, by_metric in differences.items():
            cells = [_with_interval(by_metric[n]["mean"], by_metric[n]) for n in names]
            lines.append(f"| {observer} | " + " | ".join(cells) + " |")
    return lines


def plot(metrics: Mapping[str, Any], path: Path) -> None:
    """Bars of every metric per observer, and the success rate with and without the robot."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    observers = list(metrics["observers"])
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 3.6), gridspec_kw={"width_ratios": [4, 1]})
    width = 0.8 / len(observers)
    for i, observer in enumerate(observers):
        values = [metrics["observers"][observer][m] for m in METRICS]
        xs = [j + (i - (len(observers) - 1) / 2) * width for j in range(len(METRICS))]
        left.bar(xs, [v if v is not None else 0.0 for v in values], width, label=observer)
    left.set_xticks(range(len(METRICS)), [m.replace("_", "\n", 1) for m in METRICS], fontsize=8)
    left.set_ylim(0, 1)
    left.legend(fontsize=8)
    left.set_title(
        f"online estimates, {metrics['episodes']} episodes (belief_tv: lower is better)", fontsize=9
    )
    robot = metrics["robot"]
    right.bar(
        ["with", "without"], [robot["with"] or 0.0, robot["without"] or 0.0], color=["#55A868", "#8C8C8C"]
    )
    right.set_ylim(0, 1)
    right.set_title("people ending with what they want", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def report(
    metrics: Mapping[str, Any], by_map: Mapping[str, Mapping[str, Any]] | None = None, out: Path | None = None
) -> str:
    """``report.md``'s text; with ``out``, also draws ``out/metrics.png`` and links it."""
    lines = [
        f"# Evaluation: {metrics['episodes']} episodes, seed {metrics['seed']}",
        "",
        "Online estimates against the simulated people's true minds (lower `belief_tv` is better; "
        "a false belief: the person's true belief gives the item's true location less than 0.1). "
        "In brackets: bootstrap 95% intervals over episodes. `majority`: always the most common "
        "true preference of these episodes (so fitted on them), never a false belief.",
        "",
        *_table(metrics),
    ]
    robot = metrics["robot"]
    lines += [
        "",
        "| people who end with what they want | rate |",
        "|---|---|",
        f"| with the robot acting | {_cell(robot['with'])} |",
        f"| without (observing) | {_cell(robot['without'])} |",
        "",
    ]
    waits = metrics.get("ticks_to_goal")
    if waits and waits.get("with") is not None:
        lines += [
            f"Mean ticks until a person first has what they want (the episode's length when never): "
            f"{waits['with']:.0f} with the robot acting, {waits['without']:.0f} without.",
            "",
        ]
    failed = metrics.get("episodes_failed", 0)
    if failed:
        lines += [
            f"**{failed} episode(s) failed** even after retries and are left out of these numbers "
            "(`episodes.json`: `error`).",
            "",
        ]
    retried = metrics.get("failed_runs_retried", 0)
    if retried:
        lines += [
            f"{retried} run(s) failed (a node process crashed) and were run again; their logs are kept "
            "as `*.failed<N>.log` and their reasons in `episodes.json` (`failed_runs`).",
            "",
        ]
    if out is not None:
        plot(metrics, out / FIGURE)
        lines += [f"![metrics per observer]({FIGURE})", ""]
    for name, part in (by_map or {}).items():
        if not part["episodes"]:
            continue
        robot = part["robot"]
        lines += [
            f"## Map `{name}`: {part['episodes']} episodes",
            "",
            *_table(part),
            "",
            f"Robot: with {_cell(robot['with'])}, without {_cell(robot['without'])}.",
            "",
        ]
    return "\n".join(lines)
