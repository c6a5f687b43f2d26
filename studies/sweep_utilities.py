"""Which utilities of leaving and of the other item reproduce the paper's Section V.

Runs paper-1..3 through the engine core and the brain in one process for each
(leave_utility_item, other_utility) pair and prints which Section V statements fail
(smoothed estimates). This is the sweep behind docs/model.md's choice of defaults.

    python studies/sweep_utilities.py
"""

from __future__ import annotations

import itertools

from rich.console import Console
from rich.table import Table

from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from sim2d.engine import Engine

PAIRS = [(10.0, 5.0), (5.0, 2.0), (4.0, 2.0), (3.0, 1.0), (3.0, 0.0), (2.0, 1.0), (2.0, 0.0), (0.0, 5.0)]


def labelled(
    scenario: str, settings: ModelSettings
) -> dict[str, tuple[dict[str, dict[str, float]], dict[str, float]]]:
    """A1's smoothed beliefs and preference at each of its labelled steps."""
    engine = Engine(scenario)
    tracker = MindTracker(engine.scene(), settings)
    tracker.observe(engine.state(), ())
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
    track = tracker.tracks["A1"]
    smoothed = tracker.smoothed("A1")
    ticks = [s.tick for s in track.steps]
    model = tracker.model
    out = {}
    for (tick, agent), label in tracker.labels.items():
        if agent == "A1":
            i = max(j for j, t in enumerate(ticks) if t <= tick)
            est = smoothed[i]
            beliefs = {
                item: dict(zip(model.locations, est.beliefs[k], strict=True))
                for k, item in enumerate(model.items)
            }
            out[label] = (beliefs, dict(zip((*model.items, "out"), est.preference, strict=True)))
    return out


def failures(settings: ModelSettings) -> list[str]:
    runs = {name: labelled(name, settings) for name in ("paper-1", "paper-2", "paper-3")}
    fails = []
    for name, steps in runs.items():
        for step in "2345":
            b = steps[step][0]
            if b["skate"]["S1"] < 0.8:
                fails.append(f"{name}@{step} skate")
            s2, p2 = b["ball"]["S2"], b["ball"]["P2"]
            if s2 + p2 < 0.8 or max(s2, p2) > 0.9:
                fails.append(f"{name}@{step} ball S2 {s2:.2f} P2 {p2:.2f}")
    for name in ("paper-1", "paper-2"):
        b6, p6 = runs[name]["6"]
        b7 = runs[name]["7"][0]
        if (
            b6["ball"]["S1"] < 0.8
            or b6["skate"]["S1"] > 0.2
            or b7["skate"]["P2"] < 0.8
            or b7["ball"]["S1"] < 0.8
        ):
            fails.append(f"{name}@6-7 beliefs")
        if p6["skate"] <= p6["ball"]:
            fails.append(f"{name}@6 preference")
    if runs["paper-1"]["8"][1]["skate"] <= runs["paper-1"]["8"][1]["ball"]:
        fails.append("paper-1@8 preference")
    b9, p9 = runs["paper-2"]["9"]
    if b9["ball"]["P1"] < 0.8 or p9["ball"] <= p9["skate"]:
        fails.append("paper-2@9")
    b6, p6 = runs["paper-3"]["6"]
    if b6["ball"]["S2"] > 0.2 or b6["skate"]["P2"] < 0.8 or p6["ball"] <= p6["skate"]:
        fails.append("paper-3@6")
    if runs["paper-3"]["7"][0]["ball"]["S1"] < 0.8:
        fails.append("paper-3@7")
    return fails


def main() -> None:
    table = Table(title="Section V statements (smoothed) by utility of leaving / of the other item")
    table.add_column("leave (item lover)", justify="right")
    table.add_column("other item", justify="right")
    table.add_column("paper-3 steps 2-5: P(ball S2) / P(ball P2)")
    table.add_column("failing statements")
    for leave, other in PAIRS:
        settings = ModelSettings(leave_utility_item=leave, other_utility=other)
        ball = labelled("paper-3", settings)["3"][0]["ball"]
        fails = failures(settings)
        summary = sorted({f.split(" ")[0] for f in fails})
        table.add_row(
            f"{leave:g}",
            f"{other:g}",
            f"{ball['S2']:.2f} / {ball['P2']:.2f}",
            "[green]none[/]" if not fails else f"[red]{', '.join(itertools.islice(summary, 6))}[/]",
        )
    Console().print(table)


if __name__ == "__main__":
    main()
