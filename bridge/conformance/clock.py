"""The conformance checks of a real-time clock: it runs by itself, pauses and resumes, and
stops the robot when the brain's heartbeats stop."""

from __future__ import annotations

import time

from protocol import CommandState, CommandStatus, Encoding, Heartbeat, Pause, Resume

from ..pubsub import Publisher
from .driving import walk_far
from .needs import need_acting_robot, need_realtime
from .probe import HEARTBEAT_SECONDS, CheckFailed, CheckSkipped, Probe

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


def check_realtime(probe: Probe) -> str:
    """A real-time engine publishes states without being stepped."""
    need_realtime(probe)
    first = len(probe.stream.states)
    if not probe.stream.wait(lambda: len(probe.stream.states) > first + 2, probe.timeout):
        raise CheckFailed("a real-time clock should publish states by itself; none came")
    return "states arrive without stepping"


def check_pause_and_resume(probe: Probe) -> str:
    """``pause`` stops the states coming, ``resume`` starts them again."""
    need_realtime(probe)
    assert probe.info is not None
    paused = probe.control(Pause())
    if not paused.paused:
        raise CheckFailed(f"pause: expected a reply with paused true, got {paused}")
    settle = len(probe.stream.states)
    probe.stream.wait(lambda: False, 3 * probe.info.tick_seconds)  # a state already sent may land
    held = len(probe.stream.states)
    probe.stream.wait(lambda: False, 5 * probe.info.tick_seconds)
    if len(probe.stream.states) > held:
        raise CheckFailed(
            f"paused: expected no states for 5 ticks' time, got {len(probe.stream.states) - held} "
            f"(and {held - settle} while settling)"
        )
    resumed = probe.control(Resume())
    if resumed.paused:
        raise CheckFailed(f"resume: expected a reply with paused false, got {resumed}")
    after = len(probe.stream.states)
    if not probe.stream.wait(lambda: len(probe.stream.states) > after + 2, probe.timeout):
        raise CheckFailed("resumed: expected states to come again, none came")
    return "no states while paused, states again after resume"


def check_heartbeat(probe: Probe) -> str:
    """The robot keeps driving on MessagePack heartbeats, and stops without them."""
    need_realtime(probe, "the clock runs in lock-step (heartbeats matter in real time)")
    robot = need_acting_robot(probe)
    probe.silent = True  # the kit's own beats (which keep other checks' robot going) held
    try:
        return _beat_then_fall_silent(probe, robot.home.col, robot.home.row)
    finally:
        probe.silent = False


def _beat_then_fall_silent(probe: Probe, col: int, row: int) -> str:
    """Walk the robot to and fro while beating for :data:`BEATING_SECONDS`; then, as the
    beats stop, queue one more walk back across the map (a command counts as hearing from
    the brain, so the silence starts there) and expect the engine to fail the robot's
    commands within :data:`SILENT_SECONDS`."""
    assert probe.robot is not None
    command, target = walk_far(probe, col, row)
    # in MessagePack: an engine must read it on every key (and a JSON-only one stops the robot)
    beats: Publisher[Heartbeat] = Publisher(
        probe.bridge.session, probe.keys.heartbeat(probe.robot), encoding=Encoding.MSGPACK
    )
    for seq in range(int(BEATING_SECONDS / HEARTBEAT_SECONDS)):
        beats.put(Heartbeat(robot=probe.robot, seq=seq))
        time.sleep(HEARTBEAT_SECONDS)
        done = probe.statuses_of(command)
        if done and done[-1].state is CommandState.SUCCEEDED:  # a fast robot: walk it back
            command, target = walk_far(probe, *target)
        elif done and done[-1].state.final:
            if done[-1].state is CommandState.FAILED and "heartbeat" in done[-1].reason:
                raise CheckFailed(f"the robot stopped although heartbeats came: {done[-1].reason}")
            raise CheckSkipped(f"the navigation ended {shown_status(done[-1])} while the kit beat")
    last, _ = walk_far(probe, *target)  # queued behind the running walk: back across the map
    silent_since = time.monotonic()

    def stopped() -> bool:
        got = probe.statuses_of(last)
        return bool(got) and got[-1].state.final

    try:
        if not probe.stream.wait(stopped, SILENT_SECONDS):
            raise CheckFailed(
                f"no heartbeat for {SILENT_SECONDS:g} s: expected the robot's commands to fail, got "
                f"{[s.state.value for s in probe.statuses_of(last)]}"
            )
    finally:
        beats.close()
    ended = probe.statuses_of(last)[-1]
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
