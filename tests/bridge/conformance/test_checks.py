"""The conformance kit's registry and the preconditions its checks share, without an engine:
every ``check_<name>`` function registered once, in order; a failure of a check the others
need ends the run; what a check raises decides its outcome; and each precondition of
:mod:`bridge.conformance.needs` says why a check does not run."""

from __future__ import annotations

import inspect
from typing import cast

import msgspec
import pytest
from support import golden_examples

from bridge.conformance import (
    CHECK_NAMES,
    CHECKS,
    Check,
    CheckOutcome,
    Probe,
    clock,
    commands,
    handshake,
    items,
    run_checks,
    stepping,
    wire,
)
from bridge.conformance.needs import need_acting_robot, need_lockstep, need_realtime
from bridge.conformance.probe import CheckFailed, CheckSkipped, NotApplicable
from bridge.errors import BridgeError
from protocol import Capability, ClockMode, EngineInfo

CHECK_MODULES = (handshake, clock, wire, stepping, commands, items)


def test_every_check_function_is_registered_once() -> None:
    defined = {
        function
        for module in CHECK_MODULES
        for name, function in inspect.getmembers(module, inspect.isfunction)
        if name.startswith("check_") and function.__module__ == module.__name__
    }
    registered = [check.run for check in CHECKS]
    assert len(registered) == len(set(registered)) and set(registered) == defined
    assert len(set(CHECK_NAMES)) == len(CHECK_NAMES) and CHECK_NAMES[0] == "handshake"
    assert [c.name for c in CHECKS if c.stops_run] == ["handshake", "reset"]
    assert Check(commands.check_command_while_one_runs).name == "command while one runs"


def test_a_failure_of_a_check_the_others_need_ends_the_run() -> None:
    def check_first(probe: Probe) -> str:
        raise CheckFailed("expected this, got that")

    def check_second(probe: Probe) -> str:
        return "never run"

    probe = cast(Probe, object())
    stopped = run_checks(probe, (Check(check_first, stops_run=True), Check(check_second)))
    assert [(r.name, r.outcome) for r in stopped] == [("first", CheckOutcome.FAILED)]
    going = run_checks(probe, (Check(check_first), Check(check_second)))
    assert [(r.name, r.outcome, r.detail) for r in going][1] == ("second", CheckOutcome.PASSED, "never run")


@pytest.mark.parametrize(
    ("raised", "outcome", "detail"),
    [
        (NotApplicable("not declared"), CheckOutcome.NOT_APPLICABLE, "not declared"),
        (CheckSkipped("nothing to pick"), CheckOutcome.SKIPPED, "nothing to pick"),
        (CheckFailed("expected 1, got 2"), CheckOutcome.FAILED, "expected 1, got 2"),
        (BridgeError("no reply"), CheckOutcome.FAILED, "no reply"),
        (KeyError("robot"), CheckOutcome.FAILED, "KeyError: 'robot'"),
    ],
)
def test_what_a_check_raises_is_its_outcome(raised: Exception, outcome: CheckOutcome, detail: str) -> None:
    def check_it(probe: Probe) -> str:
        raise raised

    (result,) = run_checks(cast(Probe, object()), (Check(check_it),))
    assert (result.name, result.outcome, result.detail) == ("it", outcome, detail)


def probe_on(info: EngineInfo) -> Probe:
    """A probe that knows ``info`` (as after the handshake), with no engine behind it."""
    probe = object.__new__(Probe)
    probe.info = info
    return probe


INFO = cast(EngineInfo, golden_examples()["engine_info"])
"""A lock-step engine declaring ``robot``, whose scene's robot acts."""


def test_need_acting_robot() -> None:
    assert need_acting_robot(probe_on(INFO)).id == "robot"
    without = msgspec.structs.replace(INFO, capabilities=(Capability.LOCKSTEP,))
    with pytest.raises(NotApplicable, match="does not declare 'robot'"):
        need_acting_robot(probe_on(without))
    people = tuple(a for a in INFO.scene.agents if a.id != "robot")
    no_robot = msgspec.structs.replace(INFO, scene=msgspec.structs.replace(INFO.scene, agents=people))
    with pytest.raises(CheckSkipped, match="no robot in the scene"):
        need_acting_robot(probe_on(no_robot))
    agents = tuple(msgspec.structs.replace(a, acts=a.id != "robot") for a in INFO.scene.agents)
    watching = msgspec.structs.replace(INFO, scene=msgspec.structs.replace(INFO.scene, agents=agents))
    with pytest.raises(CheckSkipped, match=r"robot 'robot' only observes in this scene \(acts: false\)"):
        need_acting_robot(probe_on(watching))


def test_need_realtime_and_need_lockstep() -> None:
    lockstep, realtime = probe_on(INFO), probe_on(msgspec.structs.replace(INFO, clock=ClockMode.REALTIME))
    need_lockstep(lockstep)
    need_realtime(realtime)
    with pytest.raises(NotApplicable, match="the clock runs in real time"):
        need_lockstep(realtime)
    with pytest.raises(NotApplicable, match=r"^the clock runs in lock-step$"):
        need_realtime(lockstep)
    with pytest.raises(NotApplicable, match="heartbeats matter"):
        need_realtime(lockstep, "the clock runs in lock-step (heartbeats matter in real time)")
