"""The engine conformance kit: checks that any engine speaks the protocol, the way
Gymnasium's ``check_env`` checks an environment.

:func:`check_engine` connects to whatever engine serves a world and runs every check in
order, each giving a :class:`CheckResult` that says what was expected and what came.
``toyroom conform --world W`` prints them and exits non-zero on any failure; the test
suite runs the same checks against every engine the repository has.

Each check passes, fails, is skipped (it applies, but what it needs was not there: a robot
that acts, a free item, a reachable spot; the reason says what) or does not apply (the other
clock mode, a capability the engine does not declare); ``toyroom conform`` prints the four
counts, and with ``--strict`` fails on a skip too.

Checks (:data:`CHECK_NAMES`, in order): the handshake (fields, version, capabilities by
name); the scene (ids unique, doors joining walkable cells, every location reachable,
visibility naming known locations); the liveliness token; a real-time clock that runs,
pauses and resumes, and stops the robot when heartbeats stop; MessagePack understood and
answered in kind on every key a client writes; reset with a seed; lock-step stepping
(``step n`` advances exactly ``n`` ticks, one state per tick, monotonic); the
``control_reply`` carrying the step's last state and exactly the events and statuses it
published; events naming known ids; every robot command kind ending ``succeeded`` or
``failed`` with a reason; a real navigation to the farthest cell, one cell at a time; pick,
place and give succeeding (with the state showing it); cancel of a running command; a
command sent while another runs answered and run after it; a command of an unknown kind
failed with a reason; impossible commands failing rather than hanging; every command's
statuses in order (accepted, running, one final, nothing after); each tick's events before
its state; the engine still serving after malformed input; ``truth`` when declared.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

from protocol import (
    PROTOCOL_VERSION,
    Capability,
    ClockMode,
    Hello,
    Reset,
    Version,
    scene_problems,
)

from ..bridge import Bridge
from ..errors import BridgeError
from ..handshake import ask_engine
from ..presence import PresenceWatcher
from .clock import ClockChecks
from .items import ItemChecks
from .probe import CheckFailed, CheckResult, CheckSkipped, NotApplicable, Outcome

CHECK_NAMES = (
    "handshake",
    "scene",
    "liveliness",
    "realtime",
    "pause and resume",
    "heartbeat",
    "messagepack",
    "reset",
    "stepping",
    "control reply",
    "events",
    "robot commands",
    "say several",
    "ask",
    "navigation",
    "pick place give",
    "cancel",
    "command while one runs",
    "unknown command",
    "impossible command",
    "status order",
    "event order",
    "malformed input",
    "truth",
)
"""Every check, in the order they run (later ones need earlier ones): the one list that
``toyroom conform`` and the pytest mixin (:mod:`bridge.conformance.suite`) both use."""

LOCKSTEP_ONLY = frozenset({"reset", "stepping", "control reply"})
"""Checks of ``reset`` and ``step`` themselves: they do not apply to a real-time engine. Every
other check runs in both clocks: in real time the kit waits for the engine's own ticks where
it would step them (a command is given as many ticks as in lock-step, at the engine's
``tick_seconds``, times :data:`~bridge.conformance.probe.REALTIME_SLACK`, plus the timeout),
and sends the robot's heartbeats every 0.25 s throughout, except in the heartbeat check."""

STOP_AFTER_FAILING = ("handshake", "reset")
"""Checks the others depend on: a failure ends the run."""


class Checker(ClockChecks, ItemChecks):
    """The checks, one method each (``check_<name>``; the clock's, the commands' and the
    items' in :mod:`~bridge.conformance.clock`, :mod:`~bridge.conformance.commands` and
    :mod:`~bridge.conformance.items`)."""

    def check_handshake(self) -> str:
        info = ask_engine(self.bridge, Hello(client="toyroom-conform", role="conform"), self.timeout)
        self.info = info
        ours, theirs = Version.parse(PROTOCOL_VERSION), Version.parse(info.protocol)
        if theirs.major != ours.major:
            raise CheckFailed(f"expected protocol {ours.major}.x, got {info.protocol}")
        if info.world != self.bridge.world:
            raise CheckFailed(f"expected world '{self.bridge.world}', got '{info.world}'")
        if not info.engine:
            raise CheckFailed("expected an engine name, got an empty string")
        return f"engine '{info.engine}', protocol {info.protocol}, capabilities " + (
            ", ".join(str(c) for c in info.capabilities) or "none"
        )

    def check_scene(self) -> str:
        assert self.info is not None
        problems = scene_problems(self.info.scene)
        if problems:
            raise CheckFailed("expected a consistent scene, got: " + "; ".join(problems))
        scene = self.info.scene
        return (
            f"{len(scene.regions)} regions, {len(scene.locations)} locations, {len(scene.agents)} agents, "
            f"{len(scene.items)} items"
        )

    def check_liveliness(self) -> str:
        watcher = PresenceWatcher(self.bridge.session, self.keys.alive("engine", "*"))
        try:
            if not watcher.wait_alive(timeout=self.timeout):
                raise CheckFailed(
                    f"expected a liveliness token under '{self.keys.alive('engine', '*')}', got none"
                )
            return ", ".join(p.name for p in watcher.alive)
        finally:
            watcher.close()

    def check_reset(self) -> str:
        assert self.info is not None
        if Capability.LOCKSTEP not in self.info.capabilities:
            raise CheckFailed("expected the 'lockstep' capability (the brain's reproducible mode), got none")
        before = len(self.stream.states)
        reply = self.control(Reset(scenario=None, seed=7))
        if reply.tick != 0:
            raise CheckFailed(f"expected tick 0 after reset, got {reply.tick}")
        self.episode, self.tick = reply.episode, 0
        arrived = self.stream.wait(
            lambda: any(s.episode == reply.episode and s.tick == 0 for s in self.stream.states[before:]),
            self.timeout,
        )
        if reply.state is None and not arrived:
            raise CheckFailed("expected the state of tick 0 (in the reply or on engine/state), got neither")
        return f"episode {reply.episode}"

    def check_stepping(self) -> str:
        for n in (1, 5, 3):
            before_tick, mark = self.tick, len(self.stream.states)
            reply = self.step(n)
            if reply.tick != before_tick + n:
                raise CheckFailed(
                    f"step {n} from tick {before_tick}: expected tick {before_tick + n}, got {reply.tick}"
                )
            if reply.state is not None and reply.state.tick != reply.tick:
                raise CheckFailed(
                    f"expected the reply's state at tick {reply.tick}, got tick {reply.state.tick}"
                )
            want = list(range(before_tick + 1, before_tick + n + 1))

            def published(mark: int = mark, episode: int = reply.episode) -> list[int]:
                return [s.tick for s in self.stream.states[mark:] if s.episode == episode]

            def complete(n: int = n, want: list[int] = want) -> bool:
                return published()[-n:] == want

            if not self.stream.wait(complete, self.timeout):
                raise CheckFailed(f"step {n}: expected states for ticks {want}, got {published()}")
            ticks = [s.tick for s in self.stream.states if s.episode == reply.episode]
            if ticks != sorted(ticks):
                raise CheckFailed(f"expected monotonic state ticks, got {ticks[-12:]}")
        return f"now at tick {self.tick}"

    def check_events(self) -> str:
        assert self.info is not None
        self.step(20 if self.realtime else 60)
        scene = self.info.scene
        agents = {a.id for a in scene.agents}
        items = {i.id for i in scene.items}
        places = (
            {r.id for r in scene.regions} | {loc.id for loc in scene.locations} | {d.id for d in scene.doors}
        )
        for event in self.stream.events:
            for name, value, known in (
                ("actor", event.actor, agents),
                ("target", event.target, agents),
                ("item", event.item, items),
                ("offer", event.offer, items),
                ("location", event.location, places),
            ):
                if value is not None and value not in known:
                    raise CheckFailed(
                        f"event {event.kind} at tick {event.tick}: {name} '{value}' is no known id"
                    )
        return f"{len(self.stream.events)} events, all with known ids"

    def check_malformed_input(self) -> str:
        for payload in (b"{not json", b'{"type": "teleport", "protocol": "1.0"}', b"\xff\x00"):
            replies = list(self.bridge.session.get(self.keys.control, payload=payload, timeout=self.timeout))
            if not replies or replies[0].err is None:
                raise CheckFailed(
                    f"control query with payload {payload!r}: expected an error reply, got "
                    f"{'none' if not replies else 'a success'}"
                )
        if self.robot is not None:
            self.bridge.session.put(self.keys.command(self.robot), b"\x00 garbage")
        self.bridge.session.put(self.keys.control, b"{}")
        before = self.latest().tick if self.realtime else self.tick
        reply = self.step(1)
        if reply.tick != before + 1 and not (self.realtime and reply.tick > before):
            raise CheckFailed(f"after malformed input, expected step to tick {before + 1}, got {reply.tick}")
        return (
            "error replies to bad queries, and still stepping (this check also puts '{}' on "
            "engine/control and garbage on the robot's command key: an engine or gateway that logs "
            "them as dropped is right to)"
        )

    def check_truth(self) -> str:
        assert self.info is not None
        if Capability.TRUTH not in self.info.capabilities:
            raise NotApplicable("the engine does not declare 'truth'")
        before = len(self.stream.truths)
        self.step(3)
        if not self.stream.wait(lambda: len(self.stream.truths) > before, self.timeout):
            raise CheckFailed("the engine declares 'truth' but published nothing on engine/truth in 3 ticks")
        return f"{len(self.stream.truths) - before} truth messages in 3 ticks"

    def checks(self) -> Iterator[tuple[str, Callable[[], str]]]:
        """Every check of :data:`CHECK_NAMES`, in order (lock-step ones do not apply to a
        real-time engine)."""
        for name in CHECK_NAMES:
            if name in LOCKSTEP_ONLY and self.info is not None and self.info.clock is ClockMode.REALTIME:
                yield name, _not_applicable("the clock runs in real time")
            else:
                yield name, getattr(self, f"check_{name.replace(' ', '_')}")


def _not_applicable(reason: str) -> Callable[[], str]:
    def check() -> str:
        raise NotApplicable(reason)

    return check


def check_engine(bridge: Bridge, timeout: float = 5.0) -> list[CheckResult]:
    """Run every check against the engine of ``bridge``'s world; stop at the first failure
    of a check the others depend on (the handshake, the reset)."""
    checker = Checker(bridge, timeout)
    results: list[CheckResult] = []
    try:
        _run_checks(checker, results)
    finally:
        checker.close()
    return results


def _run_checks(checker: Checker, results: list[CheckResult]) -> None:
    """Run the checks in order into ``results``, stopping at the first failure of a check the
    others depend on."""
    for name, check in checker.checks():
        try:
            results.append(CheckResult(name, Outcome.PASSED, check()))
        except NotApplicable as why:
            results.append(CheckResult(name, Outcome.NOT_APPLICABLE, str(why)))
        except CheckSkipped as why:
            results.append(CheckResult(name, Outcome.SKIPPED, str(why)))
        except (CheckFailed, BridgeError) as err:
            results.append(CheckResult(name, Outcome.FAILED, str(err)))
        except Exception as err:  # a protocol error or a bug in the engine's answers
            results.append(CheckResult(name, Outcome.FAILED, f"{type(err).__name__}: {err}"))
        if results[-1].failed and name in STOP_AFTER_FAILING:
            break


def summary(results: list[CheckResult]) -> str:
    """The counts (``19 passed, 0 skipped, 0 failed, 3 not applicable``)."""
    count = {outcome: sum(r.outcome is outcome for r in results) for outcome in Outcome}
    return (
        f"{count[Outcome.PASSED]} passed, {count[Outcome.SKIPPED]} skipped, {count[Outcome.FAILED]} failed, "
        f"{count[Outcome.NOT_APPLICABLE]} not applicable"
    )
