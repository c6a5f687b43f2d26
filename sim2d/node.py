"""The engine node: an :class:`~sim2d.engine.Engine` on the wire.

It answers ``engine/info`` (the handshake) and ``engine/control`` (reset, step, pause,
resume), publishes ``engine/state`` every tick (dropped rather than queued when the
network is congested: a newer state supersedes it), ``engine/events`` for every event and
``robot/<id>/status`` for every command status (both never dropped), takes commands on
``robot/<id>/command``, and holds the liveliness token ``@alive/engine/sim2d``.

In lock-step the world advances only on ``step``; in real time it runs at ``rate`` times
wall-clock speed, and ``pause`` / ``resume`` stop and restart it. In real time the robot is
stopped (its commands failed) when neither a command nor a ``heartbeat`` has come from the
brain for ``heartbeat_timeout`` seconds: a dead brain never leaves a robot driving.

People named in ``puppets`` are driven from ``person/<id>/command`` (a participant of
``toyroom play``, :mod:`sim2d.people.puppet`) instead of their script, episode after episode.
"""

from __future__ import annotations

import logging
import threading
import time

from bridge import Bridge, Congestion, Received, Refused, serve_info
from bridge.processes import wait_for_stop
from protocol import (
    ClockMode,
    CommandStatus,
    ControlReply,
    EngineInfo,
    ErrorCode,
    Event,
    Heartbeat,
    Message,
    Pause,
    PersonCommand,
    Reset,
    Resume,
    RobotCommand,
    Step,
)

from .engine import Engine, TickResult
from .errors import ScenarioError
from .people.puppet import PuppetPerson, install_puppets
from .scenario.scenario import scenario_names

log = logging.getLogger("toyroom.sim2d")


class EngineNode:
    """Serves one engine on one world. A context manager; :meth:`close` is idempotent.

    Args:
        engine: the engine core.
        bridge: an open bridge on the world.
        clock: lock-step or real time.
        rate: real-time speed factor (2.0: twice as fast as wall-clock).
    """

    def __init__(
        self,
        engine: Engine,
        bridge: Bridge,
        *,
        clock: ClockMode = ClockMode.LOCKSTEP,
        rate: float = 1.0,
        heartbeat_timeout: float = 1.0,
        puppets: tuple[str, ...] = (),
    ) -> None:
        self.engine = engine
        self.puppet_ids = puppets
        self.puppets: dict[str, PuppetPerson] = {}
        self._install_puppets()
        self.bridge = bridge
        self.clock = clock
        self.rate = rate
        self.paused = False
        self._lock = threading.RLock()
        self._stop = threading.Event()
        keys = bridge.keys
        self._state = bridge.publisher(keys.state, congestion=Congestion.DROP)
        self._events = bridge.publisher(keys.events)
        self._truth = bridge.publisher(keys.truth)  # evaluation data: never dropped
        self._status = {rid: bridge.publisher(keys.status(rid)) for rid in engine.robots}
        serve_info(bridge, self.info)
        # lock-step: answer in Zenoh's thread (a tick is short; the hand-off would double it)
        bridge.queryable(
            keys.control,
            self._control,
            expected=(Reset, Step, Pause, Resume),
            inline=clock is ClockMode.LOCKSTEP,
        )
        bridge.subscribe(keys.command(), self._on_command, expected=RobotCommand)
        bridge.subscribe(keys.heartbeat(), self._on_heartbeat, expected=Heartbeat)
        if puppets:
            bridge.subscribe(keys.person_command(), self._on_person, expected=PersonCommand)
        self.heartbeat_timeout = heartbeat_timeout
        self._last_heard = time.monotonic()
        bridge.token("engine", "sim2d")
        self._ticker: threading.Thread | None = None
        if clock is ClockMode.REALTIME:
            self._ticker = threading.Thread(target=self._run_realtime, name="sim2d clock", daemon=True)
            self._ticker.start()

    def _install_puppets(self) -> None:
        """Puppets in place of the people named (again after every reset)."""
        engine = self.engine
        self.puppets = install_puppets(engine.people, engine.scenario, engine.world, self.puppet_ids)

    def _on_person(self, command: PersonCommand, received: Received) -> None:
        puppet = self.puppets.get(command.person)
        if puppet is None or received.key != self.bridge.keys.person_command(command.person):
            log.warning("person command for '%s' on '%s': no such puppet here", command.person, received.key)
            return
        puppet.receive(command)

    def info(self) -> EngineInfo:
        with self._lock:
            return self.engine.info(self.bridge.world, self.clock)

    def _publish(self, result: TickResult) -> None:
        for event in result.events:
            self._events.put(event)
        self._publish_statuses(result)
        if result.truth is not None:
            self._truth.put(result.truth)
        self._state.put(result.state)

    def _publish_statuses(self, result: TickResult) -> None:
        for status in result.statuses:
            publisher = self._status.get(status.robot)
            if publisher is None:
                publisher = self._status[status.robot] = self.bridge.publisher(
                    self.bridge.keys.status(status.robot)
                )
            publisher.put(status)

    def _reply(
        self,
        result: TickResult | None = None,
        events: tuple[Event, ...] = (),
        statuses: tuple[CommandStatus, ...] = (),
    ) -> ControlReply:
        state = result.state if result is not None else self.engine.state()
        return ControlReply(
            episode=state.episode,
            tick=state.tick,
            time=state.time,
            paused=self.paused,
            state=state,
            events=events,
            statuses=statuses,
        )

    def _control(self, request: Message | None, key: str) -> ControlReply:
        with self._lock:
            if isinstance(request, Reset):
                try:
                    result = self.engine.reset(request.scenario, request.seed)
                except ScenarioError as err:
                    known = ", ".join(scenario_names())
                    named = request.scenario is not None and not request.scenario.endswith(".toml")
                    if named and request.scenario not in scenario_names():  # a name, not a file
                        raise Refused(
                            ErrorCode.UNKNOWN_SCENARIO,
                            f"no scenario named '{request.scenario}'; known: {known}",
                        ) from None
                    raise Refused(ErrorCode.BAD_REQUEST, str(err)) from None
                self._install_puppets()
                self._publish(result)
                return self._reply(result)
            if isinstance(request, Step):
                if self.clock is not ClockMode.LOCKSTEP:
                    raise Refused(
                        ErrorCode.UNSUPPORTED, "step needs a lock-step engine; this one runs in real time"
                    )
                stepped: TickResult | None = None
                events: list[Event] = []
                statuses: list[CommandStatus] = []
                for _ in range(request.n):
                    stepped = self.engine.step()
                    events.extend(stepped.events)
                    statuses.extend(stepped.statuses)
                    self._publish(stepped)
                return self._reply(stepped, tuple(events), tuple(statuses))
            if isinstance(request, Pause):
                self.paused = True
            elif isinstance(request, Resume):
                self.paused = False
            return self._reply()

    def _on_heartbeat(self, beat: Heartbeat, _: Received) -> None:
        self._last_heard = time.monotonic()

    def _check_heartbeat(self) -> None:
        """Real time: stop the robot when its brain has been silent for the heartbeat timeout."""
        silent = time.monotonic() - self._last_heard
        if silent > self.heartbeat_timeout:
            statuses = self.engine.stop_robots(
                f"stopped: no heartbeat or command from the brain for {silent:.1f} s"
            )
            if statuses:
                log.warning("brain silent for %.1f s: robot stopped", silent)
                self._publish_statuses(TickResult(self.engine.state(), (), statuses))

    def _on_command(self, command: RobotCommand, received: Received) -> None:
        robot_in_key = received.key.split("/")[-2]
        self._last_heard = time.monotonic()
        with self._lock:
            if robot_in_key != command.robot:
                log.warning(
                    "command '%s' names robot '%s' but came on '%s'", command.id, command.robot, received.key
                )
            statuses = self.engine.command(command)
            self._publish_statuses(TickResult(self.engine.state(), (), statuses))

    def _run_realtime(self) -> None:
        period = self.engine.scenario.tick_seconds / self.rate
        next_at = time.monotonic()
        while not self._stop.is_set():
            if not self.paused:
                with self._lock:
                    self._check_heartbeat()
                    result = self.engine.step()
                    self._publish(result)
            next_at += period
            delay = next_at - time.monotonic()
            if delay < -1.0:  # far behind (a debugger, a stall): do not race to catch up
                next_at = time.monotonic()
            self._stop.wait(max(delay, 0.0))

    def stop(self) -> None:
        """Ask :meth:`wait` to return (safe from a signal handler)."""
        self._stop.set()

    def wait(self) -> None:
        """Block until :meth:`stop` or :meth:`close` is called (from another thread or a
        signal handler: the wait wakes regularly so that handlers run, see
        :mod:`bridge.processes`)."""
        wait_for_stop(self._stop)

    def close(self) -> None:
        """Stop the clock and leave the network; safe to call twice."""
        self._stop.set()
        if self._ticker is not None and self._ticker is not threading.current_thread():
            self._ticker.join(timeout=5.0)
        self.bridge.close()

    def __enter__(self) -> EngineNode:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
