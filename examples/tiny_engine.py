"""The smallest lock-step engine: a two-cell room, Sally, a ball that changes box while she is out.

It answers the brain's protocol on a real Zenoh session (loopback only, no multicast) with
the bridge's engine side: ``engine/info`` (:func:`bridge.serve_info`), ``engine/control``
(reset and step; a world that moves only when asked), ``engine/state`` and the liveliness
token ``@alive/engine/tiny``. It prints one line per tick. Run it, then the brain::

    python examples/tiny_engine.py --world tiny &
    python -m brain --world tiny --out out/tiny     # mind.csv: Sally's belief, tick by tick
    toyroom conform --world tiny --strict            # the conformance kit passes it

The episode ends (``done``) after :data:`TICKS` ticks; the engine serves until interrupted.
"""

from __future__ import annotations

import argparse
import sys
import threading

from bridge import Bridge, serve_info, stop_on_signals, wait_for_stop
from bridge.session import SessionSettings, add_network_args, settings_from_args
from protocol import PROTOCOL_VERSION, Message
from protocol.control import Reset, Step
from protocol.geometry import Cell, Pose, Vec2
from protocol.handshake import ClockMode, EngineInfo
from protocol.replies import ControlReply
from protocol.scene import AgentKind, AgentSpec, Door, ItemSpec, Location, Region, Scene, Visibility
from protocol.state import AgentState, ItemState, State

TICKS = 8
"""Ticks in an episode: Sally leaves at tick 2, the ball moves at tick 4, she is back at 6."""
ROOM, DOOR, HALL = (Cell(0, 0), Cell(0, 1)), Cell(1, 0), (Cell(2, 0), Cell(2, 1))
SCENE = Scene(
    name="tiny", cell_size=1.0, origin=Vec2(0.0, 0.0), columns=3, rows=2,
    regions=(Region("room", "room", ROOM), Region("hall", "room", HALL)),
    doors=(Door("door", DOOR, ("room", "hall")),),
    locations=(Location("basket", "room", ROOM[0]), Location("box", "room", ROOM[1])),
    visibility=tuple(Visibility(c, ("basket", "box") if c in ROOM else ()) for c in (*ROOM, DOOR, *HALL)),
    agents=(AgentSpec("sally", AgentKind.PERSON, ROOM[0], name="Sally"),),
    items=(ItemSpec("ball"),),
)  # fmt: skip


def world_at(episode: int, tick: int) -> State:
    """The whole world at ``tick``: where Sally stands and where the ball lies (0.1 s a tick)."""
    cell, region = (ROOM[0], "room") if tick < 2 or tick >= 6 else (HALL[0], "hall")
    spot, location = (ROOM[0], "basket") if tick < 4 else (ROOM[1], "box")
    return State(
        episode=episode, tick=tick, time=tick * 0.1, done=tick >= TICKS,
        agents=(AgentState("sally", Pose(cell.col + 0.5, cell.row + 0.5), Vec2(0.0, 0.0), cell, region),),
        items=(ItemState("ball", Pose(spot.col + 0.5, spot.row + 0.5), spot, "room", location),),
    )  # fmt: skip


def main(world: str, settings: SessionSettings) -> None:
    """Serve the tiny world on ``world`` until SIGINT or SIGTERM."""
    now = world_at(episode=0, tick=0)
    lock, stop = threading.Lock(), threading.Event()
    with Bridge(world, settings) as bridge:
        states = bridge.publisher(bridge.keys.state)

        def info() -> EngineInfo:
            return EngineInfo(
                protocol=PROTOCOL_VERSION, engine="tiny 1.0", world=world, scenario="tiny",
                capabilities=("lockstep",), clock=ClockMode.LOCKSTEP, tick_seconds=0.1,
                episode=now.episode, scene=SCENE,
            )  # fmt: skip

        def control(request: Message | None, key: str) -> ControlReply:
            nonlocal now
            with lock:
                if isinstance(request, Reset):
                    now = world_at(now.episode + 1, 0)
                    states.put(now)
                elif isinstance(request, Step):
                    for _ in range(request.n):
                        now = world_at(now.episode, now.tick + 1)
                        states.put(now)
                        sally, ball = now.agents[0], now.items[0]
                        print(f"tick {now.tick}: sally in {sally.region}, ball in {ball.location}")
                return ControlReply(episode=now.episode, tick=now.tick, time=now.time, state=now)

        serve_info(bridge, info)
        bridge.queryable(bridge.keys.control, control, expected=(Reset, Step), inline=True)
        bridge.token("engine", "tiny")
        print(f"tiny engine: serving world '{world}' (ready)")
        stop_on_signals(stop)
        wait_for_stop(stop)


if __name__ == "__main__":
    sys.stdout.reconfigure(line_buffering=True)  # type: ignore[union-attr]  # a line as it is printed
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_network_args(parser)
    args = parser.parse_args()
    main(args.world, settings_from_args(args))
