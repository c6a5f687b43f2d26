"""Following people through the engine's state and events, tick by tick.

Each tick, every person's decisions are read off the stream: a move when their cell
changes to a neighbouring one, a take, drop or play when an event says so, and a wait
(the planner's Stay) when they stand still for ``ModelSettings.wait_decisions`` decision
times while a decision is due (not after playing, not outside; once per pause). A decision is
one HMM step (its action likelihood, then the percept at the new position); a change of
percept without a decision (an item moved in view, the robot's speech, an item handed
over) is a step with the percept alone. Between steps the estimate is carried forward.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from protocol import Activity, AgentKind, Event, EventKind, Observer, Scene, State

from ..model.arrays import FloatArray
from ..model.belief import Percept, percept, told, true_values
from ..model.estimates import Estimate, reread
from ..model.inference import switch_probability
from ..model.personmodel import PersonFilter, StepRecord, person_model
from ..model.planner import TAKE, Move, drop_action, play_action, use_action
from ..model.world import MOVE_STEPS
from ..settings import ModelSettings


@dataclass
class PersonTrack:
    """One person's chain: its steps, filtered posteriors and what was last seen."""

    agent: str
    cell: int | None = None
    moved_from: int | None = None
    """The cell the person left on their last move."""
    held: int = 0
    last_decision: float | None = None
    waited: bool = False
    """Whether the current pause was already counted as a decision to wait."""
    settled: bool = False
    """Whether the person played or left: no decision is due until they act again."""
    percept: Percept | None = None
    steps: list[StepRecord] = field(default_factory=list)
    filter: PersonFilter | None = None
    """The online filter (in the model's form), ``None`` before the first sight."""
    estimates: list[Estimate] = field(default_factory=list)


class MindTracker:
    """The brain's inference over every person of a scene (no I/O; feed it ticks).

    Args:
        scene: the engine's scene description.
        settings: model parameters.
        observer: which person model to use.
    """

    def __init__(
        self, scene: Scene, settings: ModelSettings | None = None, observer: Observer = Observer.BTOM
    ) -> None:
        self.scene = scene
        self.settings = settings or ModelSettings()
        self.observer = observer
        self.person_model = person_model(scene, self.settings, true_world=observer is Observer.TRUEBELIEF)
        self.model = self.person_model.model
        self.exact = self.person_model.exact
        """Whether the exact joint model is used (else the factored one: see ``exact_max_worlds``)."""
        self.people = [a.id for a in scene.agents if a.kind is AgentKind.PERSON]
        self.tracks = {p: PersonTrack(p) for p in self.people}
        self.ticks: list[int] = []
        self.truth: tuple[int, ...] = ()
        """The true item values at the last tick observed."""
        self.truths: dict[int, tuple[int, ...]] = {}
        """The true item values at every tick observed (for reading false beliefs then)."""
        self.labels: dict[tuple[int, str], str] = {}

    # ----- feeding --------------------------------------------------------------------

    def observe(self, state: State, events: Sequence[Event]) -> None:
        """Take in one tick: the state at its end and the events that happened during it."""
        model = self.model
        cell_of = {a.id: model.cell_index.get((a.cell.col, a.cell.row)) for a in state.agents}
        holders = {i.id: cell_of.get(i.held_by) if i.held_by else None for i in state.items}
        resting = {i.id: i.location for i in state.items}
        truth = true_values(model, resting, holders)
        self.truth = truth
        self.truths[state.tick] = truth
        holding = {a.id: a.holding for a in state.agents}
        self.ticks.append(state.tick)
        for event in events:
            if event.kind is EventKind.WAYPOINT and event.label is not None:
                self.labels[(state.tick, event.actor)] = event.label
        for person in self.people:
            cell = cell_of.get(person)
            if cell is None:
                continue
            self._observe_person(self.tracks[person], state, cell, holding.get(person), truth, events)

    def _observe_person(
        self,
        track: PersonTrack,
        state: State,
        cell: int,
        holding: str | None,
        truth: tuple[int, ...],
        events: Sequence[Event],
    ) -> None:
        model = self.model
        tick = state.tick
        held = 0 if holding is None else model.items.index(holding) + 1
        seen = percept(model, cell, truth, held - 1 if held else None)
        for event in events:  # speech: the robot told this person where an item is or who holds it
            if event.kind is EventKind.SAY and event.target == track.agent and event.item in model.items:
                k = model.items.index(event.item)
                if event.location in model.locations:
                    seen = told(seen, k, 2 * model.locations.index(event.location))
                elif event.detail.startswith("occupied by "):
                    seen = told(seen, k, truth[k] | 1)
        if track.cell is None:  # first sight of this person: the percept alone
            self._push(track, tick, seen, None, truth, switch=0.0)
            track.last_decision = state.time
        else:
            action = self._action(track, cell, events)
            if any(a.id == track.agent and a.activity is Activity.PLAYING for a in state.agents):
                track.settled = True
            if action is None and self._waiting(track, cell, state.time):
                action, track.waited = Move.STAY.value, True
            elif action is not None:
                track.waited = False
                track.settled = action >= play_action(model.n_items) or bool(model.outside[cell])
            if action is not None:
                likelihood = self.person_model.likelihood(track.cell, track.held, action)
                elapsed = (state.time - (track.last_decision or 0.0)) / self.settings.decision_seconds
                switch = switch_probability(self.settings.hazard, elapsed)
                decision = (track.cell, track.held, action)
                self._push(track, tick, seen, likelihood, truth, switch=switch, decision=decision)
                track.last_decision = state.time
            elif seen != track.percept or (
                self.observer is Observer.TRUEBELIEF and truth != track.steps[-1].truth
            ):
                # a new percept; or, to an observer without theory of mind, any change of the world
                self._push(track, tick, seen, None, truth, switch=0.0)
        if track.cell is not None and cell != track.cell:
            track.moved_from = track.cell
        track.cell, track.held = cell, held

    def _waiting(self, track: PersonTrack, cell: int, now: float) -> bool:
        """Whether the person has just stood still long enough, while a decision was due, to
        count as deciding to wait (once per pause; ``ModelSettings.wait_decisions``)."""
        wait = self.settings.wait_decisions * self.settings.decision_seconds
        if wait <= 0 or track.waited or track.settled or cell != track.cell or self.model.outside[cell]:
            return False
        return now - (track.last_decision or 0.0) >= wait

    def _action(self, track: PersonTrack, cell: int, events: Sequence[Event]) -> int | None:
        model = self.model
        K = model.n_items
        for event in events:
            if event.actor != track.agent:
                continue
            if event.kind is EventKind.TAKE and event.item in model.items:
                return TAKE + model.items.index(event.item)
            if event.kind is EventKind.DROP:
                return drop_action(K)
            if event.kind is EventKind.PLAY:
                return play_action(K)
            if event.kind is EventKind.USE and event.item in model.items:
                return use_action(K, model.items.index(event.item))
        assert track.cell is not None
        if cell == track.cell:
            return None
        old, new = model.cells[track.cell], model.cells[cell]
        delta = (int(new[0] - old[0]), int(new[1] - old[1]))
        if delta in MOVE_STEPS:
            return Move(MOVE_STEPS.index(delta)).value
        return None  # a jump (a reset, a lost tick): no decision to explain

    def _push(
        self,
        track: PersonTrack,
        tick: int,
        seen: Percept,
        likelihood: FloatArray | None,
        truth: tuple[int, ...],
        switch: float,
        decision: tuple[int, int, int] | None = None,
    ) -> None:
        if self.observer is Observer.PERCEPTONLY:
            likelihood, decision = None, None
        record = StepRecord(
            tick=tick, percept=seen, truth=truth, likelihood=likelihood, switch=switch, decision=decision
        )
        if track.filter is None:
            track.filter = self.person_model.new_filter()
        track.filter.step(record)
        track.steps.append(record)
        track.estimates.append(track.filter.estimate(truth))
        track.percept = seen

    # ----- reading ----------------------------------------------------------------------

    def online(self, person: str) -> Estimate | None:
        """The latest online estimate of ``person`` (``None`` before the first sight), its
        false beliefs read against the world as it is now."""
        track = self.tracks[person]
        if not track.estimates:
            return None
        return reread(track.estimates[-1], self.truth, self.settings.false_belief_mass)

    def log_evidence(self, person: str) -> float:
        """The marginal log-likelihood of ``person``'s decisions so far under the model (0
        before any decision; :attr:`Estimate.log_evidence` of each step gives the running sum)."""
        track = self.tracks[person]
        return track.estimates[-1].log_evidence if track.estimates else 0.0

    def smoothed(self, person: str) -> list[Estimate]:
        """Smoothed estimates after each of ``person``'s steps (the online ones when the
        factored model is used: it only filters)."""
        track = self.tracks[person]
        return self.person_model.smoothed(track.steps, track.estimates)
