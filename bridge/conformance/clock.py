"""The conformance checks of the clock and the wire: a real-time clock that runs, pauses and
resumes; heartbeat loss stopping the robot; MessagePack on every key a client writes; the
``control_reply`` carrying exactly what the step published; each tick's events before its
state."""

from __future__ import annotations

import time

from protocol import (
    Capability,
    Cell,
    ClockMode,
    CommandState,
    CommandStatus,
    ControlReply,
    Encoding,
    EngineInfo,
    Heartbeat,
    Hello,
    Navigate,
    Pause,
    Resume,
    Step,
    decode,
    encode,
)

from ..pubsub import Publisher, zenoh_encoding
from .probe import HEARTBEAT_SECONDS, CheckFailed, CheckSkipped, NotApplicable, Probe

BEATING_SECONDS = 1.5
"""How long the kit beats before falling silent, walking the robot to and fro across the map;
as the beats stop it queues one more walk back across the map, so that the robot still has
two walks' way to go when the silence starts (a robot that covers both within
:data:`SILENT_LIMIT` is too fast to test on that map: the check is skipped, saying so)."""
SILENT_SECONDS = 5.0
"""How long after the last heartbeat the kit waits for the engine to stop the robot."""
SILENT_LIMIT = 1.0
"""The protocol's heartbeat loss: an engine stops the robot once neither a heartbeat nor a
command has come for this long (it may take a tick or two more)."""


def shown_status(status: CommandStatus) -> str:
    """``failed (reason)``, or the state alone."""
    return f"{status.state.value} ({status.reason})" if status.reason else status.state.value


class ClockChecks(Probe):
    """The clock and wire checks (``check_<name>``)."""

    def _realtime(self) -> bool:
        assert self.info is not None
        return self.info.clock is ClockMode.REALTIME

    def check_realtime(self) -> str:
        if not self._realtime():
            raise NotApplicable("the clock runs in lock-step")
        first = len(self.stream.states)
        if not self.stream.wait(lambda: len(self.stream.states) > first + 2, self.timeout):
            raise CheckFailed("a real-time clock should publish states by itself; none came")
        return "states arrive without stepping"

    def check_pause_and_resume(self) -> str:
        if not self._realtime():
            raise NotApplicable("the clock runs in lock-step")
        assert self.info is not None
        paused = self.control(Pause())
        if not paused.paused:
            raise CheckFailed(f"pause: expected a reply with paused true, got {paused}")
        settle = len(self.stream.states)
        self.stream.wait(lambda: False, 3 * self.info.tick_seconds)  # a state already sent may land
        held = len(self.stream.states)
        self.stream.wait(lambda: False, 5 * self.info.tick_seconds)
        if len(self.stream.states) > held:
            raise CheckFailed(
                f"paused: expected no states for 5 ticks' time, got {len(self.stream.states) - held} "
                f"(and {held - settle} while settling)"
            )
        resumed = self.control(Resume())
        if resumed.paused:
            raise CheckFailed(f"resume: expected a reply with paused false, got {resumed}")
        after = len(self.stream.states)
        if not self.stream.wait(lambda: len(self.stream.states) > after + 2, self.timeout):
            raise CheckFailed("resumed: expected states to come again, none came")
        return "no states while paused, states again after resume"

    def check_heartbeat(self) -> str:
        if not self._realtime():
            raise NotApplicable("the clock runs in lock-step (heartbeats matter in real time)")
        assert self.info is not None
        if Capability.ROBOT not in self.info.capabilities:
            raise NotApplicable("the engine does not declare 'robot'")
        if self.robot is None:
            raise CheckSkipped("no robot in the scene")
        robot = next(a for a in self.info.scene.agents if a.id == self.robot)
        if not robot.acts:
            raise CheckSkipped(f"robot '{robot.id}' only observes in this scene (acts: false)")
        self.silent = True  # the kit's own beats (which keep other checks' robot going) held
        try:
            return self._beat_then_fall_silent(robot.home.col, robot.home.row)
        finally:
            self.silent = False

    def _beat_then_fall_silent(self, col: int, row: int) -> str:
        """Walk the robot to and fro while beating for :data:`BEATING_SECONDS`; then, as the
        beats stop, queue one more walk back across the map (a command counts as hearing from
        the brain, so the silence starts there) and expect the engine to fail the robot's
        commands within :data:`SILENT_SECONDS`."""
        assert self.robot is not None
        command, target = self._walk_far(col, row)
        # in MessagePack: an engine must read it on every key (and a JSON-only one stops the robot)
        beats: Publisher[Heartbeat] = Publisher(
            self.bridge.session, self.keys.heartbeat(self.robot), encoding=Encoding.MSGPACK
        )
        for seq in range(int(BEATING_SECONDS / HEARTBEAT_SECONDS)):
            beats.put(Heartbeat(robot=self.robot, seq=seq))
            time.sleep(HEARTBEAT_SECONDS)
            done = self.statuses_of(command)
            if done and done[-1].state is CommandState.SUCCEEDED:  # a fast robot: walk it back
                command, target = self._walk_far(*target)
            elif done and done[-1].state.final:
                if done[-1].state is CommandState.FAILED and "heartbeat" in done[-1].reason:
                    raise CheckFailed(f"the robot stopped although heartbeats came: {done[-1].reason}")
                raise CheckSkipped(f"the navigation ended {shown_status(done[-1])} while the kit beat")
        last, _ = self._walk_far(*target)  # queued behind the running walk: back across the map
        silent_since = time.monotonic()

        def stopped() -> bool:
            got = self.statuses_of(last)
            return bool(got) and got[-1].state.final

        try:
            if not self.stream.wait(stopped, SILENT_SECONDS):
                raise CheckFailed(
                    f"no heartbeat for {SILENT_SECONDS:g} s: expected the robot's commands to fail, got "
                    f"{[s.state.value for s in self.statuses_of(last)]}"
                )
        finally:
            beats.close()
        ended = self.statuses_of(last)[-1]
        quiet = time.monotonic() - silent_since
        if ended.state is CommandState.SUCCEEDED and quiet < SILENT_LIMIT + 0.5:
            raise CheckSkipped(
                f"the robot crossed the map {quiet:.2f} s after the brain fell silent, within the "
                f"{SILENT_LIMIT:g} s an engine may wait: too fast a robot to test on this map (the check "
                f"needs two walks across it to last longer than {SILENT_LIMIT:g} s; "
                "run it with a slower clock)"
            )
        if ended.state is not CommandState.FAILED or not ended.reason:
            raise CheckFailed(f"no heartbeat: expected the command failed with a reason, got {ended}")
        return f"kept driving with MessagePack heartbeats, stopped without: {ended.reason}"

    def _walk_far(self, col: int, row: int) -> tuple[str, tuple[int, int]]:
        """Send the robot to the walkable cell farthest from ``(col, row)``; the command's id
        and that cell."""
        assert self.info is not None
        far = max(self.info.scene.walkable(), key=lambda c: abs(c[0] - col) + abs(c[1] - row))
        return self.send(Navigate(cell=Cell(*far))), far

    def _raw_query(self, key: str, payload: bytes) -> tuple[bytes, Encoding]:
        replies = list(
            self.bridge.session.get(
                key, payload=payload, encoding=zenoh_encoding(Encoding.MSGPACK), timeout=self.timeout
            )
        )
        if not replies or replies[0].ok is None:
            got = "none" if not replies else "an error"
            raise CheckFailed(f"a MessagePack query on '{key}': expected a reply, got {got}")
        sample = replies[0].ok
        return sample.payload.to_bytes(), Encoding.from_mime(str(sample.encoding))

    def check_messagepack(self) -> str:
        hello = encode(Hello(client="toyroom-conform", role="conform"), Encoding.MSGPACK)
        data, encoding = self._raw_query(self.keys.info, hello)
        if encoding is not Encoding.MSGPACK:
            raise CheckFailed(
                f"engine/info asked in MessagePack: expected a MessagePack reply, got {encoding.value}"
            )
        decode(data, EngineInfo, Encoding.MSGPACK)
        said = ["engine/info"]
        if not self._realtime():
            before = self.step(1).tick  # the engine may have run before the kit came (no reset yet)
            data, encoding = self._raw_query(self.keys.control, encode(Step(n=1), Encoding.MSGPACK))
            if encoding is not Encoding.MSGPACK:
                raise CheckFailed(
                    f"a step asked in MessagePack: expected a MessagePack reply, got {encoding.value}"
                )
            reply = decode(data, ControlReply, Encoding.MSGPACK)
            if reply.tick != before + 1:
                raise CheckFailed(
                    f"a step asked in MessagePack: expected tick {before + 1}, got {reply.tick}"
                )
            self.tick, self.last = reply.tick, reply
            said.append("engine/control")
        if self.robot is not None and Capability.ROBOT in (self.info.capabilities if self.info else ()):
            here = self.cell_of(self.robot)
            command = self.send(Navigate(cell=Cell(*here)), Encoding.MSGPACK)
            if not self.wait_status(command):
                raise CheckFailed("a robot command sent in MessagePack: expected a status, got none")
            if not self._realtime():
                self.finish(command, "a navigate sent in MessagePack")
            said.append("robot/<id>/command")
        return "understood on " + ", ".join(said)

    def check_control_reply(self) -> str:
        moving = self._start_moving()
        before, episode = self.tick, self.last.episode
        marks = (len(self.stream.events), len(self.stream.statuses))
        reply = self.step(30)
        if reply.state is None:
            raise CheckFailed(
                "expected the control_reply of a step to carry its last state (lock-step engines must), "
                "got none"
            )
        if not self.stream.wait(
            lambda: any(s.episode == episode and s.tick == reply.tick for s in self.stream.states),
            self.timeout,
        ):
            raise CheckFailed(f"expected the state of tick {reply.tick} published, got none")
        published = next(
            s for s in reversed(self.stream.states) if s.episode == episode and s.tick == reply.tick
        )
        if published != reply.state:
            raise CheckFailed(
                f"expected the reply's state to be the one published for tick {reply.tick}; they differ"
            )

        def during(tick: int) -> bool:
            return before < tick <= reply.tick

        self.stream.wait(
            lambda: sum(during(s.tick) for s in self.stream.statuses[marks[1] :]) >= len(reply.statuses), 0.5
        )
        events = [e for e in self.stream.events[marks[0] :] if e.episode == episode and during(e.tick)]
        statuses = [s for s in self.stream.statuses[marks[1] :] if during(s.tick)]
        for name, carried, sent in (
            ("events", list(reply.events), events),
            ("statuses", list(reply.statuses), statuses),
        ):
            if carried != sent:
                detail = f" ({carried[:2]} against {sent[:2]})" if carried or sent else ""
                raise CheckFailed(
                    f"expected the reply's {name} to be the {len(sent)} published during the step, "
                    f"got {len(carried)}{detail}"
                )
        if moving is not None:
            self.finish(moving, "the navigate of the control reply check")
        return f"state, {len(events)} events and {len(statuses)} statuses, as published"

    def _start_moving(self) -> str | None:
        """A navigation sent (and answered) when the robot acts, so a step has statuses."""
        assert self.info is not None
        robot = next((a for a in self.info.scene.agents if a.id == self.robot), None)
        if robot is None or not robot.acts or Capability.ROBOT not in self.info.capabilities:
            return None
        here = self.cell_of(robot.id)
        far = max(self.info.scene.walkable(), key=lambda c: abs(c[0] - here[0]) + abs(c[1] - here[1]))
        command = self.send(Navigate(cell=Cell(*far)))
        self.wait_status(command)
        return command

    def check_event_order(self) -> str:
        with self.stream.cond:
            arrivals = list(self.stream.arrivals)
        stated: set[tuple[int, int]] = set()
        events = 0
        for kind, episode, tick in arrivals:
            if kind == "state":
                stated.add((episode, tick))
            elif (episode, tick) in stated:
                raise CheckFailed(
                    f"expected each tick's events before its state, got an event of tick {tick} after it"
                )
            else:
                events += 1
        return f"{events} events, each before its tick's state"
