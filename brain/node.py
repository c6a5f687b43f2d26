"""The brain node: the inference and the robot on the wire.

It waits for the engine's handshake, builds its model from the scene it receives (never
from engine files), drives the engine's clock in lock-step one tick at a time, updates
every person's online estimate from each tick's state and events, ticks the robot's
behaviour tree and sends its commands (waiting for the engine to accept or refuse each
before the next tick, so runs are reproducible), follows their statuses, publishes
``brain/mind`` every tick, and holds the liveliness token ``@alive/brain/<name>``.
The robot acts only when the scene says it does (or ``robot=RobotMode.ACT`` overrides it).

Against an engine whose clock runs in real time (its handshake says ``clock: realtime``),
the brain free-runs instead: it subscribes to ``engine/state`` and ``engine/events``, takes
the newest state whenever it is ready (with every event up to it), and sends commands
without waiting.
"""

from __future__ import annotations

import logging
import queue
import threading
import time
from collections.abc import Callable, Sequence
from pathlib import Path

from bridge import Bridge, LockstepClient, NoReply, StepTimeout, handshake
from protocol import (
    AgentKind,
    ClockMode,
    CommandStatus,
    ControlReply,
    EngineInfo,
    Event,
    Reset,
    RobotMode,
    State,
)

from .errors import EngineLost, StateError
from .link import Closable, Link, Stopped
from .memory import MemoryKeeper
from .model.revisions import SharedRevisions
from .oracle import oracle_minds, truth_feed
from .outputs.results import mind_message
from .outputs.runlog import RunLog
from .outputs.shadows import ShadowMinds
from .realtime import EventFeed, Heartbeats
from .reconnect import ask_again, await_receipt, drain, rejoins, waited_for
from .robot.controller import RobotBrain
from .settings import ModelSettings, RobotSettings
from .tracking.tracker import MindTracker, Observer

log = logging.getLogger("toyroom.brain")

BRAIN_NAME = "toyroom-brain"


class BrainNode:
    """Runs the inference against whatever engine serves the bridge's world.

    Args:
        bridge: an open bridge on the world.
        settings: model parameters.
        observer: which person model to use.
        timeout: seconds each lock-step request may take (``None``: no limit).
        handshake_timeout: seconds to wait for an engine to answer.
        lost_timeout: seconds a lost engine may stay gone before the run fails
            (:class:`EngineLost`; ``None``: wait however long, as at an editor's breakpoint).
        shadows: other observers run on the same ticks, each writing its minds to
            ``shadow_dir`` (:mod:`brain.outputs.shadows`).
        run_log: a directory to write every state and event handled, and every ``mind``
            message published, into (:mod:`brain.outputs.runlog`); ``None``: none.
        memory: the memory of households across days (:mod:`brain.memory`): a scene that
            names its household starts from it, and the brain saves what it learns into it.

    Each :meth:`run` follows one episode with a fresh model; a node may run several in turn
    (``python -m brain --episodes``), each into its own ``shadow_dir`` and ``run_log``
    (attributes a caller may change between runs). What a run subscribes to and declares
    is withdrawn when it ends.
    """

    def __init__(
        self,
        bridge: Bridge,
        *,
        settings: ModelSettings | None = None,
        observer: Observer = Observer.BTOM,
        timeout: float | None = 10.0,
        handshake_timeout: float | None = 30.0,
        lost_timeout: float | None = None,
        robot: RobotMode | None = None,
        robot_settings: RobotSettings | None = None,
        shadows: Sequence[Observer] = (),
        shadow_dir: Path | None = None,
        run_log: Path | None = None,
        memory: MemoryKeeper | None = None,
    ) -> None:
        self.bridge = bridge
        self.stopping = threading.Event()
        """Set (by the node's SIGTERM handler) to end the episode at the next tick: :meth:`run`
        returns what the brain has so far, and :attr:`stopped` says so."""
        self.stopped = False
        self.memory = memory
        self.run_log = run_log
        self._run_log: RunLog | None = None
        self._declared: list[Closable] = []
        """What the current run subscribed to and declared (withdrawn when it ends)."""
        self.shadows = tuple(shadows)
        self.shadow_dir = shadow_dir or Path(".")
        self._open_shadows: list[ShadowMinds] = []
        self._max_ticks: int | None = None
        self._lost: threading.Event | None = None
        """Set while no engine is alive (lock-step runs: :func:`.reconnect.await_receipt` looks at it)."""
        self._skipped = 0
        """States skipped because the tracker could not follow them."""
        self._on_tick: Callable[[State, tuple[Event, ...]], None] | None = None
        self.robot_mode = robot
        self.robot_settings = robot_settings or RobotSettings()
        self._truths = truth_feed(bridge, self.robot_settings, robot, timeout)  # the oracle's, from the start
        self.settings = settings or ModelSettings()
        self.observer = observer
        self.timeout = timeout
        self.handshake_timeout = handshake_timeout
        self.lost_timeout = lost_timeout
        self._mind = bridge.publisher(bridge.keys.mind)
        bridge.token("brain", BRAIN_NAME)

    def _robot(self, info: EngineInfo, tracker: MindTracker) -> RobotBrain | None:
        robots = [a for a in info.scene.agents if a.kind is AgentKind.ROBOT]
        if not robots:
            return None
        spec = robots[0]
        acts = spec.acts if self.robot_mode is None else self.robot_mode == RobotMode.ACT
        log.info("robot '%s' %s", spec.id, "acts" if acts else "only observes")
        minds = oracle_minds(self._truths, info, tracker) if acts else None  # None: the inferred minds
        return RobotBrain(tracker, spec.id, self.robot_settings, minds) if acts else None

    def _link(self, info: EngineInfo, old: Link | None, realtime: bool, tick: int | None = None) -> Link:
        """What following the engine of ``info`` takes: the person models (kept from ``old``
        when the scene is the same, new otherwise: from the memory of the household's days
        before, when there is one, joined at engine tick ``tick``), the shadow observers
        (which stop when the scene changes: their files hold one scene), and the robot's
        command channel, once the engine listens to it."""
        same = old is not None and old.info.scene == info.scene
        revisions = SharedRevisions()  # the shadows', and an embodied robot's branches'
        if old is not None and same:
            tracker = old.tracker
        else:
            memory = None if self.memory is None else self.memory.start(info.scene, tick)
            tracker = MindTracker(info.scene, self.settings, self.observer, revisions, memory)
        shadow = old.shadow if old is not None and same else None
        if old is None and self.shadows:
            shadow = ShadowMinds(info.scene, self.shadows, self.shadow_dir, self.settings, revisions)
            self._open_shadows.append(shadow)
        elif old is not None and old.shadow is not None and not same:
            log.warning("another scene: the shadow observers stop here")
        # the same scene is the same episode carried on: the robot keeps what it saw happen
        # (who left each item where, the moves), its tasks and its command numbering
        robot = (
            old.robot if old is not None and same and old.robot is not None else self._robot(info, tracker)
        )
        link = Link(info, tracker, shadow, robot)
        if self._run_log is not None:
            self._run_log.engine(info)
        if robot is None:
            return link
        keys = self.bridge.keys
        self._declared.append(
            self.bridge.subscribe(
                keys.status(robot.robot), lambda s, _: link.inbox.put(s), expected=CommandStatus
            )
        )
        link.commands = self.bridge.publisher(keys.command(robot.robot))
        self._declared.append(link.commands)
        if not link.commands.wait_matched(self.handshake_timeout):
            raise StepTimeout(f"the engine never subscribed to '{keys.command(robot.robot)}'")
        if realtime:
            link.heartbeats = Heartbeats(self.bridge, robot.robot)
            if link.heartbeats.publisher is not None:
                self._declared.append(link.heartbeats.publisher)
        return link

    def run(
        self,
        scenario: str | None = None,
        seed: int = 0,
        *,
        max_ticks: int | None = None,
        on_tick: Callable[[State, tuple[Event, ...]], None] | None = None,
    ) -> tuple[str, MindTracker]:
        """Reset the engine, follow the episode to its end, return (scenario, tracker)."""
        self._max_ticks, self._on_tick = max_ticks, on_tick
        if self.run_log is not None:
            self._run_log = RunLog(self.run_log, self.observer)
        self.stopped = False
        try:
            first = handshake(self.bridge, client=BRAIN_NAME, role="brain", timeout=self.handshake_timeout)
            if first.clock is ClockMode.REALTIME:
                return self._free_run(scenario, seed)
            return self._lockstep(first, scenario, seed)
        finally:
            self._lost = None
            for shadow in self._open_shadows:
                shadow.close()
            self._open_shadows.clear()
            if self._run_log is not None:
                self._run_log.close()
                self._run_log = None
            for declared in reversed(self._declared):
                declared.close()
            self._declared.clear()

    def _tick(self, link: Link, state: State, events: tuple[Event, ...]) -> bool:
        """The per-tick pipeline of both clocks: the estimates, the shadows, the robot's tree
        and commands (in lock-step each awaited until the engine accepts or refuses it), the
        ``brain/mind`` message. Whether the episode is over. A state the tracker cannot
        follow is skipped, and logged (the first one with its reason)."""
        if self._run_log is not None:
            self._run_log.inputs(state, events)
        try:
            link.tracker.observe(state, events)
        except StateError as err:
            self._skipped += 1
            if self._skipped == 1:
                log.error("%s; skipping such states (this is logged once)", err)
            return state.done or (self._max_ticks is not None and state.tick >= self._max_ticks)
        if link.shadow is not None:
            link.shadow.observe(state, events)
        robot = link.robot
        if robot is not None and link.commands is not None:
            if link.heartbeats is not None:  # real time: tell the engine the brain is there
                link.heartbeats.beat()
                drain(robot, link.inbox)
            robot.observe(events)
            for command in robot.tick(link.tracker.believed_state(state)):
                link.commands.put(command)
                if link.heartbeats is None:
                    await_receipt(robot, link.inbox, command.id, self.timeout, self._lost)
        activity = robot.activity() if robot is not None else None
        mind = mind_message(link.tracker, state, activity, link.minds)
        self._mind.put(mind)
        if self._run_log is not None:
            self._run_log.mind(mind)
        over = state.done or (self._max_ticks is not None and state.tick >= self._max_ticks)
        if not over and self.stopping.is_set():
            self.stopped = over = True
        if self.memory is not None:
            self.memory.after_tick(mind, link.tracker.robot_items(), over)
        if self._on_tick is not None:
            self._on_tick(state, events)
        return over

    def _lockstep(self, first: EngineInfo, scenario: str | None, seed: int) -> tuple[str, MindTracker]:
        """Drive the engine's clock one tick at a time."""
        clock = LockstepClient(self.bridge, timeout=self.timeout)
        state = clock.reset(scenario=scenario or first.scenario or None, seed=seed)
        info = handshake(self.bridge, client=BRAIN_NAME, role="brain", timeout=self.handshake_timeout)
        log.info("engine '%s', scenario '%s', scene '%s'", info.engine, info.scenario, info.scene.name)
        link = self._link(info, None, realtime=False, tick=state.tick)
        lost = self._lost = self._watch_engine()
        events = clock.last_reply.events if clock.last_reply is not None else ()
        while not self._tick(link, state, events):
            try:
                link, state = self._advance(clock, link, lost, state, scenario, seed)
            except Stopped:
                self.stopped = True
                break
            reply = clock.last_reply
            events = reply.events if reply is not None else ()
            if link.robot is not None and reply is not None:
                for status in reply.statuses:
                    link.robot.record(status)
                drain(link.robot, link.inbox)
        clock.close()
        return link.info.scenario, link.tracker

    def _advance(
        self,
        clock: LockstepClient,
        link: Link,
        lost: threading.Event,
        state: State,
        scenario: str | None,
        seed: int,
    ) -> tuple[Link, State]:
        """The link and the state after one more step of ``state``'s episode. An engine lost
        meanwhile (its liveliness token gone: killed, or stalled past its link's lease) is
        waited for, however long; back where the brain left it, or having carried out the step
        whose answer was lost with the link, the step is asked again under its request id and
        the episode carries on (:mod:`.reconnect`); restarted (another episode, or tick), the
        episode starts again (a reset).

        Raises:
            BrainError: the engine came back further on in the same episode: it stepped while
                the link was down, and what happened on those ticks is lost.
            StepTimeout: the engine is there but does not answer.
        """
        again = False  # ask the unanswered step again, not a new one
        while True:
            try:
                return link, ask_again(clock, link.info.engine, state) if again else clock.step(1)
            except (StepTimeout, NoReply) as err:
                if not lost.wait(2.0):  # the engine is there but does not answer: a real failure
                    raise StepTimeout(
                        f"{waited_for(clock, state)}, the engine still there (paused?): {err}"
                    ) from None
            robot = link.robot
            link = self._engine_lost(link, lost, realtime=False)
            again = rejoins(clock, link.info.engine, state)
            if not again:
                self._resend(link, robot)
                return link, clock.reset(scenario=scenario or link.info.scenario or None, seed=seed)

    def _watch_engine(self) -> threading.Event:
        """An event set while no engine of the world is alive."""
        lost = threading.Event()
        self._declared.append(
            self.bridge.presence("engine", lambda e: lost.clear() if e.alive else lost.set())
        )
        return lost

    def _free_run(self, scenario: str | None, seed: int) -> tuple[str, MindTracker]:
        """Follow a real-time engine: the newest state each time, with the events up to it."""
        states: queue.Queue[State] = queue.Queue()
        feed = EventFeed(self.bridge)
        self._declared.append(feed.subscriber)
        self._declared.append(
            self.bridge.subscribe(self.bridge.keys.state, lambda m, _: states.put(m), expected=State)
        )
        episode: int | None = None
        if scenario is not None:  # a fresh episode, as in lock-step
            reset = Reset(scenario=scenario, seed=seed)
            episode = self.bridge.query(self.bridge.keys.control, reset, ControlReply).episode
        info = handshake(self.bridge, client=BRAIN_NAME, role="brain", timeout=self.handshake_timeout)
        log.info("free-running with engine '%s', scenario '%s'", info.engine, info.scenario)
        link = self._link(info, None, realtime=True)
        lost = self._watch_engine()
        last_state = time.monotonic()
        while True:
            try:
                state = states.get(timeout=0.2)
            except queue.Empty:
                if self.stopping.is_set():  # no state comes (the engine stopped too): stop here
                    self.stopped = True
                    break
                if lost.is_set():
                    try:
                        link, episode = self._engine_lost(link, lost, realtime=True), None
                    except Stopped:
                        continue
                    feed.clear()  # the old engine's events
                    last_state = time.monotonic()
                elif self.timeout is not None and time.monotonic() - last_state > self.timeout:
                    key = self.bridge.keys.state
                    raise StepTimeout(
                        f"no state from the real-time engine on '{key}' for {self.timeout:g} s"
                    ) from None
                continue
            last_state = time.monotonic()
            while not states.empty():  # take the newest
                state = states.get_nowait()
            episode = state.episode if episode is None else episode
            if state.episode < episode:
                continue  # a state of the episode before the reset
            if state.episode != episode:
                log.info("the engine started episode %s: stopping", state.episode)
                break
            if self._tick(link, state, feed.up_to(state)):
                break
        return link.info.scenario, link.tracker

    def _engine_lost(self, link: Link, lost: threading.Event, realtime: bool) -> Link:
        """The engine went away: say so, keep the estimates, and wait for an engine of the same
        world; then shake hands again. The same scene is the same episode carried on: the robot
        keeps its tasks; in real time it sends the commands in flight again under new ids (an
        engine back mid-episode remembers the old ones, and a task dropped now may never be
        called for again; in lock-step :meth:`_advance` does, for a restarted engine alone);
        another scene gets a new model and a new robot."""
        info, robot = link.info, link.robot
        log.warning("engine '%s' lost: keeping the estimates, waiting for it to come back", info.engine)
        since = time.monotonic()
        while lost.is_set():
            if self.stopping.is_set():
                raise Stopped
            if self.lost_timeout is not None and time.monotonic() - since > self.lost_timeout:
                raise EngineLost(
                    f"engine '{info.engine}' lost for {self.lost_timeout:g} s and not back (--lost-timeout): "
                    "a link that does not come back while both live (a peer's link dropped under "
                    "load, with a third session holding the world port) fails the run, to be run again"
                )
            time.sleep(0.1)
        again = handshake(self.bridge, client=BRAIN_NAME, role="brain", timeout=self.handshake_timeout)
        if again.scene != info.scene:
            log.warning("engine '%s' is back with another scene: a new model", again.engine)
        else:
            log.warning("engine '%s' is back: carrying on", again.engine)
        back = self._link(again, link, realtime)
        if back.robot is not None and robot is not None and back.robot is not robot:
            back.robot.tree.context.book.number_after(robot.tree.context.book)  # ids never reused
        if realtime:
            self._resend(back, robot)
        return back

    @staticmethod
    def _resend(back: Link, robot: RobotBrain | None) -> None:
        """The same robot on an engine that may not have its commands in flight: send them
        again, under new ids."""
        if back.robot is not None and back.robot is robot:
            sent = back.robot.tree.context.book.resend_in_flight()
            if sent:
                log.info("sending again, under new ids: %s", ", ".join(sent))
