"""The live table ``toyroom run`` shows: each person's most likely belief per item and
preference, flagged false beliefs, and what the robot is doing. Built from ``brain/mind``
messages only, so it shows any brain's estimates."""

from __future__ import annotations

from rich.table import Table

from protocol import Mind, Prob


def _best(probs: tuple[Prob, ...]) -> str:
    if not probs:
        return "-"
    top = max(probs, key=lambda p: p.p)
    return f"{top.id} {top.p:.2f}"


def mind_table(mind: Mind | None, title: str) -> Table:
    """A table of one ``mind`` message (an empty one before the first)."""
    table = Table(title=title, title_justify="left")
    table.add_column("person")
    table.add_column("believes (most likely)")
    table.add_column("prefers")
    table.add_column("heading for")
    table.add_column("false belief")
    if mind is None:
        table.caption = "waiting for the brain..."
        return table
    for agent in mind.agents:
        beliefs = ", ".join(f"{b.item} @ {_best(b.locations)}" for b in agent.beliefs)
        intention = agent.intention
        heading = (
            "out"
            if intention is not None and intention.item is None
            else f"{intention.item} @ {intention.location} ({intention.p:.2f})"
            if intention is not None
            else "-"
        )
        table.add_row(
            agent.agent, beliefs, _best(agent.preference), heading, ", ".join(agent.false_beliefs) or "-"
        )
    robots = "; ".join(
        f"{r.robot}: {r.task}"
        + (f" ({r.detail})" if r.detail else "")
        + (f' - "{r.utterance}"' if r.utterance else "")
        for r in mind.robots
    )
    table.caption = f"tick {mind.tick}" + (f" | {robots}" if robots else "")
    return table
