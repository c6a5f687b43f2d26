"""The conformance checks of lock-step: reset with a seed, ``step n`` advancing exactly ``n``
ticks with one state per tick, and the ``control_reply`` carrying the step's last state and
exactly the events and statuses it published. None applies to a real-time engine."""

from __future__ import annotations

from protocol import Capability, Reset

from .driving import walk_far
from .needs import need_acting_robot, need_lockstep
from .probe import CheckFailed, CheckSkipped, Probe


def check_reset(probe: Probe) -> str:
    """The engine declares ``lockstep``; ``reset`` with a seed answers tick 0 and its state."""
    need_lockstep(probe)
    assert probe.info is not None
    if Capability.LOCKSTEP not in probe.info.capabilities:
        raise CheckFailed("expected the 'lockstep' capability (the brain's reproducible mode), got none")
    before = len(probe.stream.states)
    reply = probe.control(Reset(scenario=None, seed=7))
    if reply.tick != 0:
        raise CheckFailed(f"expected tick 0 after reset, got {reply.tick}")
    probe.episode, probe.tick = reply.episode, 0
    arrived = probe.stream.wait(
        lambda: any(s.episode == reply.episode and s.tick == 0 for s in probe.stream.states[before:]),
        probe.timeout,
    )
    if reply.state is None and not arrived:
        raise CheckFailed("expected the state of tick 0 (in the reply or on engine/state), got neither")
    return f"episode {reply.episode}"


def check_stepping(probe: Probe) -> str:
    """``step n`` advances exactly ``n`` ticks, publishing one state per tick, in order."""
    need_lockstep(probe)
    for n in (1, 5, 3):
        before_tick, mark = probe.tick, len(probe.stream.states)
        reply = probe.step(n)
        if reply.tick != before_tick + n:
            raise CheckFailed(
                f"step {n} from tick {before_tick}: expected tick {before_tick + n}, got {reply.tick}"
            )
        if reply.state is not None and reply.state.tick != reply.tick:
            raise CheckFailed(f"expected the reply's state at tick {reply.tick}, got tick {reply.state.tick}")
        want = list(range(before_tick + 1, before_tick + n + 1))

        def published(mark: int = mark, episode: int = reply.episode) -> list[int]:
            return [s.tick for s in probe.stream.states[mark:] if s.episode == episode]

        def complete(n: int = n, want: list[int] = want) -> bool:
            return published()[-n:] == want

        if not probe.stream.wait(complete, probe.timeout):
            raise CheckFailed(f"step {n}: expected states for ticks {want}, got {published()}")
        ticks = [s.tick for s in probe.stream.states if s.episode == reply.episode]
        if ticks != sorted(ticks):
            raise CheckFailed(f"expected monotonic state ticks, got {ticks[-12:]}")
    return f"now at tick {probe.tick}"


def check_control_reply(probe: Probe) -> str:
    """A step's ``control_reply`` carries its last state, and exactly the events and statuses
    published during it."""
    need_lockstep(probe)
    moving = _start_moving(probe)
    before, episode = probe.tick, probe.last.episode
    marks = (len(probe.stream.events), len(probe.stream.statuses))
    reply = probe.step(30)
    if reply.state is None:
        raise CheckFailed(
            "expected the control_reply of a step to carry its last state (lock-step engines must), got none"
        )
    if not probe.stream.wait(
        lambda: any(s.episode == episode and s.tick == reply.tick for s in probe.stream.states),
        probe.timeout,
    ):
        raise CheckFailed(f"expected the state of tick {reply.tick} published, got none")
    published = next(
        s for s in reversed(probe.stream.states) if s.episode == episode and s.tick == reply.tick
    )
    if published != reply.state:
        raise CheckFailed(
            f"expected the reply's state to be the one published for tick {reply.tick}; they differ"
        )

    def during(tick: int) -> bool:
        return before < tick <= reply.tick

    probe.stream.wait(
        lambda: sum(during(s.tick) for s in probe.stream.statuses[marks[1] :]) >= len(reply.statuses), 0.5
    )
    events = [e for e in probe.stream.events[marks[0] :] if e.episode == episode and during(e.tick)]
    statuses = [s for s in probe.stream.statuses[marks[1] :] if during(s.tick)]
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
        probe.finish(moving, "the navigate of the control reply check")
    return f"state, {len(events)} events and {len(statuses)} statuses, as published"


def _start_moving(probe: Probe) -> str | None:
    """A navigation sent (and answered) when the robot acts, so a step has statuses."""
    try:
        robot = need_acting_robot(probe)
    except CheckSkipped:  # not applicable, too: no robot to move, the step has no statuses
        return None
    command, _ = walk_far(probe, *probe.cell_of(robot.id))
    probe.wait_status(command)
    return command
