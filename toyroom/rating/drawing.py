"""What the rating page draws, as plain JSON-ready data: the scene's plan (rooms, doors,
item spots, people) once per recording, the bodies' positions tick by tick up to the tick a
question shows (enough frames to replay it smoothly at the study's rate, :func:`frames`), and
what was said aloud meanwhile (:func:`captions`). Positions are in grid cells (``x`` along
columns, ``y`` along rows, fractional: a body at a cell's centre is at ``col + 0.5``), so the
page needs no metres."""

from __future__ import annotations

from typing import Any

import numpy as np

from bridge.recording import Trace
from protocol import AgentKind, Event, EventKind, Scene
from toyroom.view.colours import REGION_COLOURS, item_colour, person_colour

FRAMES_PER_SECOND = 10
"""A replay shows about this many frames per second of replay time."""
MAX_FRAMES = 3000
"""At most this many frames of a replay are sent (evenly spaced ticks, the last always in)."""


def _hex(colour: int) -> str:
    return f"#{colour:06x}"


def plan(scene: Scene) -> dict[str, Any]:
    """The scene's static drawing: grid size, rooms (cells, name, tint), door cells, spots
    (id, cell, whether a play spot), agents (id, label, kind, colour) and items (id, label,
    colour), in the live view's colours (:mod:`toyroom.view.colours`)."""
    people = [a for a in scene.agents if a.kind is AgentKind.PERSON]
    return {
        "columns": scene.columns,
        "rows": scene.rows,
        "rooms": [
            {
                "id": r.id,
                "name": r.name or r.id,
                "colour": _hex(REGION_COLOURS[n % len(REGION_COLOURS)]),
                "cells": [[c.col, c.row] for c in r.cells],
            }
            for n, r in enumerate(scene.regions)
        ],
        "doors": [[d.cell.col, d.cell.row] for d in scene.doors],
        "spots": [{"id": s.id, "cell": [s.cell.col, s.cell.row], "play": s.play} for s in scene.locations],
        "agents": [
            {
                "id": a.id,
                "person": a.kind is AgentKind.PERSON,
                "colour": _hex(person_colour(people.index(a))) if a in people else "#444444",
                "radius": a.radius / scene.cell_size,
            }
            for a in scene.agents
        ],
        "items": [
            {"id": i.id, "label": i.name or i.id, "colour": _hex(item_colour(i.shape))}
            for i in scene.items
            if not i.absent
        ],
    }


def frame_ticks(first: int, until: int, most: int = MAX_FRAMES) -> list[int]:
    """At most ``most`` ticks from ``first`` to ``until`` (both in), evenly spaced."""
    if until <= first:
        return [until]
    return sorted({int(t) for t in np.linspace(first, until, min(most, until - first + 1)).round()})


def frames(trace: Trace, until: int, rate: float = 1.0) -> list[dict[str, Any]]:
    """The bodies up to ``until``, at about :data:`FRAMES_PER_SECOND` frames a second of a replay
    at ``rate`` times real time (at most :data:`MAX_FRAMES`): per frame the tick and ``[x, y]``
    (cells) of each agent and item (``null`` for an item not in the state), in :func:`plan`'s
    order; an item's ``held`` names who carries it. The page shows each frame for its ticks'
    time (``tick_seconds / rate`` per tick)."""
    scene = trace.info.scene
    size, ox, oy = scene.cell_size, scene.origin.x, scene.origin.y
    states = {state.tick: state for state, _ in trace.ticks if state.tick <= until}
    if not states:
        return []
    known = sorted(states)
    span_s = (known[-1] - known[0]) * trace.info.tick_seconds / rate
    wanted = frame_ticks(known[0], known[-1], max(2, min(MAX_FRAMES, int(span_s * FRAMES_PER_SECOND) + 1)))
    picks = [known[min(int(np.searchsorted(known, t)), len(known) - 1)] for t in wanted]
    out = []
    for tick in dict.fromkeys(picks):
        state = states[tick]
        agents = {a.id: a for a in state.agents}
        items = {i.id: i for i in state.items}

        def at(pose: Any) -> list[float]:
            return [round((pose.x - ox) / size, 3), round((pose.y - oy) / size, 3)]

        out.append(
            {
                "tick": tick,
                "agents": [at(agents[a.id].pose) if a.id in agents else None for a in scene.agents],
                "items": [
                    {"at": at(items[i.id].pose), "held": items[i.id].held_by} if i.id in items else None
                    for i in scene.items
                    if not i.absent
                ],
            }
        )
    return out


def _caption(event: Event, names: dict[str, str]) -> str | None:
    """One line of what was said aloud at ``event`` (``None``: the event says nothing)."""

    def name(ident: str | None) -> str:
        return names.get(ident or "", ident or "someone")

    who, to, item = name(event.actor), name(event.target), name(event.item)
    detail = f": {event.detail}" if event.detail else ""
    if event.kind == EventKind.SAY:
        return f"{who} to {to}, of the {item}{detail}" if event.item else f"{who} to {to}{detail}"
    if event.kind == EventKind.REQUEST:
        offer = f", for the {name(event.offer)}" if event.offer else ""
        return f"{who} asks {to} for the {item}{offer}"
    if event.kind == EventKind.ASK:
        return f"{who} asks {to} what they are looking for"
    if event.kind in (EventKind.REPLY, EventKind.ANSWER):
        said = "yes" if event.answer else "no"
        return f"{who} answers {said}" + (f": the {item}" if event.item and event.answer else "")
    if event.kind == EventKind.GIVE:
        return f"{who} gives {to} the {item}"
    return None


def captions(trace: Trace, until: int) -> list[dict[str, Any]]:
    """What was said aloud up to ``until`` (the robot's words, requests and questions, and the
    answers), as ``{"tick", "text"}`` in order, for the page to show beside the replay as the
    rater reaches each tick (before issue 55 a rater never saw the robot speak)."""
    scene = trace.info.scene
    names = {a.id: a.name or a.id for a in scene.agents} | {i.id: i.name or i.id for i in scene.items}
    names |= {a.id: "Robot" for a in scene.agents if a.kind is AgentKind.ROBOT}
    out = []
    for state, events in trace.ticks:
        if state.tick > until:
            break
        out += [{"tick": state.tick, "text": text} for e in events if (text := _caption(e, names))]
    return out
