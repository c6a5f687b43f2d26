"""Issue 64, item 7: a scene inside every count limit could not be carried. A 100 x 100 room
with 200 spots of 64-character ids, 100 items and 100 agents made a 134 MB ``engine_info``
(its visibility table, every spot id for every cell, nearly all of it); the gateway closed
its engine with 1009 and the user read "no engine answered". The encoded scene is now a
limit of its own, checked with the others: at a map's load (so ``toyroom run`` refuses it
before any node starts) and at the handshake."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import msgspec

from protocol import Scene, scene_problems
from protocol.geometry import Cell, Vec2
from protocol.limits import MAX_FRAME_BYTES, MAX_SCENE_BYTES
from protocol.scene import AgentKind, AgentSpec, ItemSpec, Location, Region, RegionKind, Visibility

SPOTS = tuple(f"spot{i:03d}" + "x" * 57 for i in range(200))
"""The issue's 200 spot ids of 64 characters."""
TOO_BIG = (
    "bytes as JSON (its visibility table 134,428,001: 10,000 cells, each listing the spots seen from "
    f"it), above the limit of {MAX_SCENE_BYTES:,} bytes (an engine_info must fit the WebSocket "
    f"gateway's frame of {MAX_FRAME_BYTES:,} bytes)"
)
"""The refusal of the issue's room after ``scene: N``: its visibility table is the same with
agents and items as without (as a map's load checks it)."""


def _room(spots: tuple[str, ...], people: int = 0, items: int = 0) -> Scene:
    """An open 100 x 100 room seeing every spot from every cell."""
    cells = tuple(Cell(c, r) for r in range(100) for c in range(100))
    return Scene(
        name="room",
        cell_size=1.0,
        origin=Vec2(0.0, 0.0),
        columns=100,
        rows=100,
        regions=(Region(id="room", kind=RegionKind.ROOM, cells=cells),),
        doors=(),
        locations=tuple(Location(id=s, region="room", cell=Cell(i % 100, 50)) for i, s in enumerate(spots)),
        visibility=tuple(Visibility(cell=c, locations=spots) for c in cells),
        agents=tuple(
            AgentSpec(id=f"a{k}", kind=AgentKind.PERSON, home=Cell(k % 100, 0)) for k in range(people)
        ),
        items=tuple(ItemSpec(id=f"item{k}") for k in range(items)),
    )


def test_the_issues_room_is_refused_naming_its_size_and_the_limit() -> None:
    for room in (_room(SPOTS), _room(SPOTS, people=100, items=100)):
        expected = f"scene: {len(msgspec.json.encode(room)):,} {TOO_BIG}"
        problems = scene_problems(room)
        assert problems == [expected], f"expected [{expected!r}], got {problems}"


def test_a_room_within_the_size_limit_passes() -> None:
    """22 spots of 64-character ids seen from each of the 10,000 cells fit (15.4 MB)."""
    assert scene_problems(_room(SPOTS[:22], people=100, items=100)) == []


def test_toyroom_run_refuses_it_before_anything_starts(tmp_path: Path) -> None:
    """Through the gateway, as the issue ran it: one line, exit 2, no output folder."""
    spots = "".join(
        f'[[locations]]\nid = "{s}"\nregion = "room"\ncell = [{i % 100}, 50]\n\n' for i, s in enumerate(SPOTS)
    )
    homes = "".join(f"a{k} = [{k}, 0]\n" for k in range(100))
    (tmp_path / "room.map.toml").write_text(
        'name = "room"\ncolumns = 100\nrows = 100\n\n[[regions]]\nid = "room"\nrects = [[0, 0, 100, 100]]\n\n'
        f'{spots}[[visibility]]\nfrom = ["room"]\nsees = ["room"]\n\n[homes]\n{homes}'
    )
    items = "".join(f'[[items]]\nid = "item{k}"\nat = "{SPOTS[k]}"\n\n' for k in range(100))
    agents = "".join(f'[[agents]]\nid = "a{k}"\nkind = "person"\n\n' for k in range(99))
    (tmp_path / "room.toml").write_text(
        'name = "room"\nmap = "room.map.toml"\nrobot = "act"\nobserved = "a0"\nmax_ticks = 10\n\n'
        f'{items}{agents}[[agents]]\nid = "a99"\nkind = "robot"\n'
    )
    out = tmp_path / "out"
    command = ["-m", "toyroom", "run", "--scenario", str(tmp_path / "room.toml"), "--out", str(out)]
    result = subprocess.run(
        [sys.executable, *command, "--engine", "grid", "--gateway", "--no-live"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 2 and len(lines) == 1 and TOO_BIG in lines[0], (
        f"expected exit 2 and one line saying {TOO_BIG!r}; got exit {result.returncode}: {result.stderr}"
    )
    assert not out.exists(), "expected the refusal before anything started, yet the output folder was made"
