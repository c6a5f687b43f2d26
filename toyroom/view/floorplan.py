"""The static part of the live view, drawn once per scene: floors tinted by region with
the room names on them, walls with door gaps, item spots with their names, the people's
and the robot's bodies with their labels, the items, the belief bars (moved later), and the
legend. All lie on the floor plane, seen from above (see :mod:`.layout`)."""

from __future__ import annotations

from typing import Any

import meshcat
import meshcat.geometry as g
import meshcat.transformations as tf
import numpy as np

from protocol import NEIGHBOURS, AgentKind, ItemShape, Region, Scene

from .colours import (
    DOOR_COLOUR,
    PLAY_SPOT_COLOUR,
    REGION_COLOURS,
    ROBOT_COLOUR,
    SPOT_COLOUR,
    WALL_COLOUR,
    bar_colour,
    item_colour,
    person_colour,
)
from .layout import PANEL_Z, Layout
from .panel import legend_lines, people
from .text import LINE_SPACING, draw_label, draw_lines, fit_font, plane

# Heights (metres) set what covers what in the top-down view, bottom to top: floors, spots,
# bars, room names, walls, spot names, panels, bodies, people's labels, items, dots. They are
# kept low so that a perspective camera shows little parallax (see .layout).
WALL_HEIGHT = 0.3
BODY_HEIGHT = 0.5
"""People's cylinders; the robot's box is 0.8 of it."""
WALL_THICKNESS = 0.1
ROOM_FONT_PX = 20.0
"""Room names (reference pixels), shrunk to fit their room's width."""
SPOT_FONT_PX = 13.0
PERSON_FONT_PX = 16.0
PANEL_FONT_PX = 14.0
"""The panels' largest font (reference pixels); they shrink it to fit."""
LABEL_Z = 0.55
"""People's labels: above bodies and walls, under the items (which they never hide)."""
SPOT_LABEL_Z = 0.35
BAR_BAND = (-0.47, -0.2)
"""The bars' band in a spot's cell, from its centre (cell sizes): under the item resting there."""


def flat(colour: int, opacity: float = 1.0) -> g.MeshBasicMaterial:
    """An unlit material: the colour on screen is exactly ``colour``."""
    return g.MeshBasicMaterial(color=colour, opacity=opacity, transparent=opacity < 1.0)


def put(node: meshcat.Visualizer, x: float, y: float, z: float) -> None:
    """Move ``node`` to scene point ``(x, y, z)`` (metres)."""
    node.set_transform(tf.translation_matrix([x, y, z]))


def label(node: meshcat.Visualizer, text: str, font_px: float, layout: Layout, **style: Any) -> float:
    """Set ``node`` to a label plane of ``text`` (see :func:`~.text.draw_label` for
    ``style``); returns its height in metres."""
    png, width, height = draw_label(text, font_px, **style)
    node.set_object(*plane(png, layout.metres(width), layout.metres(height)))
    return layout.metres(height)


def draw_floors(vis: meshcat.Visualizer, scene: Scene, layout: Layout) -> None:
    """Floors tinted by region, each named on its lowest row; doors in white."""
    size = scene.cell_size
    for ri, region in enumerate(scene.regions):
        material = flat(REGION_COLOURS[ri % len(REGION_COLOURS)])
        for cell in region.cells:
            centre = scene.cell_centre(cell)
            node = vis["map/floor"][f"{region.id}_{cell.col}_{cell.row}"]
            node.set_object(g.Box([size, size, 0.02]), material)
            put(node, centre.x, centre.y, -0.01)
        if region.cells:
            text = region.name or region.id
            natural_px = draw_label(text, ROOM_FONT_PX)[1]
            x, y, cells = name_place(scene, region, natural_px / (size * layout.px_per_m))
            name = vis["map/names"][region.id]
            clear = (255, 255, 255, 0)
            label(
                name,
                text,
                ROOM_FONT_PX,
                layout,
                background=clear,
                max_width_px=(cells - 0.2) * size * layout.px_per_m,
            )
            put(name, x, y, 0.03)
    for door in scene.doors:
        centre = scene.cell_centre(door.cell)
        node = vis["map/doors"][door.id]
        node.set_object(g.Box([size, size, 0.02]), flat(DOOR_COLOUR))
        put(node, centre.x, centre.y, -0.01)


def _runs(cols: list[int]) -> list[list[int]]:
    """Sorted column numbers split into runs of consecutive ones."""
    runs: list[list[int]] = []
    for col in cols:
        if runs and col == runs[-1][-1] + 1:
            runs[-1].append(col)
        else:
            runs.append([col])
    return runs


def name_place(scene: Scene, region: Region, need: float) -> tuple[float, float, int]:
    """Where to write a region's name: the centre (metres) of the longest run of its cells
    in one row free of item spots and agents' homes, in the lowest row whose run is at least
    ``need`` cells long (else the longest run), and that run's length in cells."""
    blocked = {(loc.cell.col, loc.cell.row) for loc in scene.locations}
    blocked |= {(agent.home.col, agent.home.row) for agent in scene.agents}
    candidates = []  # (row, first col, length), lowest row first
    for row in sorted({cell.row for cell in region.cells}):
        cols = sorted(cell.col for cell in region.cells if cell.row == row and (cell.col, row) not in blocked)
        if cols:
            run = max(_runs(cols), key=len)
            candidates.append((row, run[0], len(run)))
    fitting = [place for place in candidates if place[2] >= need]
    if fitting:
        row, first, length = fitting[0]
    elif candidates:
        row, first, length = max(candidates, key=lambda place: place[2])
    else:  # every cell is a spot or a home: across the lowest row
        row = min(cell.row for cell in region.cells)
        cols = sorted(cell.col for cell in region.cells if cell.row == row)
        first, length = cols[0], cols[-1] - cols[0] + 1
    size = scene.cell_size
    return scene.origin.x + (first + length / 2) * size, scene.origin.y + (row + 0.5) * size, length


def draw_walls(vis: meshcat.Visualizer, scene: Scene) -> None:
    """A wall along every side of a walkable cell that does not lead to another."""
    walkable = scene.walkable()
    size = scene.cell_size
    wall = g.MeshLambertMaterial(color=WALL_COLOUR)
    count = 0
    for col, row in sorted(walkable):
        for dc, dr in NEIGHBOURS:
            if (col + dc, row + dr) in walkable:
                continue
            x = scene.origin.x + (col + 0.5 + dc / 2) * size
            y = scene.origin.y + (row + 0.5 + dr / 2) * size
            dims = [WALL_THICKNESS, size, WALL_HEIGHT] if dc else [size, WALL_THICKNESS, WALL_HEIGHT]
            node = vis["map/walls"][str(count)]
            node.set_object(g.Box(dims), wall)
            put(node, x, y, WALL_HEIGHT / 2)
            count += 1


def draw_spots(vis: meshcat.Visualizer, scene: Scene, layout: Layout) -> None:
    """Item spots (green: play spots), each with its id just above it."""
    size = scene.cell_size
    for loc in scene.locations:
        centre = scene.cell_centre(loc.cell)
        node = vis["map/spots"][loc.id]
        colour = PLAY_SPOT_COLOUR if loc.play else SPOT_COLOUR
        node.set_object(g.Box([size * 0.6, size * 0.6, 0.04]), flat(colour))
        put(node, centre.x, centre.y, 0.02)
        name = vis["map/spot_names"][loc.id]
        style: dict[str, Any] = {"ink": 0xFFFFFF, "background": (51, 51, 51, 215)}
        height = label(name, loc.id, SPOT_FONT_PX, layout, max_width_px=size * 1.2 * layout.px_per_m, **style)
        put(name, centre.x, centre.y + size * 0.3 + height / 2, SPOT_LABEL_Z)


def draw_bodies(vis: meshcat.Visualizer, scene: Scene, layout: Layout) -> None:
    """People (discs of their colour) and the robot (a dark box), each with its id on a
    label above it, and the items (coloured by shape). The bodies' nodes only carry a
    translation, so their labels and marks (children) stay flat."""
    index = {spec.id: i for i, spec in enumerate(people(scene))}
    for agent in scene.agents:
        group = vis["agents"][agent.id]
        if agent.kind is AgentKind.PERSON:
            colour = person_colour(index[agent.id])
            group["body"].set_object(g.Cylinder(BODY_HEIGHT, agent.radius), flat(colour))
            group["body"].set_transform(
                tf.translation_matrix([0, 0, BODY_HEIGHT / 2]) @ tf.rotation_matrix(np.pi / 2, [1, 0, 0])
            )
        else:
            colour = ROBOT_COLOUR
            group["body"].set_object(
                g.Box([agent.radius * 2, agent.radius * 2, BODY_HEIGHT * 0.8]), flat(colour)
            )
            put(group["body"], 0, 0, BODY_HEIGHT * 0.4)
        height = label(group["label"], agent.id, PERSON_FONT_PX, layout, border=colour)
        put(group["label"], 0, agent.radius + height / 2 + 0.05, LABEL_Z)
    for item in scene.items:
        shapes: dict[str, Any] = {  # any other shape, known or not, is a block
            ItemShape.BALL: g.Sphere(0.16),
            ItemShape.BOARD: g.Box([0.45, 0.18, 0.06]),
            ItemShape.MARBLE: g.Sphere(0.09),
        }
        shape = shapes.get(item.shape, g.Box([0.22, 0.22, 0.22]))
        vis["items"][item.id].set_object(shape, flat(item_colour(item.shape)))


def bar_slots(scene: Scene) -> dict[tuple[str, str], int]:
    """Each (person, item)'s row among the bars at a spot, from the top."""
    items = [item.id for item in scene.items]
    return {
        (spec.id, item): pi * len(items) + ki
        for pi, spec in enumerate(people(scene))
        for ki, item in enumerate(items)
    }


def bar_geometry(scene: Scene) -> tuple[float, float]:
    """The height of a bar's row at a spot and the bar's thickness (metres)."""
    rows = max(len(bar_slots(scene)), 1)
    row = (BAR_BAND[1] - BAR_BAND[0]) * scene.cell_size / rows
    return row, row * 0.8


def draw_bars(vis: meshcat.Visualizer, scene: Scene) -> None:
    """A flat belief bar per person, item and spot, in the person's tint; its length is set
    by the view from the brain's minds (invisible until then)."""
    _, thickness = bar_geometry(scene)
    index = {spec.id: i for i, spec in enumerate(people(scene))}
    size = scene.cell_size
    band = (BAR_BAND[1] - BAR_BAND[0]) * size
    for loc in scene.locations:  # a dark track under a spot's bars: they show on any floor
        centre = scene.cell_centre(loc.cell)
        track = vis["map/bar_tracks"][loc.id]
        track.set_object(g.Box([0.9 * size, band, 0.01]), flat(SPOT_COLOUR))
        put(track, centre.x, centre.y + (BAR_BAND[0] + BAR_BAND[1]) / 2 * size, 0.045)
    for person, item in bar_slots(scene):
        for loc in scene.locations:
            node = vis["minds/bars"][person][item][loc.id]
            node.set_object(g.Box([1.0, thickness, 0.01]), flat(bar_colour(index[person])))
            node.set_transform(np.diag([1e-4, 1.0, 1.0, 1.0]))


def draw_legend(vis: meshcat.Visualizer, scene: Scene, layout: Layout) -> float:
    """The legend at the bottom of the panel column; returns its height (reference pixels)."""
    lines = legend_lines(scene)
    panel = layout.panel
    size = fit_font(lines, panel.width - 12, panel.height * 0.45, PANEL_FONT_PX)
    height = len(lines) * size * LINE_SPACING + 12
    png = draw_lines(lines, panel.width, height, size, border=0xBBBBBB)
    node = vis["panels/legend"]
    node.set_object(*plane(png, layout.metres(panel.width), layout.metres(height)))
    x, y = layout.point(panel.left + panel.width / 2, panel.top + panel.height - height / 2)
    put(node, x, y, PANEL_Z)
    return height
