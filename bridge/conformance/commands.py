"""The conformance checks of robot commands: every kind ending properly, a say of several
items at once and an ask (1.6), a real navigation to a far cell (pick, place and give are
:mod:`.items`'), cancel of a running command, a command sent while another runs, a kind the
engine does not know, impossible commands, and the order of every status seen."""

from __future__ import annotations

from protocol import (
    Action,
    AgentKind,
    Ask,
    Cancel,
    Cell,
    CommandState,
    CommandStatus,
    Event,
    EventKind,
    Give,
    Navigate,
    Pick,
    Place,
    Request,
    Say,
    SayTopic,
    Told,
    unknown_action,
)
from protocol.version import Version

from .driving import beside, far_cell, shown, succeed, until_running
from .needs import need_acting_robot
from .probe import CheckFailed, CheckSkipped, NotApplicable, Probe, kind_of

FINAL = (CommandState.SUCCEEDED, CommandState.FAILED, CommandState.CANCELLED)


def check_robot_commands(probe: Probe) -> str:
    """Every command kind ends ``succeeded``, or ``failed`` with a reason."""
    need_acting_robot(probe)
    assert probe.info is not None and probe.robot is not None
    scene = probe.info.scene
    home = next(a.home for a in scene.agents if a.id == probe.robot)
    person = next((a.id for a in scene.agents if a.kind is AgentKind.PERSON), "nobody")
    item = scene.items[0].id if scene.items else "nothing"
    location = scene.locations[0].id if scene.locations else "nowhere"
    actions: list[Action] = [
        Navigate(cell=home),
        Pick(item=item),
        Place(location=location),
        Give(person=person),
        Say(person=person, item=item, topic=SayTopic.LOCATION, location=location),
        Request(person=person, item=item),
    ]
    seen = []
    for action in actions:
        statuses = probe.command(action)
        states = [s.state for s in statuses]
        ok = states[:3] == [CommandState.ACCEPTED, CommandState.RUNNING, CommandState.SUCCEEDED] or (
            states[-1] is CommandState.FAILED
            and statuses[-1].reason
            and states[:-1] in ([], [CommandState.ACCEPTED], [CommandState.ACCEPTED, CommandState.RUNNING])
        )
        if not ok:
            raise CheckFailed(
                f"{kind_of(action)}: expected accepted -> running -> succeeded, or failed with a "
                f"reason, got {shown(statuses)}"
            )
        seen.append(f"{kind_of(action)} {states[-1].value}")
    return ", ".join(seen)


def check_say_several(probe: Probe) -> str:
    """A ``say`` of two items at once (``also``, from 1.6): one ``say`` event per item,
    on the same tick, to the person told."""
    need_acting_robot(probe)
    assert probe.info is not None and probe.robot is not None
    if Version.parse(probe.info.protocol) < Version(1, 6):
        raise NotApplicable(f"the engine speaks {probe.info.protocol}; a say of several items is from 1.6")
    scene = probe.info.scene
    people = [a.id for a in scene.agents if a.kind is AgentKind.PERSON]
    if len(scene.items) < 2 or not scene.locations or not people:
        raise CheckSkipped("the scene has fewer than two items, no location or no person")
    first, second, place = scene.items[0].id, scene.items[1].id, scene.locations[0].id
    say = Say(
        person=people[0], item=first, topic=SayTopic.LOCATION, location=place, also=(Told(second, place),)
    )
    mark, statuses = beside(probe, people[0], say)
    if statuses[-1].state is not CommandState.SUCCEEDED:
        if "earshot" in statuses[-1].reason:
            raise CheckSkipped(f"{people[0]} walked out of earshot: {shown(statuses)}")
        raise CheckFailed(f"say of '{first}' and '{second}': expected succeeded, got {shown(statuses)}")

    def said() -> list[Event]:
        return [e for e in probe.stream.events[mark:] if e.kind is EventKind.SAY and e.actor == probe.robot]

    probe.stream.wait(lambda: len(said()) >= 2, probe.timeout)
    got = [(e.tick, e.target, e.item, e.location) for e in said()]
    tick = got[0][0] if got else None
    expected = [(tick, people[0], first, place), (tick, people[0], second, place)]
    if got != expected:
        raise CheckFailed(f"expected a say event per item on one tick, {expected}, got {got}")
    return f"told {people[0]} of '{first}' and '{second}' in one say: two say events at tick {tick}"


def check_ask(probe: Probe) -> str:
    """An ``ask`` (from 1.6), open: an ``ask`` event, then the person's ``answer`` event
    (to the robot) whose yes or no the status repeats."""
    need_acting_robot(probe)
    assert probe.info is not None and probe.robot is not None
    if Version.parse(probe.info.protocol) < Version(1, 6):
        raise NotApplicable(f"the engine speaks {probe.info.protocol}; ask is from 1.6")
    people = [a.id for a in probe.info.scene.agents if a.kind is AgentKind.PERSON]
    if not people:
        raise CheckSkipped("the scene has no person to ask")
    mark, statuses = beside(probe, people[0], Ask(person=people[0]))
    final = statuses[-1]
    if final.state is CommandState.FAILED and ("earshot" in final.reason or "no answer" in final.reason):
        raise CheckSkipped(f"{people[0]} could not be asked: {shown(statuses)}")
    if final.state is not CommandState.SUCCEEDED or final.answer is None:
        raise CheckFailed(f"ask {people[0]}: expected succeeded with an answer, got {shown(statuses)}")

    def heard() -> list[Event]:
        return [e for e in probe.stream.events[mark:] if e.kind in (EventKind.ASK, EventKind.ANSWER)]

    probe.stream.wait(lambda: len(heard()) >= 2, probe.timeout)
    got = [(e.kind, e.actor, e.target) for e in heard()]
    expected = [(EventKind.ASK, probe.robot, people[0]), (EventKind.ANSWER, people[0], probe.robot)]
    if got != expected or heard()[1].answer is not final.answer:
        raise CheckFailed(
            f"expected an ask and an answer event ({expected}, answer {final.answer}), got {got}"
        )
    answer = heard()[1]
    return f"asked {people[0]}: wants {answer.item!r} ({'yes' if answer.answer else 'no'})"


def check_navigation(probe: Probe) -> str:
    """A navigation to the farthest cell succeeds, one cell at a time."""
    need_acting_robot(probe)
    assert probe.robot is not None
    target, distance = far_cell(probe)
    if distance < 2:
        raise CheckSkipped("no walkable cell two steps from the robot")
    mark = len(probe.stream.states)
    statuses = succeed(probe, Navigate(cell=Cell(*target)), f"navigate to the far cell {target}")
    ticks = statuses[-1].tick - statuses[0].tick
    if probe.cell_of(probe.robot) != target:
        raise CheckFailed(
            f"navigate succeeded: expected the robot on {target}, got {probe.cell_of(probe.robot)}"
        )
    trail = [
        (a.cell.col, a.cell.row)
        for s in probe.stream.states[mark:]
        if s.episode == probe.latest().episode
        for a in s.agents
        if a.id == probe.robot
    ]
    jumps = [
        (a, b) for a, b in zip(trail, trail[1:], strict=False) if max(abs(a[0] - b[0]), abs(a[1] - b[1])) > 1
    ]
    if jumps:
        raise CheckFailed(f"expected the robot to move one cell at a time, got the jump {jumps[0]}")
    return f"{distance} cells to {target} in {ticks} ticks"


def check_cancel(probe: Probe) -> str:
    """A cancel of an unknown command fails; one of a running navigate cancels it."""
    need_acting_robot(probe)
    statuses = probe.command(Cancel(command="conform-no-such-command"))
    if statuses[-1].state is not CommandState.FAILED or not statuses[-1].reason:
        raise CheckFailed(
            f"cancel of an unknown command: expected failed with a reason, got {shown(statuses)}"
        )
    target, distance = far_cell(probe)
    if distance < 3:
        return "unknown command failed; skipped a running one: no cell three steps away"
    navigate = probe.send(Navigate(cell=Cell(*target)))
    until_running(probe, navigate, f"navigate to {target}")
    cancel = probe.send(Cancel(command=navigate))
    probe.wait_status(cancel)
    ended = probe.finish(cancel, "cancel")
    probe.run_until(lambda: any(s.state.final for s in probe.statuses_of(navigate)), 5)
    victim = probe.statuses_of(navigate)
    if ended[-1].state is not CommandState.SUCCEEDED or victim[-1].state is not CommandState.CANCELLED:
        raise CheckFailed(
            f"cancel of a running navigate: expected the cancel succeeded and the navigate cancelled, "
            f"got cancel {shown(ended)}, navigate {shown(victim)}"
        )
    return "an unknown command fails; a running navigate ends cancelled"


def check_command_while_one_runs(probe: Probe) -> str:
    """A command sent while another runs is answered, and runs after it (or is refused)."""
    need_acting_robot(probe)
    assert probe.robot is not None
    start = probe.cell_of(probe.robot)
    target, distance = far_cell(probe)
    if distance < 3:
        raise CheckSkipped("no walkable cell three steps from the robot")
    first = probe.send(Navigate(cell=Cell(*target)))
    until_running(probe, first, f"navigate to {target}")
    second = probe.send(Navigate(cell=Cell(*start)))
    if not probe.wait_status(second):
        raise CheckFailed(
            "a command sent while another runs: expected a status (accepted or failed), got none"
        )
    one, two = probe.finish(first, "the first navigate"), probe.finish(second, "the second navigate")
    if two[0].state is CommandState.FAILED:
        return f"refused while busy: {two[0].reason}"
    order = [(s.command, s.state) for s in probe.stream.statuses if s.command in (first, second)]
    ended = order.index((first, one[-1].state))
    started = order.index((second, CommandState.RUNNING)) if (second, CommandState.RUNNING) in order else -1
    if started < ended and one[-1].state is not CommandState.CANCELLED:
        raise CheckFailed(
            f"a second command ran before the first ended: got {[f'{c} {s.value}' for c, s in order]}"
        )
    return f"queued: first {one[-1].state.value}, then second {two[-1].state.value}"


def check_unknown_command(probe: Probe) -> str:
    """A command of a kind the engine does not know fails with a reason."""
    need_acting_robot(probe)
    command = probe.send(unknown_action("conform-unknown-kind", {"note": "a kind from a newer version"}))
    statuses = (
        probe.finish(command, "a command of an unknown kind", max_steps=20)
        if probe.wait_status(command)
        else []
    )
    if not statuses or statuses[-1].state is not CommandState.FAILED or not statuses[-1].reason:
        raise CheckFailed(
            f"a command of an unknown kind: expected failed with a reason, got {shown(statuses)}"
        )
    return f"failed: {statuses[-1].reason}"


def check_impossible_command(probe: Probe) -> str:
    """A navigate into a wall and a pick of an unknown item fail rather than hang."""
    need_acting_robot(probe)
    assert probe.info is not None
    scene = probe.info.scene
    walkable = scene.walkable()
    wall = next(
        ((c, r) for r in range(scene.rows) for c in range(scene.columns) if (c, r) not in walkable),
        (scene.columns + 5, scene.rows + 5),
    )
    statuses = probe.command(Navigate(cell=Cell(*wall)), max_steps=60)
    if statuses[-1].state is not CommandState.FAILED or not statuses[-1].reason:
        raise CheckFailed(
            f"navigate into a wall at {wall}: expected failed with a reason, got {shown(statuses)}"
        )
    unknown = probe.command(Pick(item="no-such-item"), max_steps=60)
    if unknown[-1].state is not CommandState.FAILED or not unknown[-1].reason:
        raise CheckFailed(f"pick of an unknown item: expected failed with a reason, got {shown(unknown)}")
    return f"wall: '{statuses[-1].reason}'; unknown item: '{unknown[-1].reason}'"


def check_status_order(probe: Probe) -> str:
    """Every command's statuses come in order: accepted, running, one final, nothing after."""
    with probe.stream.cond:
        statuses = list(probe.stream.statuses)
    by_command: dict[str, list[CommandStatus]] = {}
    for status in statuses:
        by_command.setdefault(status.command, []).append(status)
    allowed = {
        None: {CommandState.ACCEPTED, CommandState.FAILED},
        CommandState.ACCEPTED: {CommandState.RUNNING, *FINAL},
        CommandState.RUNNING: set(FINAL),
    }
    for command, seen in by_command.items():
        before = None
        for status in seen:
            if before in FINAL or status.state not in allowed.get(before, set()):
                raise CheckFailed(
                    f"command {command}: expected accepted -> running -> one final status, got {shown(seen)}"
                )
            before = status.state
    return f"{len(statuses)} statuses of {len(by_command)} commands, each in order"
