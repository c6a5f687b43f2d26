"""pymunk: bodies pushed into walls stay outside them; the same inputs give the same stream."""

from __future__ import annotations

import math
from collections.abc import Callable

import pymunk
import pytest

import sim2d.world.world
from protocol import encode
from sim2d.engine import Engine
from sim2d.scenario.maps import load_map
from sim2d.world.physics import WALL_RADIUS, Physics
from sim2d.world.walls import wall_segments


@pytest.mark.parametrize("direction", [(1, 0), (-1, 0), (0, 1), (0, -1), (0.7, 0.7)])
def test_body_driven_into_a_wall_stays_outside(direction: tuple[float, float]) -> None:
    game_map = load_map("paper")
    physics = Physics(wall_segments(game_map.walkable, game_map.cell_size), dt=0.1)
    start = game_map.centre((6, 10))  # in S1, away from its doors at (7,9) and (5,7)
    radius = 0.25
    speed = 4.0
    physics.add_agent("pusher", start, radius, lambda _, __: (direction[0] * speed, direction[1] * speed))
    for _ in range(100):  # 10 s of pushing at 4 m/s
        physics.step()
    x, y = physics.position("pusher")
    # S1 spans x in [4, 7] and y in [8, 11]; its walls stop the body at radius + wall radius
    margin = radius + WALL_RADIUS - 0.02
    assert 4 + margin <= x <= 7 - margin and 8 + margin <= y <= 11 - margin, (x, y)
    assert game_map.cell_at(x, y) in game_map.walkable


def test_engine_core_is_deterministic() -> None:
    streams = []
    for _ in range(2):
        engine = Engine("paper-3", seed=3)
        stream = [encode(engine.state())]
        while not engine.done:
            result = engine.step()
            stream.append(encode(result.state))
            stream.extend(encode(e) for e in result.events)
        streams.append(stream)
    assert streams[0] == streams[1]


def test_walls_leave_door_gaps() -> None:
    game_map = load_map("paper")
    segments = wall_segments(game_map.walkable, 1.0)
    # the S1-E door at cell (5,7): no wall segment crosses the top or bottom edge of that cell
    for (x0, y0), (x1, y1) in segments:
        if y0 == y1 and y0 in (7.0, 8.0):
            assert not (min(x0, x1) < 5.5 < max(x0, x1)), f"a wall blocks the S1-E door: {(x0, y0, x1, y1)}"
    assert not math.isnan(sum(x for (x, _), _ in segments))


def test_an_agent_held_still_skips_its_controller_and_moves_as_without() -> None:
    """``hold_still`` is an optimisation only: a resting agent's trajectory is the same to the
    bit with its controller sitting out as with it answering zero every substep; once let go,
    the controller runs again."""
    game_map = load_map("paper")
    calls = {"held": 0, "free": 0}
    target = {"x": game_map.centre((6, 10))}

    def controller(name: str) -> Callable[[tuple[float, float], float], tuple[float, float]]:
        def velocity(position: tuple[float, float], sub_dt: float) -> tuple[float, float]:
            calls[name] += 1
            dx, dy = target["x"][0] - position[0], target["x"][1] - position[1]
            dist = math.hypot(dx, dy)
            if dist < 1e-3:
                return (0.0, 0.0)
            speed = min(1.5, dist / sub_dt)
            return (dx / dist * speed, dy / dist * speed)

        return velocity

    worlds = {}
    for name in calls:
        physics = Physics(wall_segments(game_map.walkable, game_map.cell_size), dt=0.1)
        physics.add_agent("a", game_map.centre((6, 10)), 0.25, controller(name))
        worlds[name] = physics
    for tick in range(40):
        if tick == 10:
            target["x"] = game_map.centre((5, 9))  # a new goal: the held agent must be let go
        for name, physics in worlds.items():
            if name == "held":
                physics.hold_still("a", tick < 10 and physics.at_rest("a"))
            physics.step()
        assert worlds["held"].position("a") == worlds["free"].position("a"), f"tick {tick}"
    assert calls["free"] == 40 * 5, calls
    assert calls["held"] == 30 * 5, f"expected the controller to sit out 10 ticks of 5 substeps, {calls}"
    assert worlds["held"].position("a") == pytest.approx(game_map.centre((5, 9)))


class PymunkPhysics(Physics):
    """:class:`Physics` through pymunk's own properties and ``Space.step`` alone (as it was
    before its hot calls went straight to chipmunk): the reference the fast path must match."""

    def add_agent(self, agent_id: str, position: tuple[float, float], radius: float, controller):  # type: ignore[no-untyped-def]
        body = super().add_agent(agent_id, position, radius, controller)

        def velocity_func(body: pymunk.Body, gravity: object, damping: float, dt: float) -> None:
            body.velocity = controller(body.position, dt)

        body.velocity_func = velocity_func
        self._controlled[agent_id] = velocity_func
        return body

    def step(self) -> None:
        for _ in range(self.substeps):
            self.space.step(self.dt / self.substeps)

    def position(self, body_id: str) -> tuple[float, float]:
        p = self.bodies[body_id].position
        return (float(p.x), float(p.y))

    def velocity(self, body_id: str) -> tuple[float, float]:
        v = self.bodies[body_id].velocity
        return (float(v.x), float(v.y))

    def at_rest(self, body_id: str) -> bool:
        v = self.bodies[body_id].velocity
        return v.x == 0.0 and v.y == 0.0


def _stream(scenario: str, ticks: int = 400) -> list[bytes]:
    engine = Engine(scenario, seed=3)
    stream = [encode(engine.state())]
    for _ in range(ticks):
        result = engine.step()
        stream.append(encode(result.state))
        stream.append(encode(result.truth) if result.truth is not None else b"")
        stream.extend(encode(e) for e in result.events)
    return stream


@pytest.mark.parametrize("scenario", ["paper-auto", "paper-3", "food-trucks"])
def test_the_chipmunk_fast_path_moves_every_body_as_pymunk_does(
    scenario: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The hot calls that skip pymunk's Python (:mod:`sim2d.world.physics`) give the very stream,
    byte for byte, that pymunk's own properties and ``Space.step`` give."""
    fast = _stream(scenario)
    monkeypatch.setattr(sim2d.world.world, "Physics", PymunkPhysics)
    plain = _stream(scenario)
    differ = next((i for i, (a, b) in enumerate(zip(fast, plain, strict=True)) if a != b), None)
    assert differ is None, (
        f"message {differ} of {scenario}: fast path {fast[differ]!r}, pymunk {plain[differ]!r}"
    )
