"""pymunk: bodies pushed into walls stay outside them; the same inputs give the same stream."""

from __future__ import annotations

import math

import pytest

from protocol import encode
from sim2d.engine import Engine
from sim2d.maps import load_map
from sim2d.physics import WALL_RADIUS, Physics
from sim2d.walls import wall_segments


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
