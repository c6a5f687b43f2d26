"""A tiny scene for exact checks: a 3-cell playground with two spots, a door, the outside.

(0,0) A [play]   (1,0)   (2,0) B    door (3,0)   O (4,0)
"""

from __future__ import annotations

from protocol import (
    AgentKind,
    AgentSpec,
    AgentState,
    Cell,
    Door,
    ItemShape,
    ItemSpec,
    ItemState,
    Location,
    Pose,
    Region,
    RegionKind,
    Scene,
    State,
    Vec2,
    Visibility,
)

ROOM = tuple(Cell(c, 0) for c in range(3))


def tiny_scene() -> Scene:
    return Scene(
        name="tiny",
        cell_size=1.0,
        origin=Vec2(0.0, 0.0),
        columns=5,
        rows=1,
        regions=(
            Region(id="R", kind=RegionKind.PLAYGROUND, cells=ROOM),
            Region(id="O", kind=RegionKind.OUTSIDE, cells=(Cell(4, 0),)),
        ),
        doors=(Door(id="d", cell=Cell(3, 0), joins=("R", "O")),),
        locations=(
            Location(id="A", region="R", cell=Cell(0, 0), play=True),
            Location(id="B", region="R", cell=Cell(2, 0)),
        ),
        visibility=tuple(Visibility(cell=c, locations=("A", "B")) for c in (*ROOM, Cell(3, 0)))
        + (Visibility(cell=Cell(4, 0), locations=()),),
        agents=(AgentSpec(id="p", kind=AgentKind.PERSON, home=Cell(4, 0)),),
        items=(ItemSpec(id="ball", shape=ItemShape.BALL),),
    )


def tiny_state(tick: int, cell: tuple[int, int], ball_at: str | None, holding: bool = False) -> State:
    """The person on ``cell``; the ball resting at ``ball_at`` or carried by the person."""
    region = "O" if cell[0] == 4 else "R"
    person = AgentState(
        id="p",
        pose=Pose(cell[0] + 0.5, 0.5),
        velocity=Vec2(0.0, 0.0),
        cell=Cell(*cell),
        region=region,
        holding="ball" if holding else None,
    )
    ball_cell = Cell(*cell) if holding else Cell(0 if ball_at == "A" else 2, 0)
    ball = ItemState(
        id="ball",
        pose=Pose(ball_cell.col + 0.5, 0.5),
        cell=ball_cell,
        region="R",
        location=None if holding else ball_at,
        held_by="p" if holding else None,
    )
    return State(episode=1, tick=tick, time=tick * 0.7, agents=(person,), items=(ball,))


def lookout_scene() -> Scene:
    """A corridor with a spot at each end and a lookout above its middle:

        (3,1) lookout: sees A and B
        (0,0) A [play]  (1,0) (2,0) (3,0) (4,0) (5,0)  (6,0) B [play]

    Only A's own cell sees A, and only B's sees B. Someone in the middle who does not know
    whether the ball is at A or B does best to step up and look (5 steps against 6 on
    average for walking to one end and back)."""
    corridor = tuple(Cell(c, 0) for c in range(7))
    lookout = Cell(3, 1)
    visibility = tuple(
        Visibility(cell=c, locations=("A",) if c.col == 0 else ("B",) if c.col == 6 else ()) for c in corridor
    ) + (Visibility(cell=lookout, locations=("A", "B")),)
    return Scene(
        name="lookout",
        cell_size=1.0,
        origin=Vec2(0.0, 0.0),
        columns=7,
        rows=2,
        regions=(Region(id="R", kind=RegionKind.PLAYGROUND, cells=(*corridor, lookout)),),
        doors=(),
        locations=(
            Location(id="A", region="R", cell=Cell(0, 0), play=True),
            Location(id="B", region="R", cell=Cell(6, 0), play=True),
        ),
        visibility=visibility,
        agents=(AgentSpec(id="p", kind=AgentKind.PERSON, home=Cell(3, 0)),),
        items=(ItemSpec(id="ball", shape=ItemShape.BALL),),
    )


CORRIDOR = tuple(Cell(c, 0) for c in range(2, 9))
"""O (0,0) | door (1,0) | A (2,0) . . . . . B (8,0): the robot stands outside and sees nothing."""


def corridor_scene() -> Scene:
    return Scene(
        name="corridor",
        cell_size=1.0,
        origin=Vec2(0.0, 0.0),
        columns=9,
        rows=1,
        regions=(
            Region(id="R", kind=RegionKind.PLAYGROUND, cells=CORRIDOR),
            Region(id="O", kind=RegionKind.OUTSIDE, cells=(Cell(0, 0),)),
        ),
        doors=(Door(id="d", cell=Cell(1, 0), joins=("R", "O")),),
        locations=(
            Location(id="A", region="R", cell=Cell(2, 0), play=True),
            Location(id="B", region="R", cell=Cell(8, 0), play=True),
        ),
        visibility=tuple(Visibility(cell=c, locations=("A", "B")) for c in (*CORRIDOR, Cell(1, 0)))
        + (Visibility(cell=Cell(0, 0), locations=()),),
        agents=(
            AgentSpec(id="p", kind=AgentKind.PERSON, home=Cell(5, 0)),
            AgentSpec(id="r", kind=AgentKind.ROBOT, home=Cell(0, 0)),
        ),
        items=(ItemSpec(id="ball", shape=ItemShape.BALL),),
    )


def corridor_state(
    tick: int, person: int, robot: int = 0, ball_at: str = "B", holding: bool = False
) -> State:
    def agent(agent_id: str, col: int, held: str | None = None) -> AgentState:
        return AgentState(
            id=agent_id,
            pose=Pose(col + 0.5, 0.5),
            velocity=Vec2(0.0, 0.0),
            cell=Cell(col, 0),
            region="O" if col == 0 else "R",
            holding=held,
        )

    ball_col = person if holding else (2 if ball_at == "A" else 8)
    ball = ItemState(
        id="ball",
        pose=Pose(ball_col + 0.5, 0.5),
        cell=Cell(ball_col, 0),
        region="R",
        location=None if holding else ball_at,
        held_by="p" if holding else None,
    )
    return State(
        episode=1,
        tick=tick,
        time=tick * 0.7,
        agents=(agent("p", person, "ball" if holding else None), agent("r", robot)),
        items=(ball,),
    )


SCHOOL_WIDTH = 4
"""Columns of a classroom of :func:`school_scene` (each has 3 rows)."""


def school_scene(
    spots: tuple[int, ...] = (4, 4, 4, 4),
    items: tuple[str, ...] = ("backpack", "book", "ball"),
    people: tuple[str, ...] = ("ann", "bob", "cat"),
) -> Scene:
    """A school: classrooms ``C0``, ``C1``, ... side by side (``spots[i]`` locations in
    ``Ci``, named ``Ci.0``, ``Ci.1``, ...; each room sees its own), under a hallway ``H`` with
    no locations (it sees none), which leads out at its west end::

        (0,6) O
        (0,5) door
        (0,4) H  H  H  H  H  H  H  H  H  H ...   row 4: the hallway
        (1,3) door of C0   (6,3) door of C1 ...   row 3: walls and doors
        rows 0-2: C0 at columns 0-3, C1 at 5-8, C2 at 10-13, ...

    The people start in C0, C1, C2, ... (column 1, row 1 of each); the robot at the hallway's
    east end."""
    regions, doors, locations, visibility = [], [], [], []
    for r, count in enumerate(spots):
        x0, rid = r * (SCHOOL_WIDTH + 1), f"C{r}"
        cells = tuple(Cell(x0 + c, y) for y in range(3) for c in range(SCHOOL_WIDTH))
        regions.append(Region(id=rid, kind=RegionKind.ROOM, cells=cells))
        ids = tuple(f"{rid}.{s}" for s in range(count))
        locations += [Location(id=i, region=rid, cell=c, play=True) for i, c in zip(ids, cells, strict=False)]
        door = Cell(x0 + 1, 3)
        doors.append(Door(id=f"d{r}", cell=door, joins=(rid, "H")))
        visibility += [Visibility(cell=c, locations=ids) for c in (*cells, door)]
    width = len(spots) * (SCHOOL_WIDTH + 1)
    hall = tuple(Cell(c, 4) for c in range(width))
    regions += [
        Region(id="H", kind=RegionKind.ROOM, cells=hall),
        Region(id="O", kind=RegionKind.OUTSIDE, cells=(Cell(0, 6),)),
    ]
    doors.append(Door(id="out", cell=Cell(0, 5), joins=("H", "O")))
    visibility += [Visibility(cell=c, locations=()) for c in (*hall, Cell(0, 5), Cell(0, 6))]
    agents = tuple(
        AgentSpec(id=p, kind=AgentKind.PERSON, home=Cell(i * (SCHOOL_WIDTH + 1) + 1, 1))
        for i, p in enumerate(people)
    ) + (AgentSpec(id="robot", kind=AgentKind.ROBOT, home=Cell(width - 1, 4)),)
    return Scene(
        name="school-" + "-".join(map(str, spots)),
        cell_size=1.0,
        origin=Vec2(0.0, 0.0),
        columns=width,
        rows=7,
        regions=tuple(regions),
        doors=tuple(doors),
        locations=tuple(locations),
        visibility=tuple(visibility),
        agents=agents,
        items=tuple(ItemSpec(id=i, shape=ItemShape.BLOCK) for i in items),
    )


def school_state(scene: Scene, tick: int, cells: dict[str, tuple[int, int]], items: dict[str, str]) -> State:
    """Every agent of ``scene`` on ``cells`` (col, row; an agent not named is at home); each
    item resting at the location ``items`` names, or carried by the agent it names."""
    region_of = {(c.col, c.row): r.id for r in scene.regions for c in r.cells}
    at = {a.id: cells.get(a.id, (a.home.col, a.home.row)) for a in scene.agents}
    spots = {loc.id: loc for loc in scene.locations}
    holding = {where: item for item, where in items.items() if where in at}
    agents = tuple(
        AgentState(
            id=a,
            pose=Pose(c + 0.5, r + 0.5),
            velocity=Vec2(0.0, 0.0),
            cell=Cell(c, r),
            region=region_of.get((c, r), ""),
            holding=holding.get(a),
        )
        for a, (c, r) in at.items()
    )
    states = []
    for item, where in items.items():
        cell = Cell(*at[where]) if where in at else spots[where].cell
        states.append(
            ItemState(
                id=item,
                pose=Pose(cell.col + 0.5, cell.row + 0.5),
                cell=cell,
                region=region_of.get((cell.col, cell.row), ""),
                location=None if where in at else where,
                held_by=where if where in at else None,
            )
        )
    return State(episode=1, tick=tick, time=tick * 0.7, agents=agents, items=tuple(states))


def household_scene() -> Scene:
    """Two rooms and the outside, for days in sequence (:mod:`brain.memory`):

        R1: A [play] (0,0)  (1,0)  (2,0) | door (3,0) | R2: (4,0)  (5,0)  B [play] (6,0)
                                                              door (5,1)
                                                              O (5,2)

    R1's cells see A, R2's see B, the door between them both; the outside sees nothing.
    The person ``p`` and the robot ``r``; a ball and a skate."""
    r1 = tuple(Cell(c, 0) for c in range(3))
    r2 = tuple(Cell(c, 0) for c in range(4, 7))
    visibility = (
        *(Visibility(cell=c, locations=("A",)) for c in r1),
        Visibility(cell=Cell(3, 0), locations=("A", "B")),
        *(Visibility(cell=c, locations=("B",)) for c in r2),
        Visibility(cell=Cell(5, 1), locations=("B",)),
        Visibility(cell=Cell(5, 2), locations=()),
    )
    return Scene(
        name="household",
        cell_size=1.0,
        origin=Vec2(0.0, 0.0),
        columns=7,
        rows=3,
        regions=(
            Region(id="R1", kind=RegionKind.PLAYGROUND, cells=r1),
            Region(id="R2", kind=RegionKind.PLAYGROUND, cells=r2),
            Region(id="O", kind=RegionKind.OUTSIDE, cells=(Cell(5, 2),)),
        ),
        doors=(
            Door(id="d1", cell=Cell(3, 0), joins=("R1", "R2")),
            Door(id="d2", cell=Cell(5, 1), joins=("R2", "O")),
        ),
        locations=(
            Location(id="A", region="R1", cell=Cell(0, 0), play=True),
            Location(id="B", region="R2", cell=Cell(6, 0), play=True),
        ),
        visibility=visibility,
        agents=(
            AgentSpec(id="p", kind=AgentKind.PERSON, home=Cell(1, 0)),
            AgentSpec(id="r", kind=AgentKind.ROBOT, home=Cell(5, 2)),
        ),
        items=(ItemSpec(id="ball", shape=ItemShape.BALL), ItemSpec(id="skate", shape=ItemShape.BOARD)),
    )


HOUSEHOLD_SPOTS = {"A": Cell(0, 0), "B": Cell(6, 0)}


def household_state(
    tick: int,
    person: tuple[int, int],
    robot: tuple[int, int] = (5, 2),
    items: tuple[str, str] = ("A", "B"),
    holding: str | None = None,
) -> State:
    """``p`` on ``person``, the robot on ``robot``; the ball and the skate resting at
    ``items`` (location ids), or the one named by ``holding`` carried by ``p``."""

    def region(cell: tuple[int, int]) -> str:  # a door cell: the region left last (approximately)
        return "O" if cell == (5, 2) else "R1" if cell[0] <= 3 else "R2"

    def agent(agent_id: str, cell: tuple[int, int], held: str | None = None) -> AgentState:
        return AgentState(
            id=agent_id,
            pose=Pose(cell[0] + 0.5, cell[1] + 0.5),
            velocity=Vec2(0.0, 0.0),
            cell=Cell(*cell),
            region=region(cell),
            holding=held,
        )

    states = []
    for item, at in zip(("ball", "skate"), items, strict=True):
        carried = holding == item
        spot = Cell(*person) if carried else HOUSEHOLD_SPOTS[at]
        states.append(
            ItemState(
                id=item,
                pose=Pose(spot.col + 0.5, spot.row + 0.5),
                cell=spot,
                region=region((spot.col, spot.row)),
                location=None if carried else at,
                held_by="p" if carried else None,
            )
        )
    return State(
        episode=1,
        tick=tick,
        time=tick * 0.7,
        agents=(agent("p", person, holding), agent("r", robot)),
        items=tuple(states),
    )
