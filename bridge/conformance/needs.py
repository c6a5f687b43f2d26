"""What a check needs before it can run, one helper each: the engine's clock in the right
mode, and a robot that acts. Each raises :class:`NotApplicable` (the engine declares
otherwise) or :class:`CheckSkipped` (it applies, but the scene lacks it), saying why."""

from __future__ import annotations

from protocol import AgentSpec, Capability

from .probe import CheckSkipped, NotApplicable, Probe


def need_realtime(probe: Probe, reason: str = "the clock runs in lock-step") -> None:
    """Raise :class:`NotApplicable` (with ``reason``) unless the engine runs its own clock."""
    if not probe.realtime:
        raise NotApplicable(reason)


def need_lockstep(probe: Probe) -> None:
    """Raise :class:`NotApplicable` unless the engine steps on request: the checks of ``reset``
    and ``step`` themselves. Every other check runs in both clocks: in real time the kit waits
    for the engine's own ticks where it would step them (a command is given as many ticks as in
    lock-step, at the engine's ``tick_seconds``, times
    :data:`~bridge.conformance.probe.REALTIME_SLACK`, plus the timeout), and sends the robot's
    heartbeats every 0.25 s throughout, except in the heartbeat check."""
    if probe.realtime:
        raise NotApplicable("the clock runs in real time")


def need_acting_robot(probe: Probe) -> AgentSpec:
    """The scene's robot; raise unless the engine declares ``robot`` and that robot acts."""
    assert probe.info is not None
    if Capability.ROBOT not in probe.info.capabilities:
        raise NotApplicable("the engine does not declare 'robot'")
    if probe.robot is None:
        raise CheckSkipped("no robot in the scene")
    robot = next(a for a in probe.info.scene.agents if a.id == probe.robot)
    if not robot.acts:
        raise CheckSkipped(f"robot '{robot.id}' only observes in this scene (acts: false)")
    return robot
