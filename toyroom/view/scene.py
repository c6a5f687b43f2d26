"""Drawing a world in meshcat, seen from above: the map (:mod:`.floorplan`), people, the
robot and the items moving with each state, and the brain's estimates: per person a flat
bar per item at every spot (as long as the believed probability), a dot of their colour by
the item they most likely want, a red ring at their feet while a false belief is flagged,
and, beside the map, a panel of what the brain infers of each person (beliefs and desire
by name, false beliefs in red) and the robot's task, above a legend.

Bodies move at up to :data:`REFRESH_HZ`; the brain's estimates are redrawn at most
:data:`MIND_HZ` times a second, so that a fast brain never makes the view lag."""

from __future__ import annotations

import logging
import threading
import time

import meshcat
import meshcat.geometry as g
import meshcat.transformations as tf
import numpy as np

from bridge.pubsub import Received
from protocol import Mind, Scene, State

from .colours import HALO_COLOUR, person_colour
from .floorplan import (
    BAR_BAND,
    PANEL_FONT_PX,
    bar_geometry,
    bar_slots,
    draw_bars,
    draw_bodies,
    draw_floors,
    draw_legend,
    draw_spots,
    draw_walls,
    flat,
    put,
)
from .layout import PANEL_Z, Layout, frame
from .panel import mind_lines, people
from .text import draw_lines, fit_font, plane

log = logging.getLogger("toyroom.view")

REFRESH_HZ = 30.0
"""The most frames a second the bodies are moved."""
MIND_HZ = 5.0
"""The most times a second the brain's estimates (bars, marks, the panel) are redrawn."""
RESTING_Z = 0.6
"""Height (metres) of an item at rest: above people's labels (see :mod:`.floorplan`)."""
HELD_Z = 0.65
"""Height (metres) of a carried item: over its carrier and their label."""


class SceneView:
    """Draws one world's scene, state and minds into a meshcat visualizer."""

    def __init__(self, vis: meshcat.Visualizer) -> None:
        self.vis = vis
        self.scene: Scene | None = None
        self.layout: Layout | None = None
        self.state: State | None = None
        self.mind: Mind | None = None
        self.dirty = threading.Event()
        """Set when something new came (a scene, a state, a mind) that is not drawn yet."""
        self.lock = threading.Lock()
        self._drawn_state: State | None = None
        self._drawn_mind: Mind | None = None
        self._mind_drawn_at = -np.inf
        self._marks: dict[str, tuple[bool, str | None]] = {}
        """Per person, as drawn: (false belief flagged, the item wearing their dot)."""
        self._panel = ""
        self._legend_px = 0.0

    # ----- static map ---------------------------------------------------------------------

    def draw_scene(self, scene: Scene, episode: int | None = None) -> Layout:
        """(Re)draw the map, the bodies, the bars and the legend for a new scene, centred on
        the origin (see :mod:`.layout`); returns the layout, for the camera. A state and a
        mind already received are kept when they are of ``episode`` (they may come before
        the handshake is answered), else dropped."""
        layout = frame(scene)
        with self.lock:
            self.scene, self.layout = scene, layout
            if self.state is None or self.state.episode != episode:
                self.state = None
            if self.mind is None or self.mind.episode != episode:
                self.mind = None
            self._drawn_state, self._drawn_mind, self._marks, self._panel = None, None, {}, ""
        self.vis["/meshcat"].delete()
        cx, cy = layout.centre
        self.vis["/meshcat"].set_transform(tf.translation_matrix([-cx, -cy, 0]))
        vis = self.vis["/meshcat"]
        draw_floors(vis, scene, layout)
        draw_walls(vis, scene)
        draw_spots(vis, scene, layout)
        draw_bodies(vis, scene, layout)
        draw_bars(vis, scene)
        self._legend_px = draw_legend(vis, scene, layout)
        self.dirty.set()
        return layout

    # ----- dynamic ---------------------------------------------------------------------------

    def on_state(self, state: State, _: Received) -> None:
        with self.lock:
            self.state = state
        self.dirty.set()

    def on_mind(self, mind: Mind, _: Received) -> None:
        log.debug("received the mind of tick %d", mind.tick)
        with self.lock:
            self.mind = mind
        self.dirty.set()

    def mind_due(self) -> bool:
        """Whether a mind came that is not drawn yet and :data:`MIND_HZ` allows drawing it."""
        return self.mind is not self._drawn_mind and time.monotonic() - self._mind_drawn_at >= 1.0 / MIND_HZ

    def drawn_ticks(self) -> tuple[int | None, int | None]:
        """The ticks of the state and of the mind last drawn (``None``: none yet)."""
        state, mind = self._drawn_state, self._drawn_mind
        return (state.tick if state else None), (mind.tick if mind else None)

    def reached(self, tick: int) -> bool:
        """Whether a mind of ``tick`` or later is drawn, over a state (the newest received:
        states are sent drop-on-congestion, so a busy viewer may never get the one of the
        mind's tick; minds are not)."""
        state, mind = self.drawn_ticks()
        return state is not None and mind is not None and mind >= tick

    def render(self) -> None:
        """Move the bodies to the newest state and, when :meth:`mind_due`, redraw the
        brain's estimates."""
        with self.lock:
            scene, state, mind = self.scene, self.state, self.mind
        if scene is None:
            return
        if state is not None and state is not self._drawn_state:
            self.move_bodies(state)
        if mind is not None and state is not None and self.mind_due():
            self.draw_mind(scene, state, mind)

    def move_bodies(self, state: State) -> None:
        """Move every agent and item to where ``state`` has it."""
        vis = self.vis["/meshcat"]
        for agent in state.agents:
            put(vis["agents"][agent.id], agent.pose.x, agent.pose.y, 0.0)
        for item in state.items:
            put(vis["items"][item.id], item.pose.x, item.pose.y, HELD_Z if item.held_by else RESTING_Z)
        self._drawn_state = state

    def draw_mind(self, scene: Scene, state: State, mind: Mind) -> None:
        """Redraw the brain's estimates: bars, rings, dots and the minds panel."""
        self._mind_drawn_at = time.monotonic()
        vis = self.vis["/meshcat"]
        spots = {loc.id: scene.cell_centre(loc.cell) for loc in scene.locations}
        slots = bar_slots(scene)
        row, _ = bar_geometry(scene)
        size = scene.cell_size
        for agent in mind.agents:
            for belief in agent.beliefs:
                slot = slots.get((agent.agent, belief.item))
                if slot is None:
                    continue
                y = BAR_BAND[1] * size - (slot + 0.5) * row
                for prob in belief.locations:
                    centre = spots.get(prob.id)
                    if centre is None:
                        continue
                    length = max(prob.p * 0.9 * size, 1e-4)
                    at = tf.translation_matrix([centre.x - 0.45 * size + length / 2, centre.y + y, 0.06])
                    vis["minds/bars"][agent.agent][belief.item][prob.id].set_transform(
                        at @ np.diag([length, 1.0, 1.0, 1.0])
                    )
        self._draw_marks(scene, mind)
        self._draw_panel(scene, state, mind)
        self._drawn_mind = mind
        log.debug(
            "drew the mind of tick %d in %.0f ms", mind.tick, (time.monotonic() - self._mind_drawn_at) * 1e3
        )

    def _draw_marks(self, scene: Scene, mind: Mind) -> None:
        """Per person, the red ring at their feet (while a false belief is flagged) and the dot
        on the item they most likely want; only what changed is sent."""
        vis = self.vis["/meshcat"]
        folks = people(scene)
        index = {spec.id: i for i, spec in enumerate(folks)}
        radius = {spec.id: spec.radius for spec in folks}
        items = {item.id for item in scene.items}
        for agent in mind.agents:
            if agent.agent not in index:
                continue
            flagged = bool(agent.false_beliefs)
            best = max(agent.preference, key=lambda p: p.p).id if agent.preference else None
            wanted = best if best in items else None
            was_flagged, was_wanted = self._marks.get(agent.agent, (False, None))
            if flagged != was_flagged:
                ring = vis["agents"][agent.agent]["false_belief"]
                if flagged:
                    ring.set_object(g.Cylinder(0.04, radius[agent.agent] * 1.6), flat(HALO_COLOUR))
                    ring.set_transform(
                        tf.translation_matrix([0, 0, 0.03]) @ tf.rotation_matrix(np.pi / 2, [1, 0, 0])
                    )
                else:
                    ring.delete()
            if wanted != was_wanted:
                if was_wanted is not None:
                    vis["items"][was_wanted]["wanted"][agent.agent].delete()
                if wanted is not None:
                    dot = vis["items"][wanted]["wanted"][agent.agent]
                    dot.set_object(g.Sphere(0.08), flat(person_colour(index[agent.agent])))
                    # beside the item (north of it), never hiding it
                    put(dot, (index[agent.agent] - (len(folks) - 1) / 2) * 0.2, 0.28, 0.1)
            self._marks[agent.agent] = (flagged, wanted)

    def _draw_panel(self, scene: Scene, state: State, mind: Mind) -> None:
        """The minds panel at the top of the panel column (resent only when its text changed)."""
        layout = self.layout
        if layout is None:
            return
        panel = layout.panel
        wrap = max(20, int(panel.width / (PANEL_FONT_PX * 0.6)))
        lines = mind_lines(scene, state, mind, wrap)
        text = repr(lines)
        if text == self._panel:
            return
        self._panel = text
        height = panel.height - self._legend_px - 8
        size = fit_font(lines, panel.width - 12, height - 12, PANEL_FONT_PX)
        png = draw_lines(lines, panel.width, height, size, border=0xBBBBBB)
        node = self.vis["/meshcat"]["panels/minds"]
        node.set_object(*plane(png, layout.metres(panel.width), layout.metres(height)))
        x, y = layout.point(panel.left + panel.width / 2, panel.top + height / 2)
        put(node, x, y, PANEL_Z)
