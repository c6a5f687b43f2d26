"""The robot's settings (:class:`RobotSettings`): when it acts, what its help is weighed
against, and how long it waits; re-exported by :mod:`brain.settings`, which reads settings
files."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass

from protocol import PREFERENCE_THRESHOLD, Policy

MAGNITUDE = 1e6
"""The largest size of any float setting (model's and robot's). The model's numbers are
sums and products of them: ``beta`` times Q-values (at most a utility over ``1 - discount``,
itself at least float64's 1e-16: ``1e6 * 1e6 / 1e-16 = 1e28``), ``r`` summed over the model's
worlds, rates (per second) times seconds; within this bound each stays far inside float64's
1.8e308, so no setting can make the model's numbers overflow into inf or NaN (``beta=1e308``
did: ``beta * Q`` overflowed before the softmax could subtract its maximum, and mind.csv
filled with NaN). The softmax itself already subtracts the largest ``beta * Q`` (log-sum-exp)."""

MIN_DECISION_SECONDS = 0.05
"""The shortest ``decision_seconds`` (s). Every decision time a person stands is one Stay step
of their filter, so the brain's work per engine second grows as ``1 / decision_seconds``:
``paper-robot`` ran in 5 s at the default 0.7, 8 s at 0.05, 13 s at 0.01, and at ``1e-9`` it
reached tick 5 in 170 s. 0.05 s is a sixth of the quickest step sim2d's people take (0.3 s)."""
MIN_COMMAND_TIMEOUT = 1.0
"""The shortest ``navigate_timeout``, ``action_timeout`` and ``answer_timeout`` (engine s): an
engine answers a command a tick later at the soonest, and a walk to the next cell takes 0.67 s
(1.5 m/s); a shorter timeout fails commands that are going as they should, each then tried
``attempts`` times for nothing."""

FINITE_ALLOWED = (
    f"a finite number of size at most {MAGNITUDE:.0e}".replace("e+0", "e")
    + ": the model multiplies and sums the settings, so a larger one overflows float64 into inf/NaN"
)
"""What :func:`unbounded` says every float setting allows."""

ROBOT_ALLOWED = {
    "policy": f"one of {', '.join(Policy.names())}",
    "confirm_seconds": "confirm_seconds >= 0",
    "attempts": "an int >= 1",
    "navigate_timeout": f"navigate_timeout >= {MIN_COMMAND_TIMEOUT:g} (engine seconds)",
    "action_timeout": f"action_timeout >= {MIN_COMMAND_TIMEOUT:g} (engine seconds)",
    "answer_timeout": f"answer_timeout >= {MIN_COMMAND_TIMEOUT:g} (engine seconds)",
    "deception_threshold": "0 <= deception_threshold <= 1",
    "interruption_cost": "interruption_cost >= 0 (steps)",
    "robot_step_cost": "robot_step_cost >= 0 (steps)",
    "put_back_slack": "put_back_slack >= 0 (steps)",
    "tell_item_cost": "tell_item_cost >= 0 (steps)",
    "ask_again_after": "ask_again_after >= 0 (engine seconds)",
    "search_factor": "search_factor >= 1",
}
"""What the robot's settings allow of each value they check that is not a share of one."""


def allowed_text(values: object, names: list[str], allowed: Mapping[str, str]) -> str:
    """``name=value (allowed: ...)`` for each of ``names``, for an error message."""
    return "; ".join(
        f"{n}={getattr(values, n)!r} (allowed: {allowed.get(n) or f'0 <= {n} <= 1'})" for n in names
    )


def unbounded(values: object) -> list[str]:
    """The float fields of the dataclass ``values`` that are not finite or are larger than
    :data:`MAGNITUDE` (NaN, an infinity, ``1e308``), by name."""
    return [
        f.name
        for f in dataclasses.fields(values)  # type: ignore[arg-type]
        if isinstance(value := getattr(values, f.name), float)
        and not (math.isfinite(value) and abs(value) <= MAGNITUDE)
    ]


def check_values(kind: str, values: object, checks: Mapping[str, bool], allowed: Mapping[str, str]) -> None:
    """Raise ``ValueError`` naming every value out of bounds: first any float that is not
    finite or too large (:func:`unbounded`), else any of ``checks`` that failed.

    Raises:
        ValueError: ``invalid KIND settings: name=value (allowed: ...)``, one line.
    """
    huge = unbounded(values)
    if huge:
        raise ValueError(
            f"invalid {kind} settings: {allowed_text(values, huge, dict.fromkeys(huge, FINITE_ALLOWED))}"
        )
    bad = [name for name, ok in checks.items() if not ok]
    if bad:
        raise ValueError(f"invalid {kind} settings: {allowed_text(values, bad, allowed)}")


@dataclass(frozen=True)
class RobotSettings:
    """When the robot acts, and how long it waits.

    Attributes:
        preference_threshold: a person's preference must be at least this probable for
            the robot to act on it.
        intention_threshold: the same for the intention (item and believed location).
        belief_threshold: a false belief (``Estimate.false_belief``: the person's belief gives
            the item's true location less than ``false_belief_mass`` times its likeliest
            location's) must be at least this probable for the robot to act on it.
        put_back_preference: an item nobody left where it is is put back for someone who
            does not know it was moved only when they want it at least this probably (0:
            for anyone with a false belief about it: the robot walks, nobody is interrupted).
        put_back_harm: no put-back when someone else who may want the item believes it where
            it is now (their belief there times their preference at least this).
        inform_mass: a person heading for a wrong place is told where the item they want
            is when they probably hold a false belief about it, or when their belief gives
            its true place less than this (they do not know where it is: searching).
        swap_accept: a swap is asked for only when the holder probably accepts (their
            preference for the offered item at least this) or the person does not know who
            holds the item.
        confirm_seconds: engine seconds a task must be seen, tick after tick, before the
            robot starts it (a passing blip of the online estimates starts nothing).
        attempts: how often the robot tries one task before giving up on it.
        navigate_timeout: engine seconds a navigation may take (each of the three timeouts at
            least :data:`MIN_COMMAND_TIMEOUT`, 1 s).
        action_timeout: engine seconds a pick, place or say may take.
        answer_timeout: engine seconds a give, request or ask may take: each waits for a
            person's answer, and a participant may take their time (sim2d's own limit for a
            participant's answer is 30 s, after which it is no; issue 55).
        policy: ``tom`` (the paper's tree, on the people's inferred minds, with the
            thresholds above), ``benefit`` (the same minds, each task chosen by its expected
            benefit against the costs below: :mod:`brain.robot.choice`), or a baseline
            without theory of mind: ``tidy`` (put every moved item back where it was) or
            ``announce`` (tell everyone about every move); or ``oracle``: reads the simulated
            people's true minds (an upper bound, not a robot one could build): ``tom``'s tree on
            the engine's truth (``engine/truth``: sim2d's autonomous people) instead of the
            inferred minds (:mod:`brain.oracle`).
        deception_threshold: a move reads as a likely deception (:mod:`brain.robot.deception`)
            when its mover believes, at least this probably, that someone who most probably
            wants the item still believes it where it was (did not see the move).
        on_deception: ``tell`` the deceived person where the item is (and no put-back behind
            the mover's back), or ``put_back`` as for any move.
        interruption_cost: what one word from the robot costs the person it speaks to, in
            *steps* (cells of a person's walk: people and the robot walk at the same speed,
            so a step is a fixed number of engine ticks); the ``benefit`` robot tells a person
            where an item is only when the steps it expects to save them, weighted by how
            probably they want the item, exceed this (``benefit`` policy:
            :mod:`brain.robot.benefit`).
        robot_step_cost: steps of a person's time one cell of the robot's own walk is
            worth (its cost of going somewhere to help).
        search_factor: how many steps a person who finds a place empty takes, per step of
            the direct walk from there, to find the item (a search is longer than a walk).
        tell_item_cost: what each item named in a tell costs the person told, in steps, on
            top of ``interruption_cost`` (one utterance may tell where several items are: the
            ``benefit`` robot names an item only when the steps its word is expected to save
            exceed this).
        ask_again_after: engine seconds before the ``benefit`` robot may ask a person it has
            asked what they are looking for again (it asks only when what it expects to learn
            is worth more steps than the interruption: :func:`brain.robot.benefit.ask_worth`).
        put_back_slack: steps a put-back may land after the person it is for could reach
            the place and still be counted as in time (they may dawdle).
        lasting_want: read going out as an errand: weigh help by P(the person wants the
            item) plus P(they head out) times what they wanted over the items the last time
            they were not heading out (:func:`brain.robot.benefit.lasting_preference`; else by
            the preference posterior, in which an errand reads as wanting to leave).
    """

    preference_threshold: float = PREFERENCE_THRESHOLD
    intention_threshold: float = 0.5
    belief_threshold: float = 0.6
    put_back_preference: float = 0.0
    put_back_harm: float = 0.3
    inform_mass: float = 0.5
    swap_accept: float = 0.5
    confirm_seconds: float = 0.5
    attempts: int = 2
    navigate_timeout: float = 60.0
    action_timeout: float = 10.0
    answer_timeout: float = 45.0
    policy: Policy = Policy.TOM
    deception_threshold: float = 0.5
    on_deception: str = "tell"
    interruption_cost: float = 1.0
    robot_step_cost: float = 0.05
    search_factor: float = 2.5
    put_back_slack: float = 0.0
    tell_item_cost: float = 0.25
    ask_again_after: float = 60.0
    lasting_want: bool = False

    def __post_init__(self) -> None:
        if self.policy not in ROBOT_POLICIES:
            raise ValueError(
                f"invalid robot settings: policy={self.policy!r} (one of {', '.join(ROBOT_POLICIES)})"
            )
        object.__setattr__(self, "policy", Policy(self.policy))  # a name given as text: its choice
        if self.on_deception not in ("tell", "put_back"):
            raise ValueError(
                f"invalid robot settings: on_deception={self.on_deception!r} (one of tell, put_back)"
            )
        checks = {name: 0.0 <= getattr(self, name) <= 1.0 for name in ROBOT_SHARES}
        checks |= {"confirm_seconds": self.confirm_seconds >= 0, "attempts": self.attempts >= 1}
        checks |= {name: getattr(self, name) >= MIN_COMMAND_TIMEOUT for name in ROBOT_TIMEOUTS}
        checks |= {name: getattr(self, name) >= 0 for name in ROBOT_COSTS}
        checks |= {"search_factor": self.search_factor >= 1, "ask_again_after": self.ask_again_after >= 0}
        check_values("robot", self, checks, ROBOT_ALLOWED)


ROBOT_POLICIES = Policy.names()
""":attr:`RobotSettings.policy`'s values (:class:`protocol.Policy`; :data:`brain.robot.branches.POLICIES`)."""
ROBOT_SHARES = (
    "preference_threshold",
    "intention_threshold",
    "belief_threshold",
    "put_back_preference",
    "put_back_harm",
    "inform_mass",
    "swap_accept",
    "deception_threshold",
)
""":class:`RobotSettings` that are probabilities (or shares of one): each in [0, 1]."""
ROBOT_TIMEOUTS = ("navigate_timeout", "action_timeout", "answer_timeout")
""":class:`RobotSettings` that are timeouts (engine seconds): each at least :data:`MIN_COMMAND_TIMEOUT`."""
ROBOT_COSTS = ("interruption_cost", "robot_step_cost", "put_back_slack", "tell_item_cost")
""":class:`RobotSettings` that are costs in steps: each at least 0."""
