"""The grid world: people and the robot move one cell per tick along shortest paths, act
instantly, and produce the protocol's state, events and command statuses as plain dicts
(ready for ``json.dumps``). Written from protocol/README.md; no physics."""

from __future__ import annotations

from collections import deque
from typing import Any

from grid_scenario import Cell, Scenario, scaled

PROTOCOL = "1.7"
NEIGHBOURS = ((1, 0), (-1, 0), (0, 1), (0, -1))


def bfs(walkable: set[Cell], start: Cell, goals: set[Cell]) -> list[Cell] | None:
    """Cells from ``start`` (excluded) to the nearest goal (included); None if unreachable."""
    if start in goals:
        return []
    came: dict[Cell, Cell] = {}
    seen, queue = {start}, deque([start])
    while queue:
        cell = queue.popleft()
        for dc, dr in NEIGHBOURS:
            nxt = (cell[0] + dc, cell[1] + dr)
            if nxt in walkable and nxt not in seen:
                seen.add(nxt)
                came[nxt] = cell
                if nxt in goals:
                    path = [nxt]
                    while path[-1] in came and came[path[-1]] != start:
                        path.append(came[path[-1]])
                    return path[::-1]
                queue.append(nxt)
    return None


def near(a: Cell, b: Cell) -> bool:
    """Next to: the same cell or one sharing an edge."""
    return abs(a[0] - b[0]) + abs(a[1] - b[1]) <= 1


EARSHOT_CELLS = 2


def within_earshot(a: Cell, a_region: str, b: Cell, b_region: str) -> bool:
    """The protocol's earshot: the same region, or within 2 cells Manhattan, walls ignored."""
    return a_region == b_region or abs(a[0] - b[0]) + abs(a[1] - b[1]) <= EARSHOT_CELLS


class Person:
    """A scripted person: its route, and its reactions to the robot."""

    def __init__(self, spec: dict[str, Any], scenario: Scenario, tick_seconds: float) -> None:
        self.id = spec["id"]
        self.wants = spec["wants"]
        self.answers = spec["answers"]
        self.plan = [self._scale(step, scenario.tick_seconds, tick_seconds) for step in spec["script"]]
        self.index = 0
        self.started = False
        self.left = 0

    @staticmethod
    def _scale(step: dict[str, Any], scenario_tick: float, tick: float) -> dict[str, Any]:
        step = dict(step)
        if "ticks" in step:
            step["ticks"] = scaled(step["ticks"], scenario_tick, tick)
        return step

    @property
    def finished(self) -> bool:
        if self.index >= len(self.plan):
            return True
        step = self.plan[self.index]
        return (
            self.started
            and step["do"] in ("play", "use", "wait")
            and "ticks" not in step
            and "until" not in step
        )

    def replace(self, plan: list[dict[str, Any]]) -> None:
        self.plan, self.index, self.started = plan, 0, False


class GridWorld:
    """One episode of a scenario on the grid."""

    def __init__(
        self,
        scenario: Scenario,
        *,
        episode: int,
        tick_seconds: float,
        robot_acts: bool,
        broken: str | None = None,
    ) -> None:
        self.scenario = scenario
        self.broken = broken  # a deliberate defect (main.BREAKS)
        self.map = scenario.map
        self.walkable = self.map.walkable
        self.episode = episode
        self.tick_seconds = tick_seconds
        self.robot_acts = robot_acts
        self.tick = 0
        self.events: list[dict[str, Any]] = []
        self.statuses: list[dict[str, Any]] = []
        self.labels: set[tuple[str, str]] = set()
        self.cells = {a["id"]: a["home"] for a in scenario.agents}
        self.regions = {a["id"]: self.map.region_of[a["home"]] for a in scenario.agents}
        self.paths: dict[str, list[Cell]] = {a["id"]: [] for a in scenario.agents}
        self.holding: dict[str, str | None] = {a["id"]: None for a in scenario.agents}
        self.playing: dict[str, bool] = {a["id"]: False for a in scenario.agents}
        self.moved: set[str] = set()
        self.items: dict[str, dict[str, str | None]] = {}
        for item in scenario.items:
            if item["absent"]:  # not in the scene: in no state
                continue
            if item["at"] in self.cells:
                self.items[item["id"]] = {"location": None, "holder": item["at"]}
                self.holding[item["at"]] = item["id"]
            else:
                self.items[item["id"]] = {"location": item["at"], "holder": None}
        self.people = {
            a["id"]: Person(a, scenario, tick_seconds) for a in scenario.agents if a["kind"] == "person"
        }
        robots = [a for a in scenario.agents if a["kind"] == "robot"]
        self.robot = robots[0]["id"] if robots else None
        self.queue: deque[dict[str, Any]] = deque()
        self.running: dict[str, Any] | None = None
        self.busy = 0
        self.seen_ids: set[str] = set()
        self.settle = scaled(scenario.settle_ticks, scenario.tick_seconds, tick_seconds) or 1
        self.max_ticks = scaled(scenario.max_ticks, scenario.tick_seconds, tick_seconds) or 1
        self.quiet = 0
        self.done = False

    # ----- messages ---------------------------------------------------------------------

    def event(self, kind: str, actor: str, **fields: Any) -> None:
        self.events.append(
            {
                "type": "event",
                "protocol": PROTOCOL,
                "episode": self.episode,
                "tick": self.tick,
                "time": round(self.tick * self.tick_seconds, 9),
                "kind": kind,
                "actor": actor,
                **fields,
            }
        )

    def status(
        self, command: dict[str, Any], state: str, reason: str = "", answer: bool | None = None
    ) -> None:
        self.statuses.append(
            {
                "type": "command_status",
                "protocol": PROTOCOL,
                "command": command["id"],
                "robot": command["robot"],
                "state": state,
                "tick": self.tick,
                "reason": reason,
                "answer": answer,
            }
        )

    def location(self, location_id: str) -> dict[str, Any] | None:
        return next((loc for loc in self.map.locations if loc["id"] == location_id), None)

    def state(self) -> dict[str, Any]:
        size = self.map.cell_size
        agents = []
        for agent_id, cell in self.cells.items():
            moving = agent_id in self.moved
            agents.append(
                {
                    "id": agent_id,
                    "pose": {"x": (cell[0] + 0.5) * size, "y": (cell[1] + 0.5) * size, "theta": 0.0},
                    "velocity": {"x": 0.0, "y": 0.0},
                    "cell": {"col": cell[0], "row": cell[1]},
                    "region": self.regions[agent_id],
                    "holding": self.holding[agent_id],
                    "activity": "playing" if self.playing[agent_id] else "moving" if moving else "idle",
                }
            )
        items = []
        for item_id, where in self.items.items():
            if where["holder"] is not None:
                cell, region = self.cells[where["holder"]], self.regions[where["holder"]]
            else:
                loc = self.location(where["location"] or "")
                assert loc is not None
                cell, region = loc["cell"], loc["region"]
            items.append(
                {
                    "id": item_id,
                    "pose": {"x": (cell[0] + 0.5) * size, "y": (cell[1] + 0.5) * size, "theta": 0.0},
                    "cell": {"col": cell[0], "row": cell[1]},
                    "region": region,
                    "location": where["location"],
                    "held_by": where["holder"],
                }
            )
        return {
            "type": "state",
            "protocol": PROTOCOL,
            "episode": self.episode,
            "tick": self.tick,
            "time": round(self.tick * self.tick_seconds, 9),
            "agents": agents,
            "items": items,
            "done": self.done,
        }

    # ----- shared actions ---------------------------------------------------------------

    def move(self, agent: str) -> None:
        """One cell along the agent's path."""
        if not self.paths[agent]:
            return
        cell = self.paths[agent].pop(0)
        self.cells[agent] = cell
        self.moved.add(agent)
        region = self.map.region_of.get(cell)
        if region is not None and region != self.regions[agent]:
            self.event("leave", agent, location=self.regions[agent])
            self.event("enter", agent, location=region)
            self.regions[agent] = region

    def take(self, agent: str, item: str) -> str | None:
        where = self.items.get(item)
        if where is None:
            return f"unknown id '{item}': no such item"
        if self.holding[agent] is not None:
            return f"hands full: {agent} holds '{self.holding[agent]}'"
        if where["holder"] is not None:
            return f"item held by {where['holder']}"
        loc = self.location(where["location"] or "")
        if loc is None or not near(self.cells[agent], loc["cell"]):
            return f"item not there: '{item}' is at {where['location']}"
        self.event("take", agent, item=item, location=where["location"])
        where["location"], where["holder"] = None, agent
        self.holding[agent] = item
        return None

    def drop(self, agent: str, location_id: str) -> str | None:
        item = self.holding[agent]
        loc = self.location(location_id)
        if item is None:
            return "hands empty"
        if loc is None or not near(self.cells[agent], loc["cell"]):
            return f"out of reach: location {location_id}"
        here = [i for i, where in self.items.items() if where["location"] == location_id]
        if loc["capacity"] is not None and len(here) >= loc["capacity"]:
            return f"location full: {location_id} holds at most {loc['capacity']}"
        self.items[item] = {"location": location_id, "holder": None}
        self.holding[agent], self.playing[agent] = None, False
        self.event("drop", agent, item=item, location=location_id)
        return None

    def hand(self, giver: str, receiver: str) -> None:
        item = self.holding[giver]
        assert item is not None
        self.holding[giver], self.playing[giver] = None, False
        self.holding[receiver] = item
        self.items[item]["holder"] = receiver
        self.event("give", giver, item=item, target=receiver)

    def play_spot_path(self, agent: str) -> list[Cell] | None:
        return bfs(
            self.walkable, self.cells[agent], {loc["cell"] for loc in self.map.locations if loc["play"]}
        )

    # ----- the tick -----------------------------------------------------------------------

    def step(self) -> None:
        self.tick += 1
        self.events, self.statuses = [], []
        self.moved = set()
        for person in self.people.values():
            self.update_person(person)
        self.update_robot()
        idle = self.running is None and not self.queue
        quiet = all(p.finished for p in self.people.values()) and idle
        self.quiet = self.quiet + 1 if quiet else 0
        if self.quiet >= self.settle or self.tick >= self.max_ticks:
            self.done = True

    def complete(self, person: Person, label: str | None) -> None:
        if label:
            self.labels.add((person.id, label))
            self.event("waypoint", person.id, label=label, location=self.regions[person.id])
        person.index += 1
        person.started = False

    def update_person(self, person: Person) -> None:
        """One tick of a scripted person: a move or one action."""
        agent = person.id
        while person.index < len(person.plan):
            step = person.plan[person.index]
            do = step["do"]
            if do in ("enter", "goto"):
                if not person.started:
                    person.started = True
                    if do == "enter":
                        cells = {c for c, r in self.map.region_of.items() if r == step["region"]}
                    elif "location" in step:
                        cells = {self.location(step["location"])["cell"]}  # type: ignore[index]
                    elif "cell" in step:
                        cells = {(step["cell"][0], step["cell"][1])}
                    else:
                        cells = {c for c in (p["cell"] for p in self.map.locations if p["play"])}
                    path = bfs(self.walkable, self.cells[agent], cells)
                    self.paths[agent] = path or []
                if self.paths[agent]:
                    self.move(agent)
                    if self.paths[agent]:
                        return
                    self.complete(person, step.get("label"))
                    return
                self.complete(person, step.get("label"))
                continue
            if do in ("take", "drop"):
                here = next((loc for loc in self.map.locations if loc["cell"] == self.cells[agent]), None)
                if do == "take":
                    reason = self.take(agent, step["item"])
                else:
                    reason = "no spot here" if here is None else self.drop(agent, here["id"])
                self.complete(person, step.get("label") if reason is None else None)
                return
            if not person.started:  # play or wait begins
                person.started = True
                person.left = step.get("ticks") or 0
                if do == "play":
                    if self.holding[agent] is None:
                        self.complete(person, None)
                        continue
                    self.playing[agent] = True
                    spot = next(
                        (loc["id"] for loc in self.map.locations if loc["cell"] == self.cells[agent]), None
                    )
                    self.event("play", agent, item=self.holding[agent], location=spot)
                if do == "use":
                    where = self.items.get(step["item"], {}).get("location")
                    loc = self.location(where or "")
                    if loc is None or not loc["use"] or not near(self.cells[agent], loc["cell"]):
                        self.complete(person, None)
                        continue
                    self.playing[agent] = True
                    self.event("use", agent, item=step["item"], location=where)
                if step.get("label"):
                    self.labels.add((agent, step["label"]))
                    self.event("waypoint", agent, label=step["label"], location=self.regions[agent])
                return
            if do == "play" and not self.playing[agent]:
                self.complete(person, None)
                continue
            if "ticks" in step:
                person.left -= 1
                if person.left > 0:
                    return
            elif "until" in step:
                who, label = step["until"].split(":")
                if (who, label) not in self.labels:
                    return
            else:
                return
            if do in ("play", "use"):
                self.playing[agent] = False
                self.event("stop", agent, item=self.holding[agent] if do == "play" else step["item"])
            person.index += 1
            person.started = False
            continue

    # ----- the robot ----------------------------------------------------------------------

    def receive(self, command: dict[str, Any]) -> None:
        """A command arrived: accept (queue) it or fail it at once."""
        action = command.get("action", {})
        kind = action.get("kind")
        people = set(self.people)
        if command.get("robot") != self.robot:
            return self.status(command, "failed", f"unknown robot '{command.get('robot')}'")
        if not self.robot_acts:
            return self.status(command, "failed", f"robot '{self.robot}' only observes")
        if command["id"] in self.seen_ids:
            return self.status(command, "failed", f"duplicate command id '{command['id']}'")
        self.seen_ids.add(command["id"])
        if self.broken == "refuse-commands":
            return self.status(command, "failed", "refused")
        if self.broken == "drop-queued" and (self.running or self.queue):
            return None
        checks = {
            "navigate": lambda: (
                None
                if (action["cell"]["col"], action["cell"]["row"]) in self.walkable
                else f"not walkable: ({action['cell']['col']},{action['cell']['row']})"
            ),
            "pick": lambda: (
                None if action["item"] in self.items else f"unknown id '{action['item']}': no such item"
            ),
            "place": lambda: (
                None if self.location(action["location"]) else f"unknown id '{action['location']}'"
            ),
            "give": lambda: (
                None if action["person"] in people else f"unknown id '{action['person']}': no such person"
            ),
            "say": lambda: (
                None if action["person"] in people else f"unknown id '{action['person']}': no such person"
            ),
            "request": lambda: None if action["person"] in people else f"unknown id '{action['person']}'",
            "ask": lambda: (  # from 1.6
                None if action["person"] in people else f"unknown id '{action['person']}': no such person"
            ),
        }
        if kind == "cancel":
            victim = (
                self.running
                if self.running and self.running["id"] == action["command"]
                else next((c for c in self.queue if c["id"] == action["command"]), None)
            )
            if victim is None:
                return self.status(command, "failed", f"no queued or running command '{action['command']}'")
            if self.broken == "ignore-cancel":
                self.status(command, "accepted")
                return self.status(command, "succeeded")
            if victim is self.running:
                self.running, self.paths[self.robot] = None, []
            else:
                self.queue.remove(victim)
            self.status(command, "accepted")
            self.status(victim, "cancelled", f"cancelled by '{command['id']}'")
            return self.status(command, "succeeded")
        problem = checks[kind]() if kind in checks else f"unknown command kind {kind!r}"
        if problem:
            return self.status(command, "failed", problem)
        self.status(command, "accepted")
        self.queue.append(command)
        return None

    def update_robot(self) -> None:
        if self.robot is None:
            return
        if self.running is None:
            if not self.queue:
                return
            self.running = self.queue.popleft()
            self.status(self.running, "running")
            action = self.running["action"]
            if action["kind"] == "navigate":
                path = bfs(
                    self.walkable, self.cells[self.robot], {(action["cell"]["col"], action["cell"]["row"])}
                )
                if path is None:
                    return self.finish("failed", "unreachable")
                self.paths[self.robot] = path
            # no return: the work starts this tick, as in sim2d (a lost tick lets people walk off)
        action = self.running["action"]
        me = self.robot
        kind = action["kind"]
        if kind == "navigate":
            self.move(me)
            if not self.paths[me] and self.broken != "never-arrive":
                self.finish("succeeded")
            return
        if kind == "pick":
            reason = self.take(me, action["item"])
        elif kind == "place":
            reason = self.drop(me, action["location"])
        elif kind == "give":
            person = action["person"]
            reason = (
                "hands empty"
                if self.holding[me] is None
                else f"out of reach: {person}"
                if not near(self.cells[me], self.cells[person])
                else f"{person}'s hands are full"
                if self.holding[person]
                else None
            )
            if reason is None:
                self.hand(me, person)
                self.people[person].replace([{"do": "goto"}, {"do": "play"}])
        elif kind == "say":
            reason = self.tell(me, action)
        elif kind == "ask":
            return self.ask(me, action)
        else:  # request
            person = action["person"]
            if self.holding[person] != action["item"]:
                reason = f"{person} does not hold '{action['item']}'"
            elif not near(self.cells[me], self.cells[person]):
                reason = f"out of reach: {person}"
            else:
                answer = self.people[person].answers
                self.event("request", me, item=action["item"], target=person, offer=action.get("offer"))
                self.event("reply", person, item=action["item"], target=me, answer=answer)
                if answer:
                    self.hand(person, me)
                    self.people[person].replace([{"do": "wait"}])
                return self.finish("succeeded", answer=answer)
        self.finish("failed" if reason else "succeeded", reason or "")

    def tell(self, me: str, action: dict[str, Any]) -> str | None:
        """The robot's ``say``, heard within earshot (a person told where the item they want
        rests goes and fetches it); why it failed, or None."""
        person = action["person"]
        if not within_earshot(self.cells[me], self.regions[me], self.cells[person], self.regions[person]):
            return f"out of earshot: {person}"
        if action["topic"] != "location":
            self.event(
                "say", me, item=action["item"], target=person, detail=f"occupied by {action['holder']}"
            )
            return None
        told = [(action["item"], action["location"])]
        if self.broken != "say-one":
            told += [(t["item"], t["location"]) for t in action.get("also") or ()]  # from 1.6
        who = self.people[person]
        for item, location in told:  # one event per item told, all on this tick
            self.event("say", me, item=item, location=location, target=person)
            if item == who.wants and self.holding[person] is None:
                who.replace(
                    [
                        {"do": "goto", "location": location},
                        {"do": "take", "item": item},
                        {"do": "goto"},
                        {"do": "play"},
                    ]
                )
        return None

    def ask(self, me: str, action: dict[str, Any]) -> None:
        """The robot's ``ask`` (1.6), within earshot: the person says truthfully what they
        want (an ``answer`` event; an open question when ``item`` is null)."""
        person, item = action["person"], action.get("item")
        if not within_earshot(self.cells[me], self.regions[me], self.cells[person], self.regions[person]):
            return self.finish("failed", f"out of earshot: {person}")
        wanted = self.people[person].wants
        said, wants = (item, item == wanted) if item is not None else (wanted, wanted is not None)
        self.event("ask", me, item=item, target=person)
        self.event("answer", person, item=said, target=me, answer=wants)
        return self.finish("succeeded", answer=wants)

    def stop_robot(self, reason: str) -> None:
        """Real time, the brain silent: fail the running command and every queued one."""
        for command in [c for c in (self.running, *self.queue) if c is not None]:
            self.status(command, "failed", reason)
        self.running, self.queue = None, deque()
        if self.robot is not None:
            self.paths[self.robot] = []

    def finish(self, state: str, reason: str = "", answer: bool | None = None) -> None:
        assert self.running is not None
        self.status(self.running, state, reason, answer)
        self.running = None
