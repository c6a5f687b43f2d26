"""Scene checks: a sound scene passes; each kind of breakage is named with its entry; the
scene format fits maps other than the paper's without change."""

from __future__ import annotations

import msgspec
import pytest

from protocol import (
    AgentKind,
    AgentSpec,
    Cell,
    Door,
    EngineInfo,
    InvalidScene,
    ItemSpec,
    Location,
    Region,
    RegionKind,
    Scene,
    Vec2,
    Visibility,
    decode,
    scene_problems,
    validate_scene,
)
from protocol.examples import example_paths


def _example_scene() -> Scene:
    info = decode(example_paths()["engine_info"].read_bytes(), EngineInfo)
    return info.scene


def test_golden_scene_is_sound() -> None:
    assert scene_problems(_example_scene()) == []


@pytest.mark.parametrize(
    ("breakage", "expected"),
    [
        (
            lambda s: msgspec.structs.replace(s, items=s.items + (ItemSpec(id="sally"),)),
            "duplicate agent/item id 'sally'",
        ),
        (
            lambda s: msgspec.structs.replace(
                s, locations=(Location(id="basket", region="room", cell=Cell(0, 1)),) + s.locations[1:]
            ),
            "locations[0] 'basket': cell (0,1) is in a wall",
        ),
        (
            lambda s: msgspec.structs.replace(
                s, locations=(Location(id="basket", region="attic", cell=Cell(0, 3)),) + s.locations[1:]
            ),
            "locations[0] 'basket': unknown region 'attic'",
        ),
        (
            lambda s: msgspec.structs.replace(
                s, doors=(), visibility=tuple(v for v in s.visibility if v.cell != Cell(1, 1))
            ),
            "unreachable: no path from region 'O' to region(s) 'room'",
        ),
        (
            lambda s: msgspec.structs.replace(
                s, doors=(Door(id="door", cell=Cell(3, 1), joins=("room", "attic")),)
            ),
            "doors[0] 'door': joins unknown region 'attic'",
        ),
        (
            lambda s: msgspec.structs.replace(
                s,
                visibility=s.visibility[:-1] + (Visibility(cell=s.visibility[-1].cell, locations=("sofa",)),),
            ),
            "names unknown location 'sofa'",
        ),
        (
            lambda s: msgspec.structs.replace(s, visibility=s.visibility[1:]),
            "visibility: no entry for walkable cell(s)",
        ),
        (
            lambda s: msgspec.structs.replace(
                s, agents=(AgentSpec(id="sally", kind=AgentKind.PERSON, home=Cell(2, 1)),) + s.agents[1:]
            ),
            "agents[0] 'sally': home cell (2,1) is not walkable",
        ),
        (
            lambda s: msgspec.structs.replace(
                s, regions=s.regions + (Region(id="loft", kind=RegionKind.ROOM, cells=(Cell(9, 9),)),)
            ),
            "regions[2] 'loft': cell (9,9) is outside the 4x4 grid",
        ),
    ],
)
def test_breakage_is_named(breakage, expected: str) -> None:  # type: ignore[no-untyped-def]
    problems = scene_problems(breakage(_example_scene()))
    assert any(expected in p for p in problems), f"expected a problem containing {expected!r}, got {problems}"
    with pytest.raises(InvalidScene, match="problem"):
        validate_scene(breakage(_example_scene()))


def test_open_map_with_line_of_sight_fits() -> None:
    """An open 6x3 room with a screen in the middle: visibility differs cell by cell."""
    cells = tuple(Cell(c, r) for r in range(3) for c in range(6) if (c, r) != (3, 1))
    spots = (
        Location(id="west", region="hall", cell=Cell(0, 1)),
        Location(id="east", region="hall", cell=Cell(5, 1)),
    )

    def sees(cell: Cell) -> tuple[str, ...]:
        # the screen at (3,1) hides the far spot from cells on row 1
        if cell.row == 1:
            return ("west",) if cell.col < 3 else ("east",)
        return ("west", "east")

    scene = Scene(
        name="open",
        cell_size=0.5,
        origin=Vec2(-1.5, -0.75),
        columns=6,
        rows=3,
        regions=(Region(id="hall", kind=RegionKind.ROOM, cells=cells),),
        doors=(),
        locations=spots,
        visibility=tuple(Visibility(cell=c, locations=sees(c)) for c in cells),
        agents=(AgentSpec(id="p", kind=AgentKind.PERSON, home=Cell(1, 0)),),
        items=(ItemSpec(id="ball"),),
    )
    assert scene_problems(scene) == []
    assert scene.cell_centre(Cell(0, 0)) == Vec2(-1.25, -0.5)


def test_a_scene_beyond_the_limits_is_refused_naming_each_limit() -> None:
    """Issue 49, item 4: a scene past :mod:`protocol.limits` (here 1,000 items on a 1000 x 997
    grid with 101 agents) fails the handshake's check naming each limit and the value, and
    quickly: its cells are never walked (the bound is generous for a loaded machine)."""
    import time

    from tests.scenes import tiny_scene

    base = tiny_scene()
    agent = base.agents[0]
    scene = msgspec.structs.replace(
        base,
        columns=1000,
        rows=997,
        items=tuple(ItemSpec(id=f"i{k}") for k in range(1000)),
        agents=tuple(msgspec.structs.replace(agent, id=f"p{k}") for k in range(101)),
        cell_size=float("inf"),
    )
    start = time.monotonic()
    problems = scene_problems(scene)
    assert time.monotonic() - start < 5, "expected the limits checked before any cell is walked"
    assert problems == [
        "grid cells (columns x rows): 997,000, above the limit of 10,000",
        "items: 1,000, above the limit of 100",
        "agents: 101, above the limit of 100",
        "cell_size: inf m, not a finite size of at most 1000 m",
    ], f"expected each limit named with its value, got {problems}"
    with pytest.raises(InvalidScene, match="4 problem"):
        validate_scene(scene)
    assert scene_problems(base) == [], "the tiny scene is within every limit"
