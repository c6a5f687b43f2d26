"""A second, independent engine: a discrete grid (no physics, one move per tick) that plays
the same scenario files as sim2d. Written only from protocol/README.md and the JSON
Schemas: plain ``zenoh`` and ``json``, no toyroom import. It doubles as a fast engine.

    python examples/grid_engine/main.py --scenario paper-2 --world demo [--robot act|observe]

``--gateway ws://127.0.0.1:7448`` makes it an engine without Zenoh, speaking the gateway's
JSON frames over a WebSocket to ``toyroom gateway`` (transport.py has both wires).

``--break MODE`` makes it deliberately wrong in one realistic way, to show that
``toyroom conform`` catches each fault (``--break list`` prints the modes).

``--realtime [--tick-seconds S]`` runs its own clock: a tick every S seconds of wall time
(default 0.7, one move of one cell per tick), paused and resumed on ``engine/control``, and
the robot stopped (its commands failed) when neither a heartbeat nor a command has come on
``robot/<id>/heartbeat`` or ``robot/<id>/command`` for 1 s, as the protocol asks. Without it
the engine is lock-step (``step n``).

``--newer`` makes it a peer of a newer minor version (1.99) that uses what 1.1 does not
know: a capability ``teleport``, item shape ``cup``, region kind ``closet`` (for storage
rooms), an event ``sneeze`` every 10 ticks and a field ``mood`` on every state; a 1.1 peer
must keep working with it.
"""

from __future__ import annotations

import argparse
import signal
import sys
import threading
import time
from pathlib import Path
from typing import Any

import grid_world
from grid_scenario import Scenario, read_scenario
from grid_world import PROTOCOL, GridWorld
from transport import MALFORMED, GatewayTransport, Request, ZenohTransport

TICK_SECONDS = 0.7  # one move of one cell per tick
HEARTBEAT_TIMEOUT = 1.0  # real time: the robot stops after this long without a heartbeat
SCENARIOS = Path(__file__).resolve().parents[2] / "sim2d" / "scenarios"
NEWER = "1.99"
BREAKS = {
    "version": "answers the handshake with protocol 2.0",
    "status": "never publishes a command's 'running' status",
    "double-step": "advances 2n ticks on 'step n'",
    "extra-tick": "advances n+1 ticks on 'step n'",
    "refuse-commands": "fails every robot command ('refused')",
    "omit-lists": "leaves state, events and statuses out of its control replies",
    "events-after-state": "publishes a tick's events after its state",
    "duplicate-status": "publishes every command status twice",
    "never-arrive": "a navigation runs forever and never succeeds",
    "ignore-cancel": "answers a cancel with success but lets the command run on",
    "drop-queued": "drops a command that arrives while another one runs",
    "wrong-encoding": "answers MessagePack queries in JSON",
    "no-visibility": "leaves one walkable cell out of the visibility table",
    "door-in-region": "puts a door on a cell of a region",
    "no-token": "declares no liveliness token",
    "say-one": "tells of the first item of a say alone, ignoring its 'also' (1.6)",
}
"""The deliberate defects of ``--break``, each one ``toyroom conform`` must catch."""


def newer(message: dict[str, Any]) -> dict[str, Any]:
    """``message`` as a 1.99 peer sends it: its version, and on a state a field 1.1 lacks."""
    out = {**message, "protocol": NEWER}
    if out.get("type") == "state":
        out["mood"] = "cheerful"
    if "state" in out and isinstance(out["state"], dict):
        out["state"] = newer(out["state"])
    for key in ("events", "statuses"):
        if key in out:
            out[key] = [newer(m) for m in out[key]]
    return out


def error(code: str, message: str) -> dict[str, Any]:
    return {"type": "error", "protocol": PROTOCOL, "code": code, "message": message}


class GridEngine:
    def __init__(
        self,
        world: str,
        scenario_name: str,
        robot: str | None,
        broken: str | None,
        newer: bool = False,
        gateway: str | None = None,
        tick_seconds: float | None = None,
    ) -> None:
        self.world = world
        self.realtime = tick_seconds is not None
        self.tick_seconds = TICK_SECONDS if tick_seconds is None else tick_seconds
        self.heard = time.monotonic()
        self.newer = newer
        self.paused = False
        self.prefix = f"toyroom/{world}"
        self.robot_override = robot
        self.broken = broken
        self.lock = threading.Lock()
        self.episode = 0
        self.load(scenario_name)
        self.wire: ZenohTransport | GatewayTransport = (
            ZenohTransport(world) if gateway is None else GatewayTransport(gateway, "engine", "grid")
        )
        self.wire.serve("engine/info", self.on_info)
        self.wire.serve("engine/control", self.on_control)
        self.wire.subscribe("robot/*/command", self.on_command)
        self.wire.subscribe("robot/*/heartbeat", self.on_heartbeat)
        if broken != "no-token":
            self.wire.announce("engine", "grid")
        self.stopping = threading.Event()
        if self.realtime:
            threading.Thread(target=self.run_clock, name="grid clock", daemon=True).start()

    def load(self, name: str) -> None:
        path = Path(name) if name.endswith(".toml") else SCENARIOS / f"{name}.toml"
        self.scenario: Scenario = read_scenario(path)
        acts = self.scenario.robot_acts if self.robot_override is None else self.robot_override == "act"
        self.game = GridWorld(
            self.scenario,
            episode=self.episode,
            tick_seconds=self.tick_seconds,
            robot_acts=acts,
            broken=self.broken,
        )

    # ----- the handshake ------------------------------------------------------------------

    def info(self) -> dict[str, Any]:
        m = self.scenario.map
        cell = lambda c: {"col": c[0], "row": c[1]}  # noqa: E731
        agents = [
            {
                "id": a["id"],
                "kind": a["kind"],
                "home": cell(a["home"]),
                "name": a["name"],
                "radius": 0.3 if a["kind"] == "robot" else 0.25,
                "acts": self.game.robot_acts if a["kind"] == "robot" else True,
            }
            for a in self.scenario.agents
        ]
        scene = {
            "name": m.name,
            "cell_size": m.cell_size,
            "origin": {"x": 0.0, "y": 0.0},
            "columns": m.columns,
            "rows": m.rows,
            "regions": [
                {"id": r["id"], "kind": r["kind"], "name": r["name"], "cells": [cell(c) for c in r["cells"]]}
                for r in m.regions
            ],
            "doors": [{"id": d["id"], "cell": cell(d["cell"]), "joins": d["joins"]} for d in m.doors],
            "locations": [
                {
                    "id": loc["id"],
                    "region": loc["region"],
                    "cell": cell(loc["cell"]),
                    "play": loc["play"],
                    "use": loc["use"],
                    "capacity": loc["capacity"],
                }
                for loc in m.locations
            ],
            "visibility": [{"cell": cell(c), "locations": v} for c, v in sorted(m.sees.items())],
            "agents": agents,
            "items": [
                {"id": i["id"], "shape": i["shape"], "name": i["name"], "absent": i["absent"]}
                for i in self.scenario.items
            ],
        }
        if self.broken == "no-visibility":
            scene["visibility"] = scene["visibility"][1:]
        if self.broken == "door-in-region" and scene["doors"]:
            scene["doors"][0]["cell"] = scene["regions"][0]["cells"][0]
        if self.newer:
            for region in scene["regions"]:
                region["kind"] = "closet" if region["kind"] == "storage" else region["kind"]
            for item in scene["items"]:
                item["shape"] = "cup"
        return {
            "type": "engine_info",
            "protocol": "2.0" if self.broken == "version" else NEWER if self.newer else PROTOCOL,
            "engine": "grid-engine 0.1 (example)",
            "world": self.world,
            "scenario": self.scenario.name,
            "capabilities": [
                "realtime" if self.realtime else "lockstep",
                "robot",
                *(["teleport"] if self.newer else []),
            ],
            "clock": "realtime" if self.realtime else "lockstep",
            "tick_seconds": self.tick_seconds,
            "episode": self.episode,
            "scene": scene,
        }

    def on_info(self, query: Request) -> None:
        hello = query.message
        if hello is not None and str(hello.get("protocol", "")).split(".")[0] != PROTOCOL.split(".")[0]:
            query.reply_err(
                error(
                    "version_mismatch", f"this engine speaks {PROTOCOL}, the client {hello.get('protocol')}"
                )
            )
            return
        with self.lock:
            self.reply(query, self.info())

    # ----- the clock --------------------------------------------------------------------

    def reply(self, query: Request, message: dict[str, Any]) -> None:
        """Answer in the query's encoding (as the protocol says; not with ``wrong-encoding``)."""
        mime = "application/json" if self.broken == "wrong-encoding" else query.mime
        query.reply(self.stamped(message), mime)

    def publish(
        self, events: list[dict[str, Any]], statuses: list[dict[str, Any]], state: dict[str, Any]
    ) -> None:
        late = self.broken == "events-after-state"
        for event in [] if late else events:
            self.wire.publish("engine/events", self.stamped(event))
        self.publish_statuses(statuses)
        self.wire.publish("engine/state", self.stamped(state))
        for event in events if late else []:
            self.wire.publish("engine/events", self.stamped(event))

    def stamped(self, message: dict[str, Any]) -> dict[str, Any]:
        return newer(message) if self.newer else message

    def publish_statuses(self, statuses: list[dict[str, Any]]) -> None:
        for status in statuses:
            if self.broken == "status" and status["state"] == "running":
                continue
            for _ in range(2 if self.broken == "duplicate-status" else 1):
                self.wire.publish(f"robot/{status['robot']}/status", self.stamped(status))

    def on_control(self, query: Request) -> None:
        request = query.message or MALFORMED
        kind = request.get("type")
        if str(request.get("protocol", PROTOCOL)).split(".")[0] != PROTOCOL.split(".")[0]:
            query.reply_err(error("version_mismatch", f"this engine speaks {PROTOCOL}"))
            return
        with self.lock:
            events: list[dict[str, Any]] = []
            statuses: list[dict[str, Any]] = []
            if kind == "reset":
                try:
                    self.episode += 1
                    self.load(request.get("scenario") or self.scenario.name)
                except (OSError, KeyError, ValueError) as err:
                    self.episode -= 1  # a failed reset starts no episode
                    query.reply_err(error("unknown_scenario", f"cannot load scenario: {err}"))
                    return
                self.publish([], [], self.game.state())
            elif kind == "step" and self.realtime:
                query.reply_err(
                    error("unsupported", "step needs a lock-step engine; this one runs in real time")
                )
                return
            elif kind == "step":
                n = request.get("n", 1)
                if not isinstance(n, int) or not 1 <= n <= 1_000_000:
                    query.reply_err(
                        error("bad_request", f"step: n must be an integer in [1, 1000000], got {n!r}")
                    )
                    return
                ticks = {"double-step": 2 * n, "extra-tick": n + 1}.get(self.broken or "", n)
                for _ in range(ticks):
                    self.tick()
                    events += self.game.events
                    statuses += self.game.statuses
            elif kind in ("pause", "resume"):
                self.paused = kind == "pause"  # lock-step: only reported, as sim2d does
            else:
                query.reply_err(
                    error("bad_request", f"engine/control takes reset, step, pause or resume, got {kind!r}")
                )
                return
            state = self.game.state()
            reply = {
                "type": "control_reply",
                "protocol": PROTOCOL,
                "episode": self.episode,
                "tick": state["tick"],
                "time": state["time"],
                "paused": self.paused,
                "state": state,
                "events": events,
                "statuses": [
                    s for s in statuses if not (self.broken == "status" and s["state"] == "running")
                ],
            }
            if self.broken == "omit-lists":
                for key in ("state", "events", "statuses"):
                    del reply[key]
            self.reply(query, reply)

    def tick(self) -> None:
        """One tick of the world, published (the caller holds the lock)."""
        self.game.step()
        if self.newer and self.game.tick % 10 == 0 and self.game.people:
            self.game.event("sneeze", next(iter(self.game.people)), detail="atchoo")
        self.publish(self.game.events, self.game.statuses, self.game.state())

    def run_clock(self) -> None:
        """Real time: a tick every ``tick_seconds`` of wall time unless paused; first, the
        robot stopped when the brain has been silent for ``HEARTBEAT_TIMEOUT``."""
        next_at = time.monotonic()
        while not self.stopping.is_set():
            if not self.paused:
                with self.lock:
                    silent = time.monotonic() - self.heard
                    if silent > HEARTBEAT_TIMEOUT:
                        self.game.statuses = []
                        self.game.stop_robot(f"stopped: no heartbeat or command for {silent:.1f} s")
                        self.publish_statuses(self.game.statuses)
                    self.tick()
            next_at += self.tick_seconds
            delay = next_at - time.monotonic()
            if delay < -1.0:  # far behind: do not race to catch up
                next_at = time.monotonic()
            self.stopping.wait(max(delay, 0.0))

    def on_heartbeat(self, beat: dict[str, Any], key: str) -> None:
        self.heard = time.monotonic()

    # ----- robot commands -----------------------------------------------------------------

    def on_command(self, command: dict[str, Any], key: str) -> None:
        if command.get("type") != "robot_command" or not isinstance(command.get("action"), dict):
            print(f"grid engine: dropped a message on {key}: not a robot_command", file=sys.stderr)
            return
        self.heard = time.monotonic()
        with self.lock:
            self.game.statuses = []
            self.game.receive(command)
            self.publish_statuses(self.game.statuses)

    def close(self) -> None:
        self.stopping.set()
        self.wire.close()


def main() -> int:
    global PROTOCOL
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="paper-robot")
    parser.add_argument("--world", default="default")
    parser.add_argument("--robot", choices=("act", "observe"))
    parser.add_argument(
        "--break", dest="broken", choices=(*BREAKS, "list"), help="a deliberate defect ('list': print them)"
    )
    parser.add_argument("--newer", action="store_true", help=f"speak as a peer of protocol {NEWER}")
    parser.add_argument(
        "--speak",
        metavar="VERSION",
        help=f"stamp every message with this version, e.g. 1.1 (default {PROTOCOL})",
    )
    parser.add_argument("--lockstep", action="store_true", help="the default: step on 'step n' requests")
    parser.add_argument(
        "--realtime", action="store_true", help="run its own clock, a tick every --tick-seconds"
    )
    parser.add_argument(
        "--tick-seconds",
        type=float,
        default=TICK_SECONDS,
        help=f"real time: seconds per tick (default {TICK_SECONDS})",
    )
    parser.add_argument("--log-level", default="WARNING", help="accepted for symmetry with sim2d")
    parser.add_argument(
        "--gateway", metavar="URL", help="speak JSON frames to `toyroom gateway` at URL instead of Zenoh"
    )
    args = parser.parse_args()
    if args.broken == "list":
        for name, what in BREAKS.items():
            print(f"{name:20} {what}")
        return 0
    if args.speak:  # an older peer: the same messages (nothing this engine sends is newer than 1.1)
        PROTOCOL = grid_world.PROTOCOL = args.speak
    if args.tick_seconds <= 0:
        parser.error(f"--tick-seconds must be above 0, got {args.tick_seconds}")
    tick = args.tick_seconds if args.realtime else None
    engine = GridEngine(args.world, args.scenario, args.robot, args.broken, args.newer, args.gateway, tick)
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    print(f"grid engine: scenario '{args.scenario}' on world '{args.world}'", flush=True)
    # wait in slices: a signal delivered to one of Zenoh's threads only runs its Python
    # handler when the main thread next wakes (a bare stop.wait() may never return)
    lost = engine.wire.lost if isinstance(engine.wire, GatewayTransport) else threading.Event()
    while not stop.wait(0.2) and not lost.is_set():
        pass
    engine.close()
    return 1 if lost.is_set() else 0  # without its gateway the engine has no peers left


if __name__ == "__main__":
    sys.exit(main())
