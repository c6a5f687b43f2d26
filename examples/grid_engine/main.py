"""A second, independent engine: a discrete grid (no physics, one move per tick) that plays
the same scenario files as sim2d. Written only from protocol/README.md and the JSON
Schemas: plain ``zenoh`` and ``json``, no toyroom import. It doubles as a fast engine.

    python examples/grid_engine/main.py --scenario paper-2 --world demo [--robot act|observe]

``--break MODE`` makes it deliberately wrong in one realistic way, to show that
``toyroom conform`` catches each fault (``--break list`` prints the modes).

``--newer`` makes it a peer of a newer minor version (1.99) that uses what 1.1 does not
know: a capability ``teleport``, item shape ``cup``, region kind ``closet`` (for storage
rooms), an event ``sneeze`` every 10 ticks and a field ``mood`` on every state; a 1.1 peer
must keep working with it.
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import threading
import zlib
from pathlib import Path
from typing import Any

import msgspec
import zenoh
from grid_scenario import Scenario, read_scenario
from grid_world import PROTOCOL, GridWorld

TICK_SECONDS = 0.7  # one move of one cell per tick
SCENARIOS = Path(__file__).resolve().parents[2] / "sim2d" / "scenarios"
JSON = zenoh.Encoding("application/json")
MSGPACK = "application/msgpack"
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
}
"""The deliberate defects of ``--break``, each one ``toyroom conform`` must catch."""


def load(payload: bytes, mime: str) -> Any:
    """A payload as Python values: MessagePack when the encoding says so, else JSON."""
    if mime.split(";")[0].strip() == MSGPACK:
        return msgspec.msgpack.decode(payload)
    return json.loads(payload)


def dump(message: dict[str, Any], mime: str) -> tuple[bytes, zenoh.Encoding]:
    """A message in the encoding ``mime`` names (MessagePack or JSON)."""
    if mime.split(";")[0].strip() == MSGPACK:
        return msgspec.msgpack.encode(message), zenoh.Encoding(MSGPACK)
    return json.dumps(message).encode(), JSON


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


def world_port(world: str) -> int:
    """As protocol/README.md says: 17000 + crc32(world) % 10000."""
    return 17000 + zlib.crc32(world.encode()) % 10000


def open_session(world: str) -> zenoh.Session:
    """Loopback peer, multicast off; listen on the world port when it is free."""
    endpoint = f"tcp/127.0.0.1:{world_port(world)}"
    for listen in (endpoint, "tcp/127.0.0.1:0"):
        config = zenoh.Config()
        config.insert_json5("mode", '"peer"')
        config.insert_json5("scouting/multicast/enabled", "false")
        config.insert_json5("listen/endpoints", json.dumps([listen]))
        config.insert_json5("connect/endpoints", json.dumps([endpoint]))
        config.insert_json5("transport/link/tx/lease", "800")
        try:
            return zenoh.open(config)
        except zenoh.ZError:
            continue
    raise SystemExit(f"grid engine: cannot open a Zenoh session for world '{world}'")


def error(code: str, message: str) -> bytes:
    return json.dumps({"type": "error", "protocol": PROTOCOL, "code": code, "message": message}).encode()


class GridEngine:
    def __init__(
        self, world: str, scenario_name: str, robot: str | None, broken: str | None, newer: bool = False
    ) -> None:
        self.world = world
        self.newer = newer
        self.paused = False
        self.prefix = f"toyroom/{world}"
        self.robot_override = robot
        self.broken = broken
        self.lock = threading.Lock()
        self.episode = 0
        self.load(scenario_name)
        self.session = open_session(world)
        self.state_pub = self.session.declare_publisher(f"{self.prefix}/engine/state", encoding=JSON)
        self.event_pub = self.session.declare_publisher(f"{self.prefix}/engine/events", encoding=JSON)
        self.session.declare_queryable(f"{self.prefix}/engine/info", self.on_info)
        self.session.declare_queryable(f"{self.prefix}/engine/control", self.on_control)
        self.session.declare_subscriber(f"{self.prefix}/robot/*/command", self.on_command)
        self.token = (
            None
            if broken == "no-token"
            else self.session.liveliness().declare_token(f"{self.prefix}/@alive/engine/grid")
        )

    def load(self, name: str) -> None:
        path = Path(name) if name.endswith(".toml") else SCENARIOS / f"{name}.toml"
        self.scenario: Scenario = read_scenario(path)
        acts = self.scenario.robot_acts if self.robot_override is None else self.robot_override == "act"
        self.game = GridWorld(
            self.scenario,
            episode=self.episode,
            tick_seconds=TICK_SECONDS,
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
            "capabilities": ["lockstep", "robot", *(["teleport"] if self.newer else [])],
            "clock": "lockstep",
            "tick_seconds": TICK_SECONDS,
            "episode": self.episode,
            "scene": scene,
        }

    def on_info(self, query: zenoh.Query) -> None:
        hello = self.parse(query)
        if hello is not None and str(hello.get("protocol", "")).split(".")[0] != PROTOCOL.split(".")[0]:
            query.reply_err(
                error(
                    "version_mismatch", f"this engine speaks {PROTOCOL}, the client {hello.get('protocol')}"
                ),
                encoding=JSON,
            )
            return
        with self.lock:
            self.reply(query, self.info())

    # ----- the clock --------------------------------------------------------------------

    @staticmethod
    def mime(encoding: zenoh.Encoding | None) -> str:
        return str(encoding) if encoding is not None else "application/json"

    def parse(self, query: zenoh.Query) -> dict[str, Any] | None:
        if query.payload is None:
            return None
        try:
            message = load(query.payload.to_bytes(), self.mime(query.encoding))
        except (ValueError, msgspec.DecodeError):
            return {"type": None}
        return message if isinstance(message, dict) else {"type": None}

    def reply(self, query: zenoh.Query, message: dict[str, Any]) -> None:
        """Answer in the query's encoding (as the protocol says; not with ``wrong-encoding``)."""
        mime = "application/json" if self.broken == "wrong-encoding" else self.mime(query.encoding)
        payload, encoding = dump(self.stamped(message), mime)
        query.reply(query.key_expr, payload, encoding=encoding)

    def publish(
        self, events: list[dict[str, Any]], statuses: list[dict[str, Any]], state: dict[str, Any]
    ) -> None:
        late = self.broken == "events-after-state"
        for event in [] if late else events:
            self.event_pub.put(json.dumps(self.stamped(event)).encode())
        self.publish_statuses(statuses)
        self.state_pub.put(json.dumps(self.stamped(state)).encode())
        for event in events if late else []:
            self.event_pub.put(json.dumps(self.stamped(event)).encode())

    def stamped(self, message: dict[str, Any]) -> dict[str, Any]:
        return newer(message) if self.newer else message

    def publish_statuses(self, statuses: list[dict[str, Any]]) -> None:
        for status in statuses:
            if self.broken == "status" and status["state"] == "running":
                continue
            for _ in range(2 if self.broken == "duplicate-status" else 1):
                self.session.put(
                    f"{self.prefix}/robot/{status['robot']}/status",
                    json.dumps(self.stamped(status)).encode(),
                    encoding=JSON,
                )

    def on_control(self, query: zenoh.Query) -> None:
        request = self.parse(query) or {"type": None}
        kind = request.get("type")
        if str(request.get("protocol", PROTOCOL)).split(".")[0] != PROTOCOL.split(".")[0]:
            query.reply_err(error("version_mismatch", f"this engine speaks {PROTOCOL}"), encoding=JSON)
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
                    query.reply_err(error("unknown_scenario", f"cannot load scenario: {err}"), encoding=JSON)
                    return
                self.publish([], [], self.game.state())
            elif kind == "step":
                n = request.get("n", 1)
                if not isinstance(n, int) or not 1 <= n <= 1_000_000:
                    query.reply_err(
                        error("bad_request", f"step: n must be an integer in [1, 1000000], got {n!r}"),
                        encoding=JSON,
                    )
                    return
                ticks = {"double-step": 2 * n, "extra-tick": n + 1}.get(self.broken or "", n)
                for _ in range(ticks):
                    self.game.step()
                    if self.newer and self.game.tick % 10 == 0 and self.game.people:
                        self.game.event("sneeze", next(iter(self.game.people)), detail="atchoo")
                    events += self.game.events
                    statuses += self.game.statuses
                    self.publish(self.game.events, self.game.statuses, self.game.state())
            elif kind in ("pause", "resume"):
                self.paused = kind == "pause"  # lock-step: only reported, as sim2d does
            else:
                query.reply_err(
                    error("bad_request", f"engine/control takes reset, step, pause or resume, got {kind!r}"),
                    encoding=JSON,
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

    # ----- robot commands -----------------------------------------------------------------

    def on_command(self, sample: zenoh.Sample) -> None:
        try:
            command = load(sample.payload.to_bytes(), self.mime(sample.encoding))
            if command.get("type") != "robot_command" or not isinstance(command.get("action"), dict):
                raise ValueError("not a robot_command")
        except (ValueError, AttributeError, msgspec.DecodeError) as err:
            print(f"grid engine: dropped a message on {sample.key_expr}: {err}", file=sys.stderr)
            return
        with self.lock:
            self.game.statuses = []
            self.game.receive(command)
            self.publish_statuses(self.game.statuses)

    def close(self) -> None:
        if self.token is not None:
            self.token.undeclare()
        self.session.close()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="paper-robot")
    parser.add_argument("--world", default="default")
    parser.add_argument("--robot", choices=("act", "observe"))
    parser.add_argument(
        "--break", dest="broken", choices=(*BREAKS, "list"), help="a deliberate defect ('list': print them)"
    )
    parser.add_argument("--newer", action="store_true", help=f"speak as a peer of protocol {NEWER}")
    parser.add_argument(
        "--lockstep", action="store_true", help="accepted for symmetry with sim2d (always lock-step)"
    )
    parser.add_argument("--log-level", default="WARNING", help="accepted for symmetry with sim2d")
    args = parser.parse_args()
    if args.broken == "list":
        for name, what in BREAKS.items():
            print(f"{name:20} {what}")
        return 0
    engine = GridEngine(args.world, args.scenario, args.robot, args.broken, args.newer)
    stop = threading.Event()
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: stop.set())
    print(f"grid engine: scenario '{args.scenario}' on world '{args.world}'", flush=True)
    # wait in slices: a signal delivered to one of Zenoh's threads only runs its Python
    # handler when the main thread next wakes (a bare stop.wait() may never return)
    while not stop.wait(0.2):
        pass
    engine.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
