"""Figures and a report of a run, drawn from ``mind.csv`` like the paper's Fig. 6 and 7:
per item, the belief over locations at each labelled step (smoothed), with the paper's
ground truth beside it where the scenario has one; preferences as bars."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from types import ModuleType

from .groundtruth import GroundTruth
from .mindtable import MindRow

COLOURS = ["#4C72B0", "#DD8452", "#55A868", "#C44E52", "#8172B3", "#937860", "#DA8BC3", "#8C8C8C"]


def pyplot() -> ModuleType:
    """matplotlib's pyplot on the Agg backend, imported on first use (half a second that a
    brain which writes no figures does not pay)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


Table = dict[str, dict[str, dict[str, dict[str, float]]]]
"""label -> quantity -> item -> value -> (smoothed) probability."""


def labelled(rows: list[MindRow], agent: str, column: str = "p_smoothed") -> tuple[list[str], Table]:
    """The agent's estimates at each labelled tick, in order."""
    order: list[str] = []
    table: Table = defaultdict(lambda: defaultdict(lambda: defaultdict(dict)))
    for row in rows:
        if row.agent != agent or not row.label:
            continue
        if row.label not in order:
            order.append(row.label)
        key = row.value if row.quantity == "belief" else row.item
        item = row.item if row.quantity == "belief" else "-"
        table[row.label][row.quantity][item][key] = getattr(row, column)
    return order, table


def observed_agent(rows: list[MindRow], truth: GroundTruth | None) -> str | None:
    """The agent to plot: the ground truth's, else the one with the most labelled steps."""
    if truth is not None:
        return truth.agent
    counts: dict[str, set[str]] = defaultdict(set)
    for row in rows:
        if row.label:
            counts[row.agent].add(row.label)
    return max(counts, key=lambda a: len(counts[a])) if counts else None


def belief_figure(rows: list[MindRow], agent: str, truth: GroundTruth | None, path: Path) -> None:
    """Stacked bars of each item's believed location per step; ground truth hatched beside."""
    labels, table = labelled(rows, agent)
    items = sorted({r.item for r in rows if r.quantity == "belief"})
    locations = list(dict.fromkeys(r.value for r in rows if r.quantity == "belief"))
    plt = pyplot()
    fig, axes = plt.subplots(
        len(items), 1, figsize=(max(6, 1.0 * len(labels) + 2), 2.8 * len(items)), squeeze=False
    )
    for ax, item in zip(axes[:, 0], items, strict=True):
        x = range(len(labels))
        for series, offset, hatch in (("model", -0.2, ""), ("truth", 0.2, "//")):
            bottom = [0.0] * len(labels)
            for li, location in enumerate(locations):
                if series == "model":
                    values = [table[label]["belief"][item].get(location, 0.0) for label in labels]
                else:
                    if truth is None:
                        continue
                    values = []
                    for label in labels:
                        step = truth.at(label)
                        values.append(step.belief.get(item, {}).get(location, 0.0) if step else 0.0)
                ax.bar(
                    [i + offset for i in x],
                    values,
                    width=0.38,
                    bottom=bottom,
                    color=COLOURS[li % len(COLOURS)],
                    hatch=hatch,
                    edgecolor="white",
                    label=location if series == "model" else None,
                )
                bottom = [b + v for b, v in zip(bottom, values, strict=True)]
        ax.set_title(f"{agent}: where is the {item}? (left: model, smoothed; right, hatched: ground truth)")
        ax.set_xticks(list(x), labels)
        ax.set_ylim(0, 1.05)
        ax.set_ylabel("P")
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    axes[-1, 0].set_xlabel("step")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def preference_figure(rows: list[MindRow], agent: str, truth: GroundTruth | None, path: Path) -> None:
    """Bars of the preference per step, model (smoothed) and ground truth."""
    labels, table = labelled(rows, agent)
    options = list(dict.fromkeys(r.item for r in rows if r.quantity == "preference"))
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(max(6, 1.1 * len(labels) + 2), 3.2))
    width = 0.8 / (len(options) * (2 if truth else 1))
    for oi, option in enumerate(options):
        values = [table[label]["preference"]["-"].get(option, 0.0) for label in labels]
        xs = [i - 0.4 + width * (oi + 0.5) for i in range(len(labels))]
        ax.bar(xs, values, width=width, color=COLOURS[oi % len(COLOURS)], label=f"{option} (model)")
        if truth is not None:
            gt = []
            for label in labels:
                step = truth.at(label)
                gt.append(step.preference.get(option, 0.0) if step else 0.0)
            xs = [x + width * len(options) for x in xs]
            ax.bar(
                xs,
                gt,
                width=width,
                color=COLOURS[oi % len(COLOURS)],
                hatch="//",
                alpha=0.5,
                label=f"{option} (ground truth)",
            )
    ax.set_xticks(range(len(labels)), labels)
    ax.set_ylim(0, 1.05)
    ax.set_title(f"{agent}: preference per step (smoothed)")
    ax.set_xlabel("step")
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def report_markdown(rows: list[MindRow], scenario: str, agent: str, observer: str) -> str:
    """``report.md``: the figures and a table of the estimates at each labelled step."""
    labels, smooth = labelled(rows, agent, "p_smoothed")
    _, online = labelled(rows, agent, "p_online")
    lines = [
        f"# {scenario}: what the robot infers of {agent} ({observer} observer)",
        "",
        "![beliefs](beliefs.png)",
        "",
        "![preferences](preferences.png)",
        "",
        "Most probable believed location of each item and the preference at each labelled step;",
        "probabilities are smoothed (online in brackets).",
        "",
    ]
    items = sorted({r.item for r in rows if r.quantity == "belief"})
    options = list(dict.fromkeys(r.item for r in rows if r.quantity == "preference"))
    lines.append("| step | " + " | ".join(items) + " | " + " | ".join(f"P({o})" for o in options) + " |")
    lines.append("|---" * (1 + len(items) + len(options)) + "|")
    for label in labels:
        cells = [label]
        for item in items:
            dist = smooth[label]["belief"][item]
            best = max(dist, key=dist.__getitem__)
            cells.append(f"{best} {dist[best]:.2f} ({online[label]['belief'][item][best]:.2f})")
        for option in options:
            smoothed = smooth[label]["preference"]["-"][option]
            filtered = online[label]["preference"]["-"][option]
            cells.append(f"{smoothed:.2f} ({filtered:.2f})")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


FACTORED_NOTE = (
    "\n*This house has too many worlds for the exact model: the brain ran the factored model "
    "(docs/model.md), whose `p_smoothed` comes from forward-backward in its product form, an "
    "approximation of the exact smoother.*\n"
)


def truth_note(truth: GroundTruth | None) -> str:
    """The report's sentence on where the ground truth in the figures comes from."""
    if truth is None:
        return "\nNo ground truth for this scenario: the figures show the model alone.\n"
    return (
        f"\nGround truth: {truth.agent}'s, from `brain/groundtruth/{truth.scenario}.toml`, "
        "hatched beside the model in the figures.\n"
    )


def evidence_note(rows: list[MindRow]) -> str:
    """Each person's log-evidence: the marginal log-likelihood of their decisions under the
    model (comparable across models and settings on the same run)."""
    totals = {r.agent: r.p_smoothed for r in rows if r.quantity == "log_evidence"}
    if not totals:
        return ""
    lines = ["", "## Log-evidence", "", "| person | log P(decisions) |", "| --- | --- |"]
    lines += [f"| {agent} | {total:.2f} |" for agent, total in totals.items()]
    return "\n".join(lines) + "\n"


def write_report(
    rows: list[MindRow],
    scenario: str,
    observer: str,
    truth: GroundTruth | None,
    out: Path,
    *,
    exact: bool = True,
) -> None:
    """Write ``beliefs.png``, ``preferences.png`` and ``report.md`` into ``out`` (``exact``:
    whether the exact model ran, else the report says that smoothing was not available)."""
    note = "" if exact else FACTORED_NOTE
    agent = observed_agent(rows, truth)
    if agent is None:
        text = f"# {scenario}\n\nNo labelled steps to report.\n{truth_note(truth)}{note}"
        (out / "report.md").write_text(text, encoding="utf-8")
        return
    belief_figure(rows, agent, truth, out / "beliefs.png")
    preference_figure(rows, agent, truth, out / "preferences.png")
    text = report_markdown(rows, scenario, agent, observer) + evidence_note(rows) + truth_note(truth) + note
    (out / "report.md").write_text(text, encoding="utf-8")
