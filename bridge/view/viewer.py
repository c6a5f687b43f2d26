"""The meshcat live view: ``python -m bridge.view [--world W]`` (``toyroom view``).

It reads only the protocol, so it shows a Unity engine's world as well as sim2d's
(:mod:`bridge.view.scene` draws it). It prints its URL, redraws the map when the engine
restarts (a new handshake), and draws at up to 30 Hz. ``--screenshot FILE.png [--after
SECONDS]`` renders the scene in headless Chromium and saves it, once the engine has answered
the handshake and a state and a brain's mind have come; without them it saves nothing and
exits 1 saying which is missing (no engine, an engine of another protocol version, no state,
no brain).
"""

from __future__ import annotations

import argparse
import logging
import sys
import threading
from collections.abc import Sequence
from pathlib import Path

import meshcat

from protocol import EngineInfo, Mind, Scene, State
from protocol import Error as ProtocolError

from ..bridge import Bridge
from ..errors import BridgeError, NoReply
from ..flags import add_log_level, command_parser, configure_logging
from ..handshake import handshake
from ..presence import PresenceEvent
from ..processes import stop_on_signals, stop_process_group, wait_for_stop
from ..session import SessionSettings, add_network_args, settings_from_args
from .scene import REFRESH_HZ, SceneView
from .screenshot import screenshot

log = logging.getLogger("toyroom.view")


class Viewer:
    """The viewer node: a meshcat server, a bridge to the world, and the drawing loop."""

    def __init__(
        self, world: str, settings: SessionSettings | None = None, stop: threading.Event | None = None
    ) -> None:
        self.vis = meshcat.Visualizer()
        self.url = self.vis.url()
        self.view = SceneView(self.vis)
        self.bridge = Bridge(world, settings)
        self.stop = stop or threading.Event()
        self.info: EngineInfo | None = None
        self.problem: str | None = None
        """Why the last handshake failed, other than no answer (another protocol version, an
        inconsistent scene); ``None`` when it did not."""
        self._reconnect = threading.Event()
        self.bridge.subscribe(self.bridge.keys.state, self.view.on_state, expected=State)
        self.bridge.subscribe(self.bridge.keys.mind, self.view.on_mind, expected=Mind)
        self.bridge.presence("engine", self._on_presence)
        self.bridge.token("viewer", "meshcat")
        self.vis["/Background"].set_property("top_color", [0.95, 0.95, 0.97])
        self.vis["/Background"].set_property("bottom_color", [0.85, 0.87, 0.9])
        self.vis["/Grid"].set_property("visible", False)
        self.vis["/Axes"].set_property("visible", False)

    def _on_presence(self, event: PresenceEvent) -> None:
        if event.alive:
            self._reconnect.set()

    def connect(self, timeout: float | None = None) -> bool:
        """(Re)do the handshake and redraw the map; False when no engine answered, or one
        answered that this viewer cannot draw (:attr:`problem` says why, logged once)."""
        try:
            info = handshake(self.bridge, client="toyroom-view", role="viewer", timeout=timeout or 1.0)
        except NoReply:
            return False
        except (ProtocolError, BridgeError) as err:
            if str(err) != self.problem:
                log.error("cannot draw the engine of world '%s': %s", self.bridge.world, err)
            self.problem = str(err)
            return False
        self.problem = None
        if self.info is None or info.scene != self.info.scene or info.episode != self.info.episode:
            self.view.draw_scene(info.scene)
            self._aim(info.scene)
        self.info = info
        return True

    def _aim(self, scene: Scene) -> None:
        """Look down on the map (drawn centred on the origin) from above and in front."""
        distance = max(scene.columns, scene.rows) * scene.cell_size
        self.vis["/Cameras/default/rotated/<object>"].set_property(
            "position", [0, distance * 1.05, distance * 0.3]
        )

    def run(self) -> None:
        """Draw until :attr:`stop` is set; re-handshake when an engine (re)appears."""
        while not self.stop.is_set():
            if self.info is None or self._reconnect.is_set():
                self._reconnect.clear()
                if not self.connect(timeout=1.0):
                    self.stop.wait(0.5)
                    continue
            if self.view.dirty.wait(1.0 / REFRESH_HZ):
                self.view.dirty.clear()
                self.view.render()

    def missing(self, waited: float) -> str | None:
        """What a screenshot would lack after drawing for ``waited`` seconds (no engine, an
        engine it cannot draw, no state, no brain's mind), or ``None`` when nothing is."""
        world = self.bridge.world
        if self.info is None:
            if self.problem is not None:
                return f"the engine of world '{world}' cannot be drawn: {self.problem}"
            return (
                f"no engine answered on world '{world}' within {waited:g} s "
                f"(start one, e.g. `toyroom sim --world {world}`)"
            )
        if self.view.state is None:
            return (
                f"the engine of world '{world}' published no state within {waited:g} s "
                "(a lock-step engine moves only when a brain steps it)"
            )
        if self.view.mind is None:
            return (
                f"no brain published a mind on world '{world}' within {waited:g} s "
                f"(start one, e.g. `toyroom brain --world {world}`)"
            )
        return None

    def close(self) -> None:
        """Stop drawing, close the bridge and stop the meshcat server (its own process group)."""
        self.stop.set()
        self.bridge.close()
        server = self.vis.window.server_proc
        if server is not None:
            stop_process_group(server)


def build_parser() -> argparse.ArgumentParser:
    """``python -m bridge.view``'s options."""
    parser = command_parser("python -m bridge.view", "The meshcat live view of a world.")
    parser.add_argument("--screenshot", type=Path, metavar="FILE.png", help="save a rendering and exit")
    parser.add_argument("--after", type=float, default=3.0, help="seconds to draw before the screenshot")
    add_log_level(parser, "WARNING")
    add_network_args(parser)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """The viewer until SIGINT or SIGTERM (or, with ``--screenshot``, until the picture is
    saved); either way its meshcat server and any Chromium are stopped before it exits."""
    args = build_parser().parse_args(argv)
    configure_logging(args.log_level)
    stop = threading.Event()
    stop_on_signals(stop)  # before the meshcat server starts, so no signal can orphan it
    viewer = Viewer(args.world, settings_from_args(args), stop=stop)
    try:
        print(f"toyroom view: world '{args.world}' at {viewer.url}", flush=True)
        threading.Thread(target=viewer.run, daemon=True).start()
        if args.screenshot is None:
            wait_for_stop(stop)
            return 0
        if wait_for_stop(stop, args.after):
            print("toyroom view: stopped before the screenshot was saved", file=sys.stderr, flush=True)
            return 1
        if (missing := viewer.missing(args.after)) is not None:
            print(f"toyroom view: no screenshot saved: {missing}", file=sys.stderr, flush=True)
            return 1
        if not screenshot(viewer.url, args.screenshot, stop):
            print("toyroom view: stopped before the screenshot was saved", file=sys.stderr, flush=True)
            return 1
        print(f"toyroom view: saved {args.screenshot}", flush=True)
        return 0
    finally:
        viewer.close()
