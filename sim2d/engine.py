"""The engine core: a scenario's world advanced tick by tick, with no I/O.

:class:`Engine` owns the pymunk world, the scripted people and the robot body. The node
(:mod:`sim2d.node`) wraps it with Zenoh; tests drive it directly or over the wire.
"""

from __future__ import annotations

from dataclasses import dataclass

import msgspec
import numpy as np

from protocol import (
    AgentKind,
    Capability,
    ClockMode,
    CommandState,
    CommandStatus,
    EngineInfo,
    Event,
    ItemPlace,
    ItemSpec,
    RobotCommand,
    RobotMode,
    Scene,
    State,
    Truth,
)

from .errors import ScenarioError
from .people.autonomous import AutonomousPerson
from .people.hearsay import exchange, tell_jobs
from .people.person import Person
from .people.planned import PlannedPerson
from .people.policytable import PolicyTable
from .people.scripted import ScriptedPerson
from .robot import RobotBody
from .scenario.maps import agent_spec
from .scenario.scenario import AgentSetup, Scenario, load_scenario
from .world.world import World

ENGINE_NAME = "sim2d 0.1.0"


@dataclass(frozen=True)
class TickResult:
    """What one tick (or a reset) produced, in publication order: events, statuses, state."""

    state: State
    events: tuple[Event, ...]
    statuses: tuple[CommandStatus, ...]
    truth: Truth | None = None
    """Simulated people's true minds, when the scenario has autonomous people."""


class Engine:
    """A scenario running in pymunk.

    Args:
        scenario: a loaded scenario or its name.
        seed: seeds the episode's random generator (scripted scenarios use none).
        substeps: physics steps per tick.
        robot: ``act`` or ``observe`` to override what the scenario says.
    """

    def __init__(
        self,
        scenario: Scenario | str,
        *,
        seed: int = 0,
        substeps: int = 5,
        robot: RobotMode | None = None,
        policy: PolicyTable | None = None,
        check_policy: bool = True,
    ) -> None:
        self.substeps = substeps
        self.robot_override = robot
        self.policy = policy
        """The brain's planner table, for people with ``planner = "model"`` (:mod:`sim2d.people.planned`)."""
        self.check_policy = check_policy
        self.episode = 0
        self._load(scenario if isinstance(scenario, Scenario) else load_scenario(scenario), seed)

    def _load(self, scenario: Scenario, seed: int) -> None:
        self.scenario = scenario
        self.seed = seed
        self.rng = np.random.default_rng(seed)
        self.world = World(scenario, self.substeps)
        self.world.episode = self.episode
        self.people: dict[str, Person] = {}
        for index, setup in enumerate(scenario.people):
            if setup.autonomous:
                rng = np.random.default_rng([seed, index])
                person = self._autonomous(setup, rng)
                self._start_belief(person, np.random.default_rng([seed, index, 2]))
                self.people[setup.id] = person
            else:
                self.people[setup.id] = ScriptedPerson(setup)
        acts = (self.robot_override or scenario.robot) == RobotMode.ACT
        self.robots = {r.id: RobotBody(r.id, acts, scenario.name) for r in scenario.robots}
        self.gossip = np.random.default_rng([seed, len(scenario.people)])
        """Draws of hearsay (:mod:`sim2d.people.hearsay`), apart from every person's own."""
        self.settled = 0
        self.done = False
        self._observe_nested([p for p in self.people.values() if isinstance(p, AutonomousPerson)])

    def _observe_nested(self, autonomous: list[AutonomousPerson]) -> None:
        """Each autonomous person takes in what the others they see perceive now (nested
        beliefs, :mod:`sim2d.people.nested`)."""

        def belief_of(other: str) -> np.ndarray | None:
            person = self.people.get(other)
            return person.belief.p if isinstance(person, AutonomousPerson) else None

        for person in autonomous:
            person.nested.observe(self.world, belief_of)

    def _autonomous(self, setup: AgentSetup, rng: np.random.Generator) -> AutonomousPerson:
        """An autonomous person: by their own habits, or by the planner's table."""
        autonomy = self.scenario.autonomy
        if autonomy.planner != "model" or not self.check_policy:
            return AutonomousPerson(setup, self.world, rng, autonomy)
        if self.policy is None:
            raise ScenarioError(
                self.scenario.path,
                "autonomy",
                'planner = "model": people act by the brain\'s planner, so the engine needs its '
                "table (--policy FILE.npz, written by `python -m brain plan`)",
            )
        world = self.world
        self.policy.check(list(world.items), [loc.id for loc in world.map.locations], list(world.walkable))
        return PlannedPerson(setup, world, rng, autonomy, self.policy)

    def _start_belief(self, person: AutonomousPerson, rng: np.random.Generator) -> None:
        """What ``person`` knows before the episode (``Autonomy.knows`` and ``stale``; their
        own draws, so people who start not knowing draw exactly as before)."""
        autonomy = self.scenario.autonomy
        truth = {i.id: i.location for i in self.world.items.values() if i.location is not None}
        if autonomy.knows > 0 or autonomy.stale > 0:
            person.belief.start(truth, autonomy.knows, autonomy.stale, rng)
        setup = next(a for a in self.scenario.agents if a.id == person.id)
        for item in setup.jobs.knows:  # a task's owner knows where they left their item
            if truth.get(item) is not None:
                person.belief.told(item, truth[item])
        for item, location in setup.jobs.believes:  # sure of a place from before the episode
            person.belief.told(item, location)

    # ----- description ----------------------------------------------------------------

    @property
    def acts(self) -> bool:
        return (self.robot_override or self.scenario.robot) == RobotMode.ACT

    def scene(self) -> Scene:
        """The protocol scene of the loaded scenario."""
        agents = tuple(
            agent_spec(a.id, a.kind, a.home, a.name, self.acts if a.kind is AgentKind.ROBOT else True)
            for a in self.scenario.agents
        )
        items = tuple(
            ItemSpec(id=i.id, shape=i.shape, name=i.name, absent=i.absent) for i in self.scenario.items
        )
        scene = self.scenario.map.scene(agents, items)
        return msgspec.structs.replace(scene, household=self.scenario.household)

    def info(self, world: str, clock: ClockMode) -> EngineInfo:
        """The handshake answer for ``world``."""
        return EngineInfo(
            engine=ENGINE_NAME,
            world=world,
            scenario=self.scenario.name,
            capabilities=(Capability.LOCKSTEP, Capability.REALTIME, Capability.ROBOT)
            + ((Capability.TRUTH,) if self.scenario.autonomous else ()),
            clock=clock,
            tick_seconds=self.scenario.tick_seconds,
            episode=self.episode,
            scene=self.scene(),
        )

    # ----- clock ----------------------------------------------------------------------

    def reset(self, scenario: Scenario | str | None = None, seed: int = 0) -> TickResult:
        """Start a new episode (of ``scenario``, or the current one) and return tick 0. A
        scenario that cannot be loaded raises and leaves the episode count as it was.

        The name of the scenario playing (``engine_info``'s ``scenario``) is the scenario
        playing, whatever it was loaded from: an engine started on ``my-house.toml`` resets
        to that file when a brain that joins it asks for ``my-house``."""
        if scenario is None or scenario == self.scenario.name:
            loaded = self.scenario
        else:
            loaded = scenario if isinstance(scenario, Scenario) else load_scenario(scenario)
        self.episode += 1
        try:
            self._load(loaded, seed)
        except Exception:
            self.episode -= 1
            raise
        return TickResult(self.state(), (), (), self.truth())

    def truth(self) -> Truth | None:
        """The true minds of the autonomous people (``None`` when there are none)."""
        minds = tuple(p.mind() for p in self.people.values() if isinstance(p, AutonomousPerson))
        if not minds:
            return None
        places = tuple(
            ItemPlace(item=item_id, location=self.world.item_location(item_id), held_by=item.holder)
            for item_id, item in self.world.items.items()
        )
        return Truth(episode=self.episode, tick=self.world.tick, agents=minds, items=places)

    def step(self) -> TickResult:
        """Advance one tick."""
        world = self.world
        world.tick += 1
        world.events = []
        for person in self.people.values():
            person.update(world)
        autonomous = [p for p in self.people.values() if isinstance(p, AutonomousPerson)]
        exchange(autonomous, world, self.gossip, self.scenario.autonomy.hearsay_per_tick)
        tell_jobs(autonomous, world)
        self._observe_nested(autonomous)
        for robot in self.robots.values():
            robot.update(world, self.people)
        world.step_physics()
        for person in self.people.values():  # true minds as of the end of the tick
            if isinstance(person, AutonomousPerson):
                person.perceive(world)
        quiet = all(p.finished for p in self.people.values()) and all(r.idle for r in self.robots.values())
        self.settled = self.settled + 1 if quiet else 0
        if self.settled >= self.scenario.settle_ticks or world.tick >= self.scenario.max_ticks:
            self.done = True
        return TickResult(self.state(), tuple(world.events), self._drain(), self.truth())

    def command(self, command: RobotCommand) -> tuple[CommandStatus, ...]:
        """A robot command arrived: the statuses it produces at once (accepted or failed)."""
        robot = self.robots.get(command.robot)
        if robot is None:
            robot = next(iter(self.robots.values()), None)
            if robot is None:
                return (
                    CommandStatus(
                        command=command.id,
                        robot=command.robot,
                        state=CommandState.FAILED,
                        tick=self.world.tick,
                        reason=f"unknown robot '{command.robot}': "
                        f"scenario '{self.scenario.name}' has no robot",
                    ),
                )
        robot.receive(self.world, command)
        return self._drain()

    def stop_robots(self, reason: str) -> tuple[CommandStatus, ...]:
        """Stop every robot that has work, failing its commands with ``reason``."""
        for robot in self.robots.values():
            if not robot.idle:
                robot.stop_all(self.world, reason)
        return self._drain()

    def _drain(self) -> tuple[CommandStatus, ...]:
        out: list[CommandStatus] = []
        for robot in self.robots.values():
            out.extend(robot.pending)
            robot.pending.clear()
        return tuple(out)

    def state(self) -> State:
        """The world now."""
        world = self.world
        return State(
            episode=self.episode,
            tick=world.tick,
            time=round(world.tick * self.scenario.tick_seconds, 9),
            agents=world.agent_states(),
            items=world.item_states(),
            done=self.done,
        )
