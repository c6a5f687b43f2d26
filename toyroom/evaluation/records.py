"""An episode's record (:class:`EpisodeRecord`): what :func:`~.episodes.run_episode` returns,
:mod:`.aggregate` and :mod:`.timing` read, ``episodes.jsonl`` (:mod:`.resume`) and
``episodes.json`` keep, and a Ray task sends back.

On disk a record is the JSON object it always was (:meth:`EpisodeRecord.to_builtins`,
:meth:`EpisodeRecord.from_builtins`): each run's scores (:class:`RunScores`) under its key
(an observer's name for the observing run, ``robot-<policy>`` for an acting one) beside the
episode's own keys, and the keys of a failed episode (``error``) or of a Ray task (``node``)
only where they apply, so a file written before these types reads the same."""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import msgspec

from .helpfulness import PersonHelp
from .metrics import Counts
from .robottasks import TaskTally

if TYPE_CHECKING:
    from .runs import RunResult


ROBOT = "robot"
"""The prefix of an acting run's key."""
FRESH = "fresh"
"""The suffix of a households run without memory."""


class RunKey(msgspec.Struct, frozen=True):
    """The key of one run's scores in an episode's record, as text ``str(key)``: an observing
    run under its observer's name (``btom``), an acting run as ``robot-<policy>`` (``policy``
    set); a households run without memory ends in ``-fresh`` (``btom-fresh``,
    ``robot-tom-fresh``). :meth:`parse` reads the text back."""

    observer: str = "btom"
    policy: str | None = None
    """The acting robot's policy (``None``: the robot observed)."""
    fresh: bool = False

    def __str__(self) -> str:
        name = self.observer if self.policy is None else f"{ROBOT}-{self.policy}"
        return f"{name}-{FRESH}" if self.fresh else name

    @property
    def label(self) -> str:
        """How tables name the run: its policy (``-fresh`` without memory), or its observer."""
        return str(self).removeprefix(f"{ROBOT}-")

    @classmethod
    def acting(cls, policy: object, fresh: bool = False) -> RunKey:
        """The key of a run whose robot acts by ``policy`` (a :class:`protocol.Policy` or its name)."""
        return cls(policy=str(getattr(policy, "value", policy)), fresh=fresh)

    @classmethod
    def parse(cls, key: str) -> RunKey:
        """The key whose text is ``key`` (an observer's name, ``robot-<policy>``, either with
        ``-fresh``)."""
        fresh = key.endswith(f"-{FRESH}")
        name = key.removesuffix(f"-{FRESH}") if fresh else key
        if name.startswith(f"{ROBOT}-"):
            return cls(policy=name[len(ROBOT) + 1 :], fresh=fresh)
        return cls(observer=name, fresh=fresh)


class RunScores(msgspec.Struct, kw_only=True):
    """One observer's (or one acting run's) scores of an episode."""

    counts: Counts
    outcome: dict[str, bool]
    """Per person, whether they ended with what they wanted."""
    ticks_to_goal: dict[str, int | None]
    """Per person, the first tick they had it (``None``: never)."""
    episode_ticks: int
    """The episode's last tick."""
    ticks: int
    """The ticks scored."""
    help: dict[str, PersonHelp] = msgspec.field(default_factory=dict)
    """Per person, how much the robot helped (:mod:`.helpfulness`)."""
    tasks: TaskTally = TaskTally()
    """The robot tasks of an acting run, begun and finished or not (:mod:`.robottasks`)."""

    @classmethod
    def of(cls, result: RunResult) -> RunScores:
        """What a record keeps of one observer's (or acting run's) scores of a run."""
        return cls(
            counts=result.counts,
            outcome=result.outcome.per_person,
            ticks_to_goal=result.outcome.ticks_to_goal,
            episode_ticks=result.outcome.ticks,
            ticks=result.ticks,
            help=dict(result.help),
            tasks=result.tasks,
        )


class EpisodeRecord(msgspec.Struct, kw_only=True):
    """Everything about one episode; a failed one has its ``error`` and no scores."""

    index: int
    map: str
    scenario: str
    run_seconds: dict[str, float] | None = None
    """Each run's seconds, by its tag without the scenario's name (none: failed)."""
    runs: dict[str, RunScores] = msgspec.field(default_factory=dict)
    """Each run's scores, by observer (the observing run) or ``robot-<policy>``."""
    error: str | None = None
    """Why the episode failed (none: it did not)."""
    failed_runs: list[str] | None = None
    """The failed attempts of its runs, each run again."""
    seconds: float | None = None
    """The episode's own seconds (none: failed)."""
    node: str | None = None
    """The Ray node it ran on (none: run locally)."""
    day: int | None = None
    """The day of its household (``toyroom eval --days``; none: an episode of its own)."""

    @property
    def failed(self) -> bool:
        return self.error is not None

    def to_builtins(self) -> dict[str, Any]:
        """The record as the JSON object of ``episodes.json``: the keys in the order they
        always had, each run's scores under its own key, the keys that do not apply left out."""
        out: dict[str, Any] = {"index": self.index, "map": self.map, "scenario": self.scenario}
        if self.run_seconds is not None:
            out["run_seconds"] = dict(self.run_seconds)
        out |= msgspec.to_builtins(self.runs)
        for name in ("error", "failed_runs", "seconds", "node", "day"):
            value = getattr(self, name)
            if value is not None:
                out[name] = msgspec.to_builtins(value)
        return out

    @classmethod
    def from_builtins(cls, data: dict[str, Any]) -> EpisodeRecord:
        """The record of a JSON object of :meth:`to_builtins`.

        Raises:
            msgspec.ValidationError: it is not one."""
        own = {name: data[name] for name in cls.__struct_fields__ if name in data and name != "runs"}
        runs = {key: value for key, value in data.items() if key not in cls.__struct_fields__}
        return msgspec.convert({**own, "runs": runs}, type=cls)
