"""What the live view's panels say: per person, what the brain infers of their beliefs and
desire (false beliefs in red), the robot's task, and a legend of the scene's colours. Each
is a list of :class:`~toyroom.view.text.Line` for :func:`~toyroom.view.text.draw_lines`."""

from __future__ import annotations

import textwrap
from collections.abc import Sequence

from protocol import AgentKind, AgentMind, AgentSpec, ItemState, Mind, Prob, Scene, State

from .colours import (
    DOOR_COLOUR,
    FALSE_TEXT,
    HALO_COLOUR,
    INK,
    MUTED,
    PLAY_SPOT_COLOUR,
    ROBOT_COLOUR,
    SPOT_COLOUR,
    bar_colour,
    item_colour,
    person_colour,
)
from .text import Line, Span, Swatch

LEAST_SHOWN = 0.05
"""Probabilities below this are left out of a panel line (the likeliest one always shows)."""
MOST_SHOWN = 3
"""At most this many entries of a distribution on a panel line."""


def people(scene: Scene) -> list[AgentSpec]:
    """The scene's people, in its order (which gives each their colour)."""
    return [a for a in scene.agents if a.kind is AgentKind.PERSON]


def title(agent: AgentSpec) -> str:
    """``A1 · Agent 1``, or the id alone when the agent has no other name."""
    return f"{agent.id} · {agent.name}" if agent.name and agent.name.lower() != agent.id.lower() else agent.id


def likeliest(probs: Sequence[Prob]) -> str:
    """``S2 0.62, P2 0.30``: the likeliest entries, most probable first (at most
    :data:`MOST_SHOWN`, none under :data:`LEAST_SHOWN` but the first)."""
    ranked = sorted(probs, key=lambda prob: -prob.p)
    shown = [prob for i, prob in enumerate(ranked[:MOST_SHOWN]) if i == 0 or prob.p >= LEAST_SHOWN]
    return ", ".join(f"{prob.id} {prob.p:.2f}" for prob in shown) or "-"


def whereabouts(item: ItemState | None) -> str:
    """Where an item truly is: ``at S1``, ``with A2`` (carried), ``in E`` (on the floor)."""
    if item is None:
        return "not seen"
    if item.held_by:
        return f"with {item.held_by}"
    return f"at {item.location}" if item.location else f"in {item.region}"


def _person(agent: AgentMind, spec: AgentSpec, colour: int, truth: dict[str, ItemState]) -> list[Line]:
    """A person's lines: a heading, what they want, where they believe each item is."""
    lines: list[Line] = [(Swatch(colour, "disc"), Span(title(spec), colour, bold=True))]
    if agent.preference:
        lines.append((Span("  wants: ", MUTED), Span(likeliest(agent.preference))))
    for belief in agent.beliefs:
        false = belief.item in agent.false_beliefs
        ink = FALSE_TEXT if false else INK
        line: Line = (Span(f"  {belief.item}: ", ink, bold=True), Span(likeliest(belief.locations), ink))
        if false:
            line += (Span(f"  ✗ {whereabouts(truth.get(belief.item))}", FALSE_TEXT, bold=True),)
        lines.append(line)
    intention = agent.intention
    if intention is not None and intention.item is not None:
        lines.append(
            (Span(f"  heading for {intention.item} at {intention.location} ({intention.p:.2f})", MUTED),)
        )
    return lines


def mind_lines(scene: Scene, state: State | None, mind: Mind, wrap: int = 36) -> list[Line]:
    """The minds panel: the tick, each person of the scene the mind speaks of (in the
    scene's order), then each robot's task, detail and last utterance (wrapped at ``wrap``
    characters)."""
    truth = {item.id: item for item in state.items} if state is not None else {}
    minds = {agent.agent: agent for agent in mind.agents}
    lines: list[Line] = [(Span(f"What the brain infers · tick {mind.tick}", MUTED, bold=True),)]
    for index, spec in enumerate(people(scene)):
        if spec.id in minds:
            lines += _person(minds[spec.id], spec, person_colour(index), truth)
    for robot in mind.robots:
        lines.append((Swatch(ROBOT_COLOUR), Span(f"{robot.robot}: {robot.task}", INK, bold=True)))
        for text in textwrap.wrap(robot.detail, wrap - 2):
            lines.append((Span(f"  {text}", MUTED),))
        if robot.utterance:
            for text in textwrap.wrap(f"“{robot.utterance}”", wrap - 2):
                lines.append((Span(f"  {text}", INK),))
    return lines


def legend_lines(scene: Scene) -> list[Line]:
    """The legend: who is who (a person's disc and belief-bar tint), the robot, the items,
    and what the marks mean."""
    folks = people(scene)
    lines: list[Line] = [(Span("Legend", MUTED, bold=True),)]
    for index, spec in enumerate(folks):
        lines.append(
            (
                Swatch(person_colour(index), "disc"),
                Span(title(spec), person_colour(index), bold=True),
                Span("   bars "),
                Swatch(bar_colour(index), "bar"),
            )
        )
    for agent in scene.agents:
        if agent.kind is AgentKind.ROBOT:
            lines.append((Swatch(ROBOT_COLOUR), Span(f"{title(agent)}: the robot")))
    for item in scene.items:
        lines.append((Swatch(item_colour(item.shape), "disc"), Span(f"{item.id} ({item.shape})")))
    items = ", ".join(item.id for item in scene.items)
    lines += [
        (Swatch(SPOT_COLOUR), Span("item spot "), Swatch(PLAY_SPOT_COLOUR), Span("play spot")),
        (Swatch(bar_colour(0), "bar"), Span("bar at a spot: P(person thinks")),
        (Span("     the item is there); full cell = 1"),),
        (Span(f"     rows per person: {items}"),),
        (
            Swatch(HALO_COLOUR, "ring"),
            Span("false belief (and "),
            Span("red text", FALSE_TEXT, bold=True),
            Span(")"),
        ),
        (Span("  ✗ at ...", FALSE_TEXT, bold=True), Span(": where the item really is")),
        (Swatch(person_colour(0), "disc"), Span("dot by an item: wanted most")),
        (Swatch(DOOR_COLOUR), Span("door; floors tinted by room")),
    ]
    return lines
