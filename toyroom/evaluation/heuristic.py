"""A motion-heuristic observer (Baker et al. 2017's baseline): no theory of mind, only
where each person is heading. Their goal is the item location (or the outside) whose
walking distance fell most over the last ``window`` ticks; they want the item truly there
(``out`` when heading outside; the last goal while standing still); their beliefs are the
truth (a point at each item's true location), so no false belief is ever flagged.

Built as ``mind`` messages from the states and the truth, so the evaluation scores it like
every other observer. With an embodied robot it knows no more of the world than the robot
does (:class:`RobotSight`): an item's place is where the robot last saw it or saw it put
down; the belief about an item the robot never saw is uniform over the places out of its view.
Pure functions.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping

from protocol import AgentKind, AgentMind, ItemBelief, Mind, Prob, RegionKind, Scene, State, Truth
from protocol.carry import location_distances, walking_distances
from protocol.geometry import GridCell

OUT = "out"
WINDOW = 5
"""Ticks over which a person's approach to each goal is measured."""


def goal_distances(scene: Scene) -> dict[str, dict[GridCell, int]]:
    """Walking distance from every cell to each location and (as ``out``) to the outside."""
    distances = location_distances(scene)
    outside = [(c.col, c.row) for r in scene.regions if r.kind is RegionKind.OUTSIDE for c in r.cells]
    if outside:
        distances[OUT] = walking_distances(scene.walkable(), outside)
    return distances


def heading(distances: Mapping[str, Mapping[GridCell, int]], before: GridCell, now: GridCell) -> str | None:
    """The goal whose distance fell most from ``before`` to ``now`` (ties: the nearer), or
    ``None`` when none fell."""
    best: tuple[int, int, str] | None = None
    for goal, d in distances.items():
        if before in d and now in d and d[now] < d[before]:
            key = (d[before] - d[now], -d[now], goal)
            best = key if best is None or key > best else best
    return best[2] if best is not None else None


class RobotSight:
    """Where an embodied robot knows the items are, from the states alone: it sees the item
    spots its own cell sees and tracks every person (so a carried item is where its carrier
    is, and one put down is where it was put down)."""

    def __init__(self, scene: Scene) -> None:
        self.sees = {(v.cell.col, v.cell.row): set(v.locations) for v in scene.visibility}
        self.robot = next((a.id for a in scene.agents if a.kind is AgentKind.ROBOT), None)
        self.known: dict[str, str | None] = {i.id: None for i in scene.items}
        self.carried: set[str] = set()

    def places(self, state: State, truth: Truth) -> dict[str, str | None]:
        """Each item's known place after ``state`` (``None``: never seen); ``truth`` gives a
        carried item's place (its carrier's, which the robot tracks)."""
        robot = next((a for a in state.agents if a.id == self.robot), None)
        visible = self.sees.get((robot.cell.col, robot.cell.row), set()) if robot is not None else set()
        where = {place.item: place.location for place in truth.items}
        for item in state.items:
            if item.id not in self.known:
                continue
            if item.held_by is not None:
                self.known[item.id] = where.get(item.id)
                self.carried.add(item.id)
            elif item.location in visible or item.id in self.carried:
                self.known[item.id] = item.location
                self.carried.discard(item.id)
            elif self.known[item.id] in visible:  # it is not where it was last seen
                self.known[item.id] = None
        return dict(self.known)


class MotionHeuristic:
    """Follows the states of one run and writes a ``mind`` per tick (``embodied``: knowing
    the world only as an embodied robot does)."""

    def __init__(self, scene: Scene, window: int = WINDOW, embodied: bool = False) -> None:
        self.scene = scene
        self.sight = RobotSight(scene) if embodied else None
        self.distances = goal_distances(scene)
        self.items = [i.id for i in scene.items]
        self.locations = [loc.id for loc in scene.locations]
        self.people = [a.id for a in scene.agents if a.kind is AgentKind.PERSON]
        self.trail: dict[str, deque[GridCell]] = {p: deque(maxlen=window + 1) for p in self.people}
        self.goal: dict[str, str | None] = dict.fromkeys(self.people)

    def mind(self, state: State, truth: Truth) -> Mind:
        """The heuristic's estimates at ``state``'s tick (the truth gives each item's place,
        or what an embodied robot knows of it)."""
        if self.sight is None:
            where: dict[str, str | None] = {place.item: place.location for place in truth.items}
        else:
            where = self.sight.places(state, truth)
        cells = {a.id: (a.cell.col, a.cell.row) for a in state.agents}
        agents = []
        for person in self.people:
            if person not in cells:
                continue
            trail = self.trail[person]
            trail.append(cells[person])
            goal = heading(self.distances, trail[0], trail[-1]) or self.goal[person]
            self.goal[person] = goal
            wanted = OUT if goal == OUT else next((i for i in self.items if where.get(i) == goal), None)
            agents.append(
                AgentMind(
                    agent=person,
                    beliefs=tuple(
                        ItemBelief(item, self._belief(where.get(item), state)) for item in self.items
                    ),
                    preference=tuple(
                        Prob(g, (1.0 if g == wanted else 0.0) if wanted else 1.0 / (len(self.items) + 1))
                        for g in (*self.items, OUT)
                    ),
                )
            )
        return Mind(episode=state.episode, tick=state.tick, agents=tuple(agents))

    def _belief(self, place: str | None, state: State) -> tuple[Prob, ...]:
        """A point at ``place``; unknown: uniform over the places the robot does not see."""
        if place is not None or self.sight is None:
            return tuple(Prob(loc, 1.0 if place == loc else 0.0) for loc in self.locations)
        robot = next((a for a in state.agents if a.id == self.sight.robot), None)
        visible = self.sight.sees.get((robot.cell.col, robot.cell.row), set()) if robot is not None else set()
        unseen = [loc for loc in self.locations if loc not in visible] or self.locations
        return tuple(Prob(loc, 1.0 / len(unseen) if loc in unseen else 0.0) for loc in self.locations)
