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

Each check is a free function ``check_<name>(probe) -> str`` (what it saw) in the module of
its concept (:mod:`.handshake`, :mod:`.clock`, :mod:`.wire`, :mod:`.stepping`,
:mod:`.commands`, :mod:`.items`); what several need before they can run is one helper each in
:mod:`.needs`. :data:`CHECKS` is the registry: the one tuple both ``toyroom conform`` and the
pytest mixin (:mod:`bridge.conformance.suite`) run, in its order.

What each check asks of an engine is its function's docstring; ``toyroom conform`` prints
the checks in :data:`CHECKS`' order.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..bridge import Bridge
from ..errors import BridgeError
from .clock import check_heartbeat, check_pause_and_resume, check_realtime
from .commands import (
    check_ask,
    check_cancel,
    check_command_while_one_runs,
    check_impossible_command,
    check_navigation,
    check_robot_commands,
    check_say_several,
    check_status_order,
    check_unknown_command,
)
from .handshake import check_handshake, check_liveliness, check_scene
from .items import check_pick_place_give
from .probe import CheckFailed, CheckOutcome, CheckResult, CheckSkipped, NotApplicable, Probe
from .stepping import check_control_reply, check_reset, check_stepping
from .wire import check_event_order, check_events, check_malformed_input, check_messagepack, check_truth


@dataclass(frozen=True)
class Check:
    """One registered check: its function (``check_<name>``, raising :class:`CheckFailed`,
    :class:`CheckSkipped` or :class:`NotApplicable`, else returning what it saw), and whether
    the others depend on it (its failure ends the run)."""

    run: Callable[[Probe], str]
    stops_run: bool = False

    @property
    def name(self) -> str:
        """The check's name as printed: its function's, ``check_`` off, spaces for ``_``."""
        return self.run.__name__.removeprefix("check_").replace("_", " ")


CHECKS = (
    Check(check_handshake, stops_run=True),
    Check(check_scene),
    Check(check_liveliness),
    Check(check_realtime),
    Check(check_pause_and_resume),
    Check(check_heartbeat),
    Check(check_messagepack),
    Check(check_reset, stops_run=True),
    Check(check_stepping),
    Check(check_control_reply),
    Check(check_events),
    Check(check_robot_commands),
    Check(check_say_several),
    Check(check_ask),
    Check(check_navigation),
    Check(check_pick_place_give),
    Check(check_cancel),
    Check(check_command_while_one_runs),
    Check(check_unknown_command),
    Check(check_impossible_command),
    Check(check_status_order),
    Check(check_event_order),
    Check(check_malformed_input),
    Check(check_truth),
)
"""Every check, in the order they run (later ones need earlier ones: the handshake's engine
info, the reset's episode, the commands' statuses for the order checks)."""

CHECK_NAMES = tuple(check.name for check in CHECKS)
"""The checks' names, in order."""


def check_engine(bridge: Bridge, timeout: float = 5.0) -> list[CheckResult]:
    """Run every check against the engine of ``bridge``'s world; stop at the first failure
    of a check the others depend on (the handshake, the reset)."""
    probe = Probe(bridge, timeout)
    try:
        return run_checks(probe)
    finally:
        probe.close()


def run_checks(probe: Probe, checks: tuple[Check, ...] = CHECKS) -> list[CheckResult]:
    """Run ``checks`` in order on ``probe``, each ending in a :class:`CheckResult`; stop after
    the first failure of one that :attr:`~Check.stops_run`."""
    results: list[CheckResult] = []
    for check in checks:
        results.append(run_check(probe, check))
        if results[-1].failed and check.stops_run:
            break
    return results


def run_check(probe: Probe, check: Check) -> CheckResult:
    """Run one check; its outcome by what it returned or raised."""
    try:
        return CheckResult(check.name, CheckOutcome.PASSED, check.run(probe))
    except NotApplicable as why:
        return CheckResult(check.name, CheckOutcome.NOT_APPLICABLE, str(why))
    except CheckSkipped as why:
        return CheckResult(check.name, CheckOutcome.SKIPPED, str(why))
    except (CheckFailed, BridgeError) as err:
        return CheckResult(check.name, CheckOutcome.FAILED, str(err))
    except Exception as err:  # a protocol error or a bug in the engine's answers
        return CheckResult(check.name, CheckOutcome.FAILED, f"{type(err).__name__}: {err}")


def summary(results: list[CheckResult]) -> str:
    """The counts (``19 passed, 0 skipped, 0 failed, 3 not applicable``)."""
    count = {outcome: sum(r.outcome is outcome for r in results) for outcome in CheckOutcome}
    return (
        f"{count[CheckOutcome.PASSED]} passed, {count[CheckOutcome.SKIPPED]} skipped, "
        f"{count[CheckOutcome.FAILED]} failed, "
        f"{count[CheckOutcome.NOT_APPLICABLE]} not applicable"
    )
