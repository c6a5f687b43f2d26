"""What the rating page draws, as plain JSON-ready data: the scene's plan (rooms, doors,
item spots, people) once per recording, and the bodies' positions tick by tick up to the
tick a question shows. Positions are in grid cells (``x`` along columns, ``y`` along rows,
fractional: a body at a cell's centre is at ``col + 0.5``), so the page needs no metres."""

from __future__ import annotations

from typing import Any

import numpy as np

from bridge.recording import Trace
from protocol import AgentKind, Scene
from toyroom.view.colours import REGION_COLOURS, item_colour, person_colour

MAX_FRAMES = 120
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


def frames(trace: Trace, until: int) -> list[dict[str, Any]]:
    """The bodies tick by tick up to ``until`` (at most :data:`MAX_FRAMES` ticks): per frame
    the tick and ``[x, y]`` (cells) of each agent and item (``null`` for an item not in the
    state), in :func:`plan`'s order; an item's ``held`` names who carries it."""
    scene = trace.info.scene
    size, ox, oy = scene.cell_size, scene.origin.x, scene.origin.y
    states = {state.tick: state for state, _ in trace.ticks if state.tick <= until}
    if not states:
        return []
    known = sorted(states)
    wanted = frame_ticks(known[0], known[-1])
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
