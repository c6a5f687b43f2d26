"""Drawing a world in meshcat: the map (floors coloured by region, walls with door gaps,
item spots), people, the robot and the items moving with each state, and the brain's
estimates as overlays (a bar per item and location for each person's believed probability,
a mark over the item they most likely want, a red disc while a false belief is flagged, a
sign over the robot with its task and last utterance)."""

from __future__ import annotations

import io
import threading
from collections.abc import Sequence
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import meshcat  # noqa: E402
import meshcat.geometry as g  # noqa: E402
import meshcat.transformations as tf  # noqa: E402
import numpy as np  # noqa: E402

from protocol import NEIGHBOURS, AgentKind, ItemShape, Mind, Scene, State  # noqa: E402

from ..pubsub import Received  # noqa: E402

REGION_COLOURS = [0xE8D5B7, 0xB7D3E8, 0xC8E8B7, 0xE8B7D9, 0xF2E6A0, 0xD0D0D0, 0xB7E8E0, 0xE0C0A0]
PERSON_COLOURS = [0x1F77B4, 0x2CA02C, 0x9467BD, 0x8C564B, 0x17BECF]
BAR_COLOURS = [0x9ECAE1, 0xA1D99B, 0xCBC9E2, 0xD9B99B, 0x9EDAE5]
"""Belief bars: a light tint of their person's colour."""
ITEM_COLOURS: dict[str, int] = {
    ItemShape.BALL: 0xD62728,
    ItemShape.BOARD: 0xFF7F0E,
    ItemShape.MARBLE: 0xE377C2,
    ItemShape.BLOCK: 0xBCBD22,
}
ROBOT_COLOUR = 0x444444
HALO_COLOUR = 0xFF0000
WALL_HEIGHT = 0.6
REFRESH_HZ = 30.0


def _material(colour: int, opacity: float = 1.0) -> g.MeshLambertMaterial:
    """A lit material (floors, walls)."""
    return g.MeshLambertMaterial(color=colour, opacity=opacity, transparent=opacity < 1.0)


def _flat(colour: int) -> g.MeshBasicMaterial:
    """An unlit material: the colour on screen is exactly ``colour`` (people, items, overlays)."""
    return g.MeshBasicMaterial(color=colour)


def _text_texture(lines: Sequence[str]) -> g.ImageTexture:
    """A PNG of ``lines`` (for the robot's sign)."""
    fig = plt.figure(figsize=(4, 1), dpi=100)
    fig.patch.set_facecolor("white")
    fig.text(0.02, 0.5, "\n".join(lines) or " ", va="center", ha="left", fontsize=11, family="sans-serif")
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png", facecolor="white")
    plt.close(fig)
    return g.ImageTexture(image=g.PngImage(buffer.getvalue()))


class SceneView:
    """Draws one world's scene, state and minds into a meshcat visualizer."""

    def __init__(self, vis: meshcat.Visualizer) -> None:
        self.vis = vis
        self.scene: Scene | None = None
        self.state: State | None = None
        self.mind: Mind | None = None
        self.sign = ""
        self.dirty = threading.Event()
        self.lock = threading.Lock()

    # ----- static map ---------------------------------------------------------------------

    def draw_scene(self, scene: Scene) -> None:
        """(Re)draw the map, the bodies and the bars for a new scene."""
        with self.lock:
            self.scene, self.state, self.mind, self.sign = scene, None, None, ""
        self.vis["/meshcat"].delete()
        width, height = scene.columns * scene.cell_size, scene.rows * scene.cell_size
        self.vis["/meshcat"].set_transform(
            tf.translation_matrix([-(scene.origin.x + width / 2), -(scene.origin.y + height / 2), 0])
        )
        vis = self.vis["/meshcat"]
        size = scene.cell_size
        walkable = scene.walkable()
        for ri, region in enumerate(scene.regions):
            material = _material(REGION_COLOURS[ri % len(REGION_COLOURS)])
            for cell in region.cells:
                centre = scene.cell_centre(cell)
                node = vis["map/floor"][f"{region.id}_{cell.col}_{cell.row}"]
                node.set_object(g.Box([size, size, 0.02]), material)
                node.set_transform(tf.translation_matrix([centre.x, centre.y, -0.01]))
        for door in scene.doors:
            centre = scene.cell_centre(door.cell)
            node = vis["map/doors"][door.id]
            node.set_object(g.Box([size, size, 0.02]), _material(0xFFFFFF))
            node.set_transform(tf.translation_matrix([centre.x, centre.y, -0.01]))
        wall = _material(0x555555)
        count = 0
        for col, row in walkable:
            for dc, dr in NEIGHBOURS:
                if (col + dc, row + dr) in walkable:
                    continue
                x = scene.origin.x + (col + 0.5 + dc / 2) * size
                y = scene.origin.y + (row + 0.5 + dr / 2) * size
                dims = [0.06, size, WALL_HEIGHT] if dc else [size, 0.06, WALL_HEIGHT]
                node = vis["map/walls"][str(count)]
                node.set_object(g.Box(dims), wall)
                node.set_transform(tf.translation_matrix([x, y, WALL_HEIGHT / 2]))
                count += 1
        for loc in scene.locations:
            centre = scene.cell_centre(loc.cell)
            node = vis["map/spots"][loc.id]
            node.set_object(
                g.Box([size * 0.6, size * 0.6, 0.04]), _material(0x333333 if not loc.play else 0x2E8B57, 0.5)
            )
            node.set_transform(tf.translation_matrix([centre.x, centre.y, 0.02]))
        people = [a for a in scene.agents if a.kind is AgentKind.PERSON]
        for pi, agent in enumerate(people):
            vis["agents"][agent.id].set_object(
                g.Cylinder(1.0, agent.radius), _material(PERSON_COLOURS[pi % 5])
            )
        for agent in scene.agents:
            if agent.kind is AgentKind.ROBOT:
                vis["agents"][agent.id].set_object(
                    g.Box([agent.radius * 2, agent.radius * 2, 0.5]), _material(ROBOT_COLOUR)
                )
        for item in scene.items:
            colour = ITEM_COLOURS.get(item.shape, 0xBCBD22)
            shapes: dict[str, Any] = {  # any other shape, known or not, is a block
                ItemShape.BALL: g.Sphere(0.16),
                ItemShape.BOARD: g.Box([0.45, 0.18, 0.06]),
                ItemShape.MARBLE: g.Sphere(0.09),
            }
            shape = shapes.get(item.shape, g.Box([0.22, 0.22, 0.22]))
            vis["items"][item.id].set_object(shape, _flat(colour))
        self.dirty.set()

    # ----- dynamic ---------------------------------------------------------------------------

    def on_state(self, state: State, _: Received) -> None:
        with self.lock:
            self.state = state
        self.dirty.set()

    def on_mind(self, mind: Mind, _: Received) -> None:
        with self.lock:
            self.mind = mind
        self.dirty.set()

    def render(self) -> None:
        """Move bodies and redraw overlays to the newest state and mind."""
        with self.lock:
            scene, state, mind = self.scene, self.state, self.mind
        if scene is None:
            return
        vis = self.vis["/meshcat"]
        people = [a.id for a in scene.agents if a.kind is AgentKind.PERSON]
        if state is not None:
            for agent in state.agents:
                z = 0.5
                rotation = tf.rotation_matrix(np.pi / 2, [1, 0, 0]) if agent.id in people else np.eye(4)
                transform = tf.translation_matrix([agent.pose.x, agent.pose.y, z]) @ rotation
                vis["agents"][agent.id].set_transform(transform)
            for item in state.items:
                z = 1.15 if item.held_by else 0.2
                vis["items"][item.id].set_transform(tf.translation_matrix([item.pose.x, item.pose.y, z]))
        if mind is not None and state is not None:
            self._overlays(scene, state, mind, people)

    def _overlays(self, scene: Scene, state: State, mind: Mind, people: list[str]) -> None:
        vis = self.vis["/meshcat"]
        spots = {loc.id: scene.cell_centre(loc.cell) for loc in scene.locations}
        items = [i.id for i in scene.items]
        positions = {a.id: a.pose for a in state.agents}
        size = scene.cell_size
        for agent in mind.agents:
            if agent.agent not in people:
                continue
            pi = people.index(agent.agent)
            colour = PERSON_COLOURS[pi % 5]
            for belief in agent.beliefs:
                ki = items.index(belief.item) if belief.item in items else 0
                for prob in belief.locations:
                    centre = spots.get(prob.id)
                    if centre is None:
                        continue
                    height = max(prob.p, 1e-3) * 0.9
                    x = centre.x - size * 0.4 + size * 0.16 * (pi * len(items) + ki) + 0.06
                    node = vis["minds"][agent.agent]["bars"][belief.item][prob.id]
                    node.set_object(g.Box([0.12, 0.12, height]), _flat(BAR_COLOURS[pi % 5]))
                    node.set_transform(tf.translation_matrix([x, centre.y - size * 0.38, height / 2]))
            pose = positions.get(agent.agent)
            if pose is None:
                continue
            preferred = max(agent.preference, key=lambda p: p.p).id if agent.preference else None
            mark = vis["minds"][agent.agent]["prefers"]
            if preferred in items:
                item_pose = next((i.pose for i in state.items if i.id == preferred), None)
                if item_pose is not None:
                    mark.set_object(g.Sphere(0.08), _flat(colour))
                    mark.set_transform(tf.translation_matrix([item_pose.x, item_pose.y, 1.6]))
            else:
                mark.delete()
            halo = vis["minds"][agent.agent]["false_belief"]
            if agent.false_beliefs:
                halo.set_object(g.Cylinder(0.04, 0.5), _flat(HALO_COLOUR))  # a red disc at their feet
                halo.set_transform(
                    tf.translation_matrix([pose.x, pose.y, 0.03]) @ tf.rotation_matrix(np.pi / 2, [1, 0, 0])
                )
            else:
                halo.delete()
        for robot in mind.robots:
            pose = positions.get(robot.robot)
            text = [
                f"{robot.robot}: {robot.task}",
                robot.detail[:60],
                f'"{robot.utterance[:60]}"' if robot.utterance else "",
            ]
            sign = "\n".join(text)
            if pose is not None and sign != self.sign:
                self.sign = sign
                node = vis["robot_sign"]
                node.set_object(g.Box([2.0, 0.01, 0.5]), g.MeshBasicMaterial(map=_text_texture(text)))
            if pose is not None:
                vis["robot_sign"].set_transform(tf.translation_matrix([pose.x, pose.y, 1.5]))
