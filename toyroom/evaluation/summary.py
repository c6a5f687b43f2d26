"""An evaluation's numbers as typed values: :func:`~.aggregate.aggregate` returns one
:class:`Summary` per set of episodes, a condition's entry is a :class:`ConditionSummary` (its
summary, by map and by task), a households condition's a :class:`HouseholdSummary` (by day),
and the whole evaluation an :class:`Evaluation` or a :class:`HouseholdEvaluation`, which the
reports read by attribute.

``metrics.json`` is written from these at one place, their ``to_builtins()``: the JSON layout
it always had (a condition's settings, name and numbers side by side in one object), so a file
written before these types reads the same."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any

import msgspec

from .conditions import Condition


class Interval(msgspec.Struct, kw_only=True):
    """A value with its bootstrap 95% interval (``lo`` and ``hi`` ``None`` without one; all
    three ``None`` where nothing was measured)."""

    mean: float | None
    lo: float | None
    hi: float | None

    @classmethod
    def of(cls, bounds: Mapping[str, float | None]) -> Interval:
        """The interval of a ``{mean, lo, hi}`` mapping (:mod:`.intervals`' results)."""
        return cls(mean=bounds["mean"], lo=bounds["lo"], hi=bounds["hi"])


NO_INTERVAL = Interval(mean=None, lo=None, hi=None)
"""What a measure without any value reads as."""

ObserverScores = dict[str, Interval | float | None]
"""One observer's metrics, by the names of :class:`~.scores.Scores` and in its order: those
that get an interval as an :class:`Interval`, the others (precision, recall, median leads) as
plain numbers."""


class CauseRecall(msgspec.Struct, kw_only=True):
    """False beliefs of one cause (:data:`~.metrics.CAUSES`): their ticks, those ticks' share
    of all false-belief ticks, and an observer's recall on them (``None``: none)."""

    ticks: int
    share: float | None
    recall: float | None


class HelpMeasures(msgspec.Struct, kw_only=True):
    """The help a robot policy gave, each a pooled mean (ticks, or counts per person) with its
    interval (:func:`~.aggregate.robot_metrics`); or one policy's minus another's, paired."""

    ticks_to_goal_fb: Interval
    """Ticks until a person with a false belief first had what they wanted (this run's people)."""
    ticks_to_goal_any_fb: Interval
    """The same over the people with a false belief in any policy's run of the episode."""
    ticks_from_false_belief: Interval
    """The first counted from the false belief's first tick."""
    wasted_trips: Interval
    """Wasted trips per person."""
    interruptions: Interval
    """Interruptions per person."""


HELP: tuple[str, ...] = HelpMeasures.__struct_fields__
"""The help measures, in order (:class:`HelpMeasures`' fields)."""


class PolicyHelp(HelpMeasures, kw_only=True):
    """One robot policy's help (:class:`HelpMeasures`), its cuts against the robot observing
    and their shares of the oracle's (``None`` for the observing robot itself, :data:`CUTS`),
    and the share of people who reached their goal."""

    cut: Interval | None
    share_of_oracle: Interval | None
    cut_any_fb: Interval | None
    share_of_oracle_any_fb: Interval | None
    success: float | None


CUTS = {"ticks_to_goal_fb": "", "ticks_to_goal_any_fb": "_any_fb"}
"""The help measures each policy's ``cut`` and ``share_of_oracle`` are read on, and the suffix
of their fields: ``cut`` = (none's mean - the policy's) / none's, ``share_of_oracle`` = (none's -
the policy's) / (none's - the oracle's) when the oracle ran and cut (:func:`~.intervals.cuts`)."""


class TickLosses(msgspec.Struct, kw_only=True):
    """Where the ticks to the goal of the people with a false belief went, for one policy (means
    over them, ``None`` without any): before the false belief, from it to the robot's first act
    for them, from that act to the goal; and the share of them the robot acted for."""

    before_false_belief: float | None
    before_robot_acted: float | None
    after_robot_acted: float | None
    robot_acted: float | None


LOSSES: tuple[str, ...] = TickLosses.__struct_fields__
"""The loss table's columns (:class:`TickLosses`' fields)."""


class TaskCounts(msgspec.Struct, kw_only=True):
    """One acting policy's robot tasks (:mod:`.robottasks`), summed over episodes, and the
    share begun and not finished (``None`` when none was begun)."""

    begun: int
    done: int
    dropped: int
    running: int
    unfinished_share: float | None


class Summary(msgspec.Struct, kw_only=True):
    """One set of episodes' numbers (:func:`~.aggregate.aggregate`): the episodes scored and
    failed, each observer's metrics with the first observer's paired differences, and per robot
    policy (``none``: observing) its help, losses and tasks."""

    episodes: int
    """Episodes scored (the failed ones left out)."""
    episodes_failed: int
    failed_runs_retried: int
    """Runs that crashed and were run again, over the scored episodes."""
    observers: dict[str, ObserverScores]
    """Observer (and ``majority``) -> its metrics."""
    paired_differences: dict[str, dict[str, Interval]]
    """Each other observer -> btom's metric minus theirs (those with an interval), paired."""
    revealed_stretches: int | None
    nested_pairs: int | None
    """Person-pair-item-ticks the nested beliefs were scored on."""
    want_ticks: int | None
    """Person-ticks the want was read on over false-belief stretches."""
    false_belief_causes: dict[str, dict[str, CauseRecall]]
    """Observer -> cause -> its false beliefs and the observer's recall on them."""
    robot: dict[str, PolicyHelp]
    """Policy -> its help (empty without episodes)."""
    robot_differences: dict[str, HelpMeasures]
    """Each policy but the first -> the first's help minus its, paired."""
    robot_losses: dict[str, TickLosses]
    robot_tasks: dict[str, TaskCounts]
    """Acting policy -> its tasks."""


def _float(value: object) -> float:
    """A float subclass (numpy's) as the float it is: ``json`` writes both alike."""
    if isinstance(value, float):
        return float(value)
    raise TypeError(f"expected a number in an evaluation's summary, got {type(value).__name__}")


def _builtins(value: object) -> Any:
    """``value`` (summaries, mappings of them) as JSON builtins, fields in order."""
    return msgspec.to_builtins(value, enc_hook=_float)


def _condition_fields(condition: Condition) -> dict[str, Any]:
    """A condition's settings and name, as ``metrics.json`` has them first."""
    return {**dataclasses.asdict(condition), "name": condition.name}


class ConditionSummary(msgspec.Struct, kw_only=True):
    """One condition of an evaluation: its numbers over every episode, per map and, for a
    ``tasks`` condition, per task kind (``None`` otherwise)."""

    condition: Condition
    numbers: Summary
    by_map: dict[str, Summary]
    by_task: dict[str, Summary] | None = None

    @property
    def name(self) -> str:
        """The condition's name."""
        return self.condition.name

    def to_builtins(self) -> dict[str, Any]:
        """The condition's entry of ``metrics.json``: its settings and name, its numbers, then
        ``by_map`` (and ``by_task``)."""
        out = _condition_fields(self.condition) | _builtins(self.numbers)
        out["by_map"] = _builtins(self.by_map)
        if self.by_task is not None:
            out["by_task"] = _builtins(self.by_task)
        return out


class Evaluation(msgspec.Struct, kw_only=True):
    """A ``toyroom eval`` (:func:`~.episodes.evaluate`): how it ran and each condition's numbers."""

    episodes: int
    """Episodes per condition."""
    seed: int
    brain_args: list[str]
    policies: list[str]
    """The acting robot's policies, then ``none`` (observing)."""
    command: str
    timing: dict[str, Any]
    """How long it took (:func:`~.timing.timing`)."""
    conditions: list[ConditionSummary]

    def to_builtins(self) -> dict[str, Any]:
        """``metrics.json``'s document."""
        out = {name: getattr(self, name) for name in self.__struct_fields__}
        out["conditions"] = [condition.to_builtins() for condition in self.conditions]
        return out


class HouseholdSummary(msgspec.Struct, kw_only=True):
    """One condition of a households evaluation: its numbers per day (by the day's number as
    text, from ``"1"``), and over the later days of each household pooled as one record
    (``None`` when no household had them all: :func:`~.days.by_day`)."""

    condition: Condition
    by_day: dict[str, Summary]
    later: Summary | None = None

    @property
    def name(self) -> str:
        """The condition's name."""
        return self.condition.name

    def to_builtins(self) -> dict[str, Any]:
        """The condition's entry of ``metrics.json``: its settings and name, ``by_day`` (and
        ``later``)."""
        out = _condition_fields(self.condition)
        out["by_day"] = _builtins(self.by_day)
        if self.later is not None:
            out["later"] = _builtins(self.later)
        return out


class HouseholdEvaluation(msgspec.Struct, kw_only=True):
    """A ``toyroom eval --days`` (:func:`~.households.evaluate_households`): how it ran and
    each condition's numbers by day."""

    households: int
    """Households per condition."""
    days: int
    seed: int
    brain_args: list[str]
    policies: list[str]
    command: str
    observers: list[str]
    conditions: list[HouseholdSummary]

    def to_builtins(self) -> dict[str, Any]:
        """``metrics.json``'s document."""
        out = {name: getattr(self, name) for name in self.__struct_fields__}
        out["conditions"] = [condition.to_builtins() for condition in self.conditions]
        return out
