"""A run's labelled steps, read from ``mind.csv`` rows, and the words that explain them
beside the figures and in ``report.md``: what a step is (a labelled waypoint of the
scenario, at the tick the person completed it), what the ground truth covers, and why a
step's smoothed preference may disagree with the online one. Read from the rows alone, so a
report inferred again from a trace says the same."""

from __future__ import annotations

import textwrap
from collections import defaultdict
from dataclasses import dataclass

from .groundtruth import GroundTruth
from .mindtable import MindRow

DISAGREE = 0.5
"""A step's online and smoothed preferences disagree when they favour different goals and the
online favourite lost at least this much probability in smoothing."""


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


@dataclass(frozen=True)
class LabelledStep:
    """One labelled step of a person: its label, the tick it was completed at, and whether the
    person had made a decision by then (else the estimates are the prior and what they saw)."""

    label: str
    tick: int
    decided: bool


def steps_of(rows: list[MindRow], agent: str) -> list[LabelledStep]:
    """The person's labelled steps in order. A step counts as decided when the person's
    log-evidence (the log-likelihood of their decisions so far) is no longer 0."""
    steps: dict[str, LabelledStep] = {}
    for row in rows:
        if row.agent == agent and row.label and row.quantity == "log_evidence" and row.label not in steps:
            steps[row.label] = LabelledStep(row.label, row.tick, row.p_online != 0.0)
    return list(steps.values())


def truth_labels(truth: GroundTruth | None, labels: list[str], *, item: str | None = None) -> list[str]:
    """The steps the ground truth covers: a belief about ``item`` (or a preference, when
    ``item`` is None) at that label."""
    if truth is None:
        return []
    covered = []
    for label in labels:
        step = truth.at(label)
        if step is not None and (step.belief.get(item) if item is not None else step.preference):
            covered.append(label)
    return covered


def steps_caption(steps: list[LabelledStep], agent: str, width: int = 110) -> str:
    """The figures' line on what the steps are, wrapped to ``width`` characters."""
    if not steps:
        return ""
    ticks = ", ".join(f"{s.label} (tick {s.tick})" for s in steps)
    first = steps[0]
    start = (
        f"step {first.label} comes before any decision of {agent}'s: the prior and what {agent} saw"
        if not first.decided
        else f"step {first.label} already includes {agent}'s first decision"
    )
    text = (
        f"Steps: the scenario's labelled waypoints {agent} completed, in order: {ticks}; "
        f"each shows the estimate after that tick ({start})."
    )
    return "\n".join(textwrap.wrap(text, width))


def truth_caption(truth: GroundTruth | None, covered: list[str], labels: list[str]) -> str:
    """How the figure shows the ground truth: nothing when it has none to show."""
    if truth is None or not covered:
        return ""
    where = "" if covered == labels else f", at steps {', '.join(covered)}"
    return f"Hatched: {truth.agent}'s ground truth (brain/groundtruth/{truth.scenario}.toml){where}."


def _paragraph(text: str) -> list[str]:
    """A markdown paragraph wrapped to 95 characters, and the blank line before it."""
    return ["", *textwrap.wrap(text, 95)]


def steps_section(rows: list[MindRow], agent: str, smooth: Table, online: Table) -> str:
    """``report.md``'s "Reading the steps": what a step is, what the first step holds (the
    prior, when it comes before any decision), and where the smoothed preference disagrees
    with the online one, and why (``smooth`` and ``online``: :func:`labelled` tables)."""
    steps = steps_of(rows, agent)
    if not steps:
        return ""
    first = steps[0]
    ticks = ", ".join(f"step {s.label} at tick {s.tick}" for s in steps)
    lines = ["", "## Reading the steps"]
    lines += _paragraph(
        f"A step is a labelled waypoint of the scenario's script: the tick at which {agent} completed "
        f"the script step with that label (the engine's `waypoint` event), with the estimates after "
        f"that tick's events: {ticks}."
    )
    if first.decided:
        start = f"already weigh {agent}'s first decision (what {agent} did at or before that tick)"
    else:
        start = (
            f"come before any decision of {agent}'s: they are the prior, revised only by what {agent} "
            f"could see, not evidence of what {agent} believes or wants"
        )
    lines += _paragraph(f"The estimates at step {first.label}, the first, {start}.")
    shifts = [s for s in steps if _disagreement(smooth, online, s.label) is not None]
    if shifts:
        lines += _paragraph(_shift_text(agent, shifts, smooth, online))
    return "\n".join(lines) + "\n"


def _disagreement(smooth: Table, online: Table, label: str) -> tuple[str, str] | None:
    """The online and smoothed favourite goals at a step when they disagree (:data:`DISAGREE`)."""
    on, sm = online[label]["preference"]["-"], smooth[label]["preference"]["-"]
    if not on or not sm:
        return None
    best_on, best_sm = max(on, key=on.__getitem__), max(sm, key=sm.__getitem__)
    if best_on == best_sm or on[best_on] - sm[best_on] < DISAGREE:
        return None
    return best_on, best_sm


def _shift_text(agent: str, shifts: list[LabelledStep], smooth: Table, online: Table) -> str:
    """The paragraph on the steps whose smoothed preference disagrees with the online one."""
    first = shifts[0]
    best_on, best_sm = _disagreement(smooth, online, first.label) or ("", "")
    on, sm = online[first.label]["preference"]["-"], smooth[first.label]["preference"]["-"]
    listed = ("steps " if len(shifts) > 1 else "step ") + ", ".join(s.label for s in shifts)
    return (
        "An online estimate uses what happened up to its tick, a smoothed one the whole run. The "
        f"preference at a step is the one {agent} acts on next: after each decision the model lets a "
        "person change their mind (the likelier the longer since their previous decision). Where the "
        f"two disagree ({listed}), what {agent} did afterwards is better explained by a change of mind "
        f"soon after that step than by the wish the step itself shows: at step {first.label}, "
        f"P({best_on}) is {on[best_on]:.2f} online but {sm[best_on]:.2f} smoothed, which favours "
        f"{best_sm} ({sm[best_sm]:.2f})."
    )
