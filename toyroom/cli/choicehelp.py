"""What ``toyroom eval --help`` says of each value of its sets of choices (the enums of
:mod:`protocol.choices`): one note per value, so that a value added to an enum and not
described here fails as soon as the parser is built."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TypeVar

from protocol import Choice, EpisodeKind, Minds, Perception, Policy

PERCEPTION_NOTES = {
    Perception.OMNISCIENT: "the robot sees every item",
    Perception.EMBODIED: "only from its own cell",
}
MINDS_NOTES = {
    Minds.SIMPLE: "people perceive exactly",
    Minds.RICH: "they forget, overlook, gossip, wander",
    Minds.MODEL: "they act by the brain's planner under --set's settings",
}
KIND_NOTES = {
    EpisodeKind.EVERYDAY: "random episodes",
    EpisodeKind.TASKS: "built around the robot's jobs",
}
C = TypeVar("C", bound=Choice)

POLICY_NOTES = {
    Policy.TOM: "on inferred minds",
    Policy.BENEFIT: "the same, each task by its expected benefit",
    Policy.TIDY: "put every moved item back",
    Policy.ANNOUNCE: "tell everyone of every move",
    Policy.ORACLE: "reads the simulated people's true minds: an upper bound, not a robot one could build",
}


def described(choices: type[C], notes: Mapping[C, str], last: str = " or ") -> str:
    """``a (note), b (note) or c (note)``: every value of ``choices`` in order, each with its
    note, the last joined by ``last`` (raises ``KeyError`` naming a value without a note)."""
    parts = [f"{choice.value} ({notes[choice]})" for choice in choices]
    return last.join([", ".join(parts[:-1]), parts[-1]]) if len(parts) > 1 else parts[0]
