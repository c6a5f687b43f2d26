"""Whether a participant's episode is over by the study's own terms (pure): its goal met, or
its time limit passed (:class:`protocol.Study`)."""

from __future__ import annotations

from dataclasses import dataclass, field

from protocol import Event, EventKind, State, Study, StudyOutcome


@dataclass
class GoalWatch:
    """Follows one participant's person through states and events; :attr:`outcome` is set
    (and kept) once the goal is met or the time limit passes.

    Args:
        study: the scenario's ``[study]`` (``None``: no goal, no limit of its own).
        person: the participant's person id.
    """

    study: Study | None
    person: str
    outcome: StudyOutcome | None = None
    after_done: bool = False
    """The goal's ``after`` step has been completed (or it names none)."""
    played: bool = False
    """The person has played with the goal's ``plays`` item since ``after``."""
    _by_limit: bool = field(default=True, init=False, repr=False)
    """A ``timed_out`` outcome came from the study's own time limit."""

    def __post_init__(self) -> None:
        goal = self.study.reached if self.study is not None else None
        self.after_done = goal is None or goal.after is None

    def on_event(self, event: Event) -> None:
        """An engine event: the ``after`` step completed, or the person playing."""
        goal = self.study.reached if self.study is not None else None
        if goal is None or event.actor != self.person:
            return
        if event.label is not None and event.label == goal.after:
            self.after_done = True
        elif self.after_done and event.kind == EventKind.PLAY and event.item == goal.plays:
            self.played = True

    def on_state(self, state: State) -> StudyOutcome | None:
        """One state: the outcome once the episode is over by the study's terms, else ``None``."""
        if self.outcome is not None or self.study is None:
            return self.outcome
        if self.after_done and self._met(state):
            self.outcome = StudyOutcome.GOAL_REACHED
        elif self.study.time_limit is not None and state.time >= self.study.time_limit:
            self.outcome = StudyOutcome.TIMED_OUT
        return self.outcome

    def _met(self, state: State) -> bool:
        goal = self.study.reached if self.study is not None else None
        me = next((a for a in state.agents if a.id == self.person), None)
        if goal is None or me is None:
            return False
        if goal.holds is not None:
            return me.holding == goal.holds
        if goal.enters is not None:
            return me.region == goal.enters
        return self.played

    def finish(self) -> StudyOutcome:
        """The episode ran to its own end (the scenario's ``max_ticks``, or its scripts over)
        before the study's terms ended it: ``timed_out`` when there was a goal to reach, else
        ``ended``. Kept as :attr:`outcome`."""
        if self.outcome is None:
            has_goal = self.study is not None and self.study.reached is not None
            self.outcome = StudyOutcome.TIMED_OUT if has_goal else StudyOutcome.ENDED
            self._by_limit = False
        return self.outcome

    def reason(self) -> str:
        """The outcome in words, as the page and the recording's ``reason`` say it."""
        limit = self.study.time_limit if self.study is not None else None
        if self.outcome is StudyOutcome.GOAL_REACHED:
            return "goal reached"
        if self.outcome is StudyOutcome.TIMED_OUT and self._by_limit and limit is not None:
            return f"the time limit of {limit:g} s was reached before the goal"
        if self.outcome is StudyOutcome.TIMED_OUT:
            return "the episode ended before the goal was reached"
        return "the episode ended"
