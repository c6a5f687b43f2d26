"""Figures and a report of a run, drawn from ``mind.csv`` like the paper's Fig. 6 and 7:
per item, the belief over locations at each labelled step (smoothed), with the paper's
ground truth beside it where the scenario has one; preferences as bars."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

from bridge.recording.atomic import replacing, write_text

from .groundtruth import GroundTruth
from .mindtable import MindRow
from .steps import Table, labelled, steps_caption, steps_of, steps_section, truth_caption, truth_labels

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

COLOURS = ["#4C72B0", "#DD8452", "#55A868", "#C44E52", "#8172B3", "#937860", "#DA8BC3", "#8C8C8C"]


def pyplot() -> ModuleType:
    """matplotlib's pyplot on the Agg backend, imported on first use (half a second that a
    brain which writes no figures does not pay)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


SHOWN = 0.01
"""A location or goal whose bars never reach this is left out of the legend (nothing shows)."""


def observed_agent(rows: list[MindRow], truth: GroundTruth | None) -> str | None:
    """The agent to plot: the ground truth's, else the one with the most labelled steps."""
    if truth is not None:
        return truth.agent
    counts: dict[str, set[str]] = defaultdict(set)
    for row in rows:
        if row.label:
            counts[row.agent].add(row.label)
    return max(counts, key=lambda a: len(counts[a])) if counts else None


def _stack(ax: Axes, xs: list[float], series: dict[str, list[float]], width: float, hatch: str) -> None:
    """Stacked bars, one colour per location (in ``series`` order, as in every figure)."""
    bottom = [0.0] * len(xs)
    for li, values in enumerate(series.values()):
        colour = COLOURS[li % len(COLOURS)]
        ax.bar(xs, values, width=width, bottom=bottom, color=colour, hatch=hatch, edgecolor="white")
        bottom = [b + v for b, v in zip(bottom, values, strict=True)]


def _truth_belief(truth: GroundTruth | None, label: str, item: str, location: str) -> float:
    """The ground truth's P(``item`` at ``location``) believed at step ``label`` (0 where none)."""
    step = truth.at(label) if truth is not None else None
    return step.belief.get(item, {}).get(location, 0.0) if step is not None else 0.0


def _belief_axes(
    ax: Axes,
    agent: str,
    item: str,
    labels: list[str],
    locations: list[str],
    table: Table,
    truth: GroundTruth | None,
) -> None:
    """One item's panel: the model's smoothed belief per step, and the ground truth hatched
    beside it only at the steps where there is one; a legend of what is drawn."""
    from matplotlib.patches import Patch

    covered = truth_labels(truth, labels, item=item)
    model = {loc: [table[label]["belief"][item].get(loc, 0.0) for label in labels] for loc in locations}
    x = [float(i) for i in range(len(labels))]
    _stack(ax, [i - 0.2 for i in x] if covered else x, model, 0.38 if covered else 0.6, "")
    shown = {loc for loc, values in model.items() if max(values, default=0.0) >= SHOWN}
    if covered:
        gt = {loc: [_truth_belief(truth, label, item, loc) for label in labels] for loc in locations}
        _stack(ax, [i + 0.2 for i in x], gt, 0.38, "//")
        shown |= {loc for loc, values in gt.items() if max(values, default=0.0) >= SHOWN}
    handles = [
        Patch(color=COLOURS[li % len(COLOURS)], label=loc) for li, loc in enumerate(locations) if loc in shown
    ]
    if covered:
        handles.append(Patch(facecolor="white", edgecolor="grey", hatch="//", label="ground truth"))
    where = "left: model, smoothed; right, hatched: ground truth" if covered else "model, smoothed"
    ax.set_title(f"{agent}: where is the {item}? ({where})")
    ax.set_xticks(x, labels)
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("P")
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)


def _captioned(fig: Figure, *lines: str) -> None:
    """Lay the figure out and put ``lines`` (the non-empty ones) under it, as its caption."""
    fig.tight_layout()
    text = "\n".join(line for line in lines if line)
    if text:
        fig.text(0.01, 0.0, text, ha="left", va="top", fontsize=8)


def draw_beliefs(rows: list[MindRow], agent: str, truth: GroundTruth | None) -> Figure:
    """The belief figure: per item, stacked bars of the believed location per step (smoothed),
    the ground truth hatched beside where it has the item at that step; a caption says what
    the steps are and what the ground truth covers."""
    labels, table = labelled(rows, agent)
    items = sorted({r.item for r in rows if r.quantity == "belief"})
    locations = list(dict.fromkeys(r.value for r in rows if r.quantity == "belief"))
    plt = pyplot()
    fig, axes = plt.subplots(
        len(items), 1, figsize=(max(6, 1.0 * len(labels) + 2), 2.8 * len(items)), squeeze=False
    )
    for ax, item in zip(axes[:, 0], items, strict=True):
        _belief_axes(ax, agent, item, labels, locations, table, truth)
    axes[-1, 0].set_xlabel("step")
    covered = sorted(
        {label for item in items for label in truth_labels(truth, labels, item=item)}, key=labels.index
    )
    _captioned(fig, steps_caption(steps_of(rows, agent), agent), truth_caption(truth, covered, labels))
    return fig


def draw_preferences(rows: list[MindRow], agent: str, truth: GroundTruth | None) -> Figure:
    """The preference figure: bars per goal and step (smoothed), and the ground truth's
    hatched beside them only where it gives a preference; a legend of what is drawn and the
    steps' caption."""
    labels, table = labelled(rows, agent)
    options = list(dict.fromkeys(r.item for r in rows if r.quantity == "preference"))
    covered = truth_labels(truth, labels)
    plt = pyplot()
    from matplotlib.patches import Patch

    fig, ax = plt.subplots(figsize=(max(6, 1.1 * len(labels) + 2), 3.2))
    width = 0.8 / (len(options) * (2 if covered else 1))
    handles = []
    for oi, option in enumerate(options):
        colour = COLOURS[oi % len(COLOURS)]
        values = [table[label]["preference"]["-"].get(option, 0.0) for label in labels]
        xs = [i - 0.4 + width * (oi + 0.5) for i in range(len(labels))]
        ax.bar(xs, values, width=width, color=colour)
        if max(values, default=0.0) >= SHOWN:
            handles.append(Patch(color=colour, label=f"{option} (model)" if covered else option))
        if not covered:
            continue
        gt = [_truth_preference(truth, label, option) for label in labels]
        ax.bar([x + width * len(options) for x in xs], gt, width=width, color=colour, hatch="//", alpha=0.5)
        if max(gt, default=0.0) >= SHOWN:
            handles.append(Patch(facecolor=colour, hatch="//", alpha=0.5, label=f"{option} (ground truth)"))
    ax.set_xticks(range(len(labels)), labels)
    ax.set_ylim(0, 1.05)
    where = "model, smoothed; hatched: ground truth" if covered else "smoothed"
    ax.set_title(f"{agent}: preference per step ({where})")
    ax.set_xlabel("step")
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    _captioned(
        fig, steps_caption(steps_of(rows, agent), agent, width=90), truth_caption(truth, covered, labels)
    )
    return fig


def _truth_preference(truth: GroundTruth | None, label: str, option: str) -> float:
    """The ground truth's preference for ``option`` at step ``label`` (0 where none)."""
    step = truth.at(label) if truth is not None else None
    return step.preference.get(option, 0.0) if step is not None else 0.0


def _save(fig: Figure, path: Path) -> None:
    """Write the figure with its caption (which lies below the axes), whole or not at all,
    and close it."""
    try:
        with replacing(path) as partial:
            fig.savefig(partial, dpi=110, bbox_inches="tight", pad_inches=0.15)
    finally:
        pyplot().close(fig)


def belief_figure(rows: list[MindRow], agent: str, truth: GroundTruth | None, path: Path) -> None:
    """Write :func:`draw_beliefs` to ``path``."""
    _save(draw_beliefs(rows, agent, truth), path)


def preference_figure(rows: list[MindRow], agent: str, truth: GroundTruth | None, path: Path) -> None:
    """Write :func:`draw_preferences` to ``path``."""
    _save(draw_preferences(rows, agent, truth), path)


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
        "Most probable believed location of each item and the preference at each labelled step",
        "(what a step is: *Reading the steps*, below); probabilities are smoothed (online in brackets).",
        "",
    ]
    items = sorted({r.item for r in rows if r.quantity == "belief"})
    options = list(dict.fromkeys(r.item for r in rows if r.quantity == "preference"))
    ticks = {step.label: step.tick for step in steps_of(rows, agent)}
    header = ["step", "tick", *items, *(f"P({o})" for o in options)]
    lines.append("| " + " | ".join(header) + " |")
    lines.append("|---" * len(header) + "|")
    for label in labels:
        cells = [label, str(ticks.get(label, ""))]
        for item in items:
            dist = smooth[label]["belief"][item]
            best = max(dist, key=dist.__getitem__)
            cells.append(f"{best} {dist[best]:.2f} ({online[label]['belief'][item][best]:.2f})")
        for option in options:
            smoothed = smooth[label]["preference"]["-"][option]
            filtered = online[label]["preference"]["-"][option]
            cells.append(f"{smoothed:.2f} ({filtered:.2f})")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n" + steps_section(rows, agent, smooth, online)


FACTORED_NOTE = (
    "\n*This house has too many worlds for the exact model: the brain ran the factored model "
    "(docs/model.md), whose `p_smoothed` comes from forward-backward in its product form, an "
    "approximation of the exact smoother.*\n"
)


def truth_note(truth: GroundTruth | None, labels: list[str] | None = None) -> str:
    """The report's sentence on where the ground truth in the figures comes from, and which
    steps (of ``labels``, the steps reported) it covers."""
    if truth is None:
        return "\nNo ground truth for this scenario: the figures show the model alone.\n"
    text = f"\nGround truth: {truth.agent}'s, from `brain/groundtruth/{truth.scenario}.toml`"
    if labels is None:
        return text + ", hatched beside the model in the figures.\n"
    beliefs = [s.label for s in truth.steps if s.belief and s.label in labels]
    preferences = [s.label for s in truth.steps if s.preference and s.label in labels]
    if not beliefs and not preferences:
        return text + ": none of its steps is among this run's, so the figures show the model alone.\n"
    parts = [
        f"{what} at steps {', '.join(at)}"
        for what, at in (("beliefs", beliefs), ("preferences", preferences))
        if at
    ]
    return text + ", hatched beside the model in the figures: " + "; ".join(parts) + ".\n"


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
    recording_note: str = "",
) -> None:
    """Write ``beliefs.png``, ``preferences.png`` and ``report.md`` into ``out`` (``exact``:
    whether the exact model ran, else the report says that smoothing was not available;
    ``recording_note``: a paragraph saying the recording was not whole, put first)."""
    note = "" if exact else FACTORED_NOTE
    first = f"\n{recording_note.strip()}\n\n" if recording_note.strip() else ""
    agent = observed_agent(rows, truth)
    if agent is None:
        text = f"# {scenario}\n{first}\nNo labelled steps to report.\n{truth_note(truth)}{note}"
        write_text(out / "report.md", text)
        return
    belief_figure(rows, agent, truth, out / "beliefs.png")
    preference_figure(rows, agent, truth, out / "preferences.png")
    labels = [step.label for step in steps_of(rows, agent)]
    title, _, body = report_markdown(rows, scenario, agent, observer).partition("\n")
    text = (
        f"{title}\n{first}{body}"
        + evidence_note(rows)
        + truth_note(truth, labels)
        + note
    )
    write_text(out / "report.md", text)
