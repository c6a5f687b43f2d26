"""The meshcat live view: ``python -m toyroom.view [--world W] [--ortho]`` (``toyroom view``).

It reads only the protocol, so it shows a Unity engine's world as well as sim2d's
(:mod:`toyroom.view.scene` draws it, seen from above by the camera :func:`.layout.aim`
sets: perspective, or orthographic with ``--ortho``). It prints its URL, redraws the map
when the engine restarts (a new handshake), moves bodies at up to 30 Hz and redraws the
brain's estimates at up to 5 Hz. ``--screenshot FILE.png [--after SECONDS] [--tick T]``
renders the scene in headless Chromium and saves it, after SECONDS (or, with ``--tick``,
as soon as a mind of tick T or later is drawn, SECONDS at most), once the engine has
answered the handshake and a state and a brain's mind have come; without them it saves
nothing and exits 1 saying which is missing (no engine, an engine of another protocol
version, no state, no brain, no mind of tick T).
"""

from __future__ import annotations

import argparse
import logging
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

import meshcat

from bridge.bridge import Bridge
from bridge.errors import BridgeError, NoReply
from bridge.flags import add_log_level, command_parser, configure_logging
from bridge.handshake import handshake
from bridge.presence import PresenceEvent
from bridge.processes import stop_on_signals, stop_process_group, wait_for_stop
from bridge.session import SessionSettings, add_network_args, settings_from_args, world_problem
from protocol import EngineInfo, Mind, State
from protocol import Error as ProtocolError

from .layout import aim
from .scene import REFRESH_HZ, SceneView
from .screenshot import screenshot
from .server import start_server

log = logging.getLogger("toyroom.view")


class Viewer:
    """The viewer node: a meshcat server, a bridge to the world, and the drawing loop."""

    def __init__(
        self,
        world: str,
        settings: SessionSettings | None = None,
        stop: threading.Event | None = None,
        ortho: bool = False,
    ) -> None:
        self.ortho = ortho
        """Frame the map with an orthographic camera instead of a perspective one."""
        self.stop = stop or threading.Event()
        self.info: EngineInfo | None = None
        self.problem: str | None = None
        """Why the last handshake failed, other than no answer (another protocol version, an
        inconsistent scene); ``None`` when it did not."""
        self._reconnect = threading.Event()
        self._held = threading.Event()
        self._drawing = threading.Lock()
        self.server, zmq_url = start_server()
        """The meshcat server (:mod:`.server`: on 127.0.0.1 only), a process group of its own."""
        try:
            self.bridge = Bridge(world, settings)
        except BaseException:  # no server left behind
            stop_process_group(self.server)
            raise
        try:
            self._draw_into(meshcat.Visualizer(zmq_url=zmq_url))
        except BaseException:
            self.close()
            raise

    def _draw_into(self, vis: meshcat.Visualizer) -> None:
        """Draw the world into ``vis`` (the page's background set, its grid and axes hidden)."""
        self.vis = vis
        self.url: str = vis.url()
        self.view = SceneView(vis)
        self.bridge.subscribe(self.bridge.keys.state, self.view.on_state, expected=State)
        self.bridge.subscribe(self.bridge.keys.mind, self.view.on_mind, expected=Mind)
        self.bridge.presence("engine", self._on_presence)
        self.bridge.token("viewer", "meshcat")
        vis["/Background"].set_property("top_color", [0.95, 0.95, 0.97])
        vis["/Background"].set_property("bottom_color", [0.85, 0.87, 0.9])
        vis["/Grid"].set_property("visible", False)
        vis["/Axes"].set_property("visible", False)

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
            aim(self.vis, self.view.draw_scene(info.scene, info.episode), self.ortho)
        self.info = info
        return True

    def run(self) -> None:
        """Draw until :attr:`stop` is set; re-handshake when an engine (re)appears."""
        while not self.stop.is_set():
            if self._held.is_set():
                self.stop.wait(0.1)
                continue
            if self.info is None or self._reconnect.is_set():
                self._reconnect.clear()
                if not self.connect(timeout=1.0):
                    self.stop.wait(0.5)
                    continue
            # wake at least every frame: a mind held back by MIND_HZ is drawn when it is due
            if self.view.dirty.wait(1.0 / REFRESH_HZ) or self.view.mind_due():
                with self._drawing:
                    if not self._held.is_set():
                        self.view.dirty.clear()
                        self.view.render()
                self.stop.wait(1.0 / REFRESH_HZ)  # at most REFRESH_HZ frames a second

    def hold(self) -> None:
        """Draw nothing more (a frame being drawn is finished first): the picture a
        screenshot then takes is of what is drawn now, and the page gets no more updates (a
        live world's stream kept headless Chromium's virtual time from running out, and
        the screenshot from ever being taken, on a loaded machine)."""
        with self._drawing:
            self._held.set()

    def missing(self, waited: float, tick: int | None = None) -> str | None:
        """What a screenshot would lack after drawing for ``waited`` seconds (no engine, an
        engine it cannot draw, no state, no brain's mind, or, with ``tick``, no mind of that
        tick or later drawn), or ``None`` when nothing is."""
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
        if tick is not None and not self.view.reached(tick):
            state, mind = self.view.drawn_ticks()
            return (
                f"no mind of tick {tick} or later came on world '{world}' within {waited:g} s "
                f"(drawn: the mind of tick {mind}, the state of tick {state})"
            )
        return None

    def close(self) -> None:
        """Stop drawing, close the bridge and stop the meshcat server (its own process group)."""
        self.stop.set()
        self.bridge.close()
        stop_process_group(self.server)


def build_parser() -> argparse.ArgumentParser:
    """``python -m toyroom.view``'s options."""
    parser = command_parser("python -m toyroom.view", "The meshcat live view of a world.")
    parser.add_argument("--screenshot", type=Path, metavar="FILE.png", help="save a rendering and exit")
    parser.add_argument(
        "--after",
        type=float,
        default=3.0,
        help="seconds to draw before the screenshot (with --tick: the most to wait for it)",
    )
    parser.add_argument(
        "--tick",
        type=int,
        metavar="T",
        help="take the screenshot as soon as the brain's mind of tick T or later is drawn",
    )
    parser.add_argument(
        "--ortho",
        action="store_true",
        help="frame the map with an orthographic camera (default: perspective)",
    )
    add_log_level(parser, "WARNING")
    add_network_args(parser)
    return parser


def _wait(viewer: Viewer, stop: threading.Event, seconds: float, tick: int | None) -> bool:
    """Let the viewer draw for ``seconds``, or with ``tick`` until it has drawn that tick (at
    most ``seconds``); whether ``stop`` was set meanwhile."""
    if tick is None:
        return wait_for_stop(stop, seconds)
    deadline = time.monotonic() + seconds
    while not viewer.view.reached(tick):
        left = deadline - time.monotonic()
        if left <= 0:
            return False
        if wait_for_stop(stop, min(left, 0.05)):
            return True
    return stop.is_set()  # what was drawn is on the meshcat server: each command waits for its reply


def main(argv: Sequence[str] | None = None) -> int:
    """The viewer until SIGINT or SIGTERM (or, with ``--screenshot``, until the picture is
    saved); either way its meshcat server and any Chromium are stopped before it exits."""
    args = build_parser().parse_args(argv)
    configure_logging(args.log_level)
    stop = threading.Event()
    if (problem := world_problem(args.world)) is not None:  # before anything starts
        print(f"toyroom view: {problem}", file=sys.stderr, flush=True)
        return 2
    stop_on_signals(stop)  # before the meshcat server starts, so no signal can orphan it
    try:
        viewer = Viewer(args.world, settings_from_args(args), stop=stop, ortho=args.ortho)
    except (BridgeError, ProtocolError) as err:  # a bad Zenoh config file or endpoint
        print(f"toyroom view: {err}", file=sys.stderr, flush=True)
        return 2
    try:
        print(f"toyroom view: world '{args.world}' at {viewer.url}", flush=True)
        threading.Thread(target=viewer.run, daemon=True).start()
        if args.screenshot is None:
            wait_for_stop(stop)
            return 0
        if _wait(viewer, stop, args.after, args.tick):
            print("toyroom view: stopped before the screenshot was saved", file=sys.stderr, flush=True)
            return 1
        if (missing := viewer.missing(args.after, args.tick)) is not None:
            print(f"toyroom view: no screenshot saved: {missing}", file=sys.stderr, flush=True)
            return 1
        viewer.hold()
        if not screenshot(viewer.url, args.screenshot, stop):
            print("toyroom view: stopped before the screenshot was saved", file=sys.stderr, flush=True)
            return 1
        print(f"toyroom view: saved {args.screenshot}", flush=True)
        return 0
    finally:
        viewer.close()
