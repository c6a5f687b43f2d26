"""Following people through the engine's state and events, tick by tick.

Each tick, every person's decisions are read off the stream: a move when their cell
changes to a neighbouring one, a take, drop or play when an event says so, and waits (the
planner's Stay) in proportion to how long they stand on their cell while a decision is due:
one for each decision time beyond what a move takes (:mod:`brain.tracking.waits`; not after
playing, not outside, not before their first decision). A decision is one HMM step (its
action likelihood, then the percept at the new position); a change of percept without a
decision (an item moved in view, the robot's speech, an item handed over) is a step with
the percept alone. Between steps the estimate is carried forward.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import cast

import numpy as np

from protocol import Activity, AgentKind, Event, EventKind, Observer, Perception, Scene, State

from ..memory.snapshot import Snapshot
from ..model.arrays import FloatArray
from ..model.belief import Percept, carried_off, true_values
from ..model.estimates import Estimate, reread, slim
from ..model.inference import switch_probability
from ..model.nested import NestedBeliefs
from ..model.person.gradedperson import GradedFilter, GradedModel
from ..model.person.personinterface import PersonFilter, StepRecord
from ..model.person.personmodel import person_model
from ..model.person.remembered import Remembered
from ..model.planner import Move, play_action
from ..model.revisions import SharedRevisions
from ..settings import ModelSettings
from .answered import answered
from .decisions import decided_action
from .hearsay import rumours
from .jointworld import JointWorld
from .percepts import person_percept
from .remembering import remembered_people, robot_items, start_view
from .statecheck import check_items
from .track import Chain, PersonTrack, add, forked, mixed, read_now, smoothed_chains, stepped
from .unseen import Unseen, believed_state, checked, unseen_world
from .waits import stays_due
from .worldview import WorldView


class MindTracker:
    """The brain's inference over every person of a scene (no I/O; feed it ticks).

    Args:
        scene: the engine's scene description.
        settings: model parameters.
        observer: which person model to use.
        revisions: belief revisions to share with the brain's other trackers of the same
            scene (:mod:`brain.model.revisions`; exact graded models only, else unused).
        memory: what the brain remembers of the household from an earlier day
            (:mod:`brain.memory`): each remembered person's desire and belief start from it
            (graded models), and an embodied robot's view of where items rest.
    """

    def __init__(
        self,
        scene: Scene,
        settings: ModelSettings | None = None,
        observer: Observer = Observer.BTOM,
        revisions: SharedRevisions | None = None,
        memory: Snapshot | None = None,
    ) -> None:
        self.scene = scene
        self.settings = settings or ModelSettings()
        self.observer = observer
        self.person_model = person_model(scene, self.settings, true_world=observer is Observer.TRUEBELIEF)
        if isinstance(self.person_model, GradedModel):
            self.person_model.revisions = revisions
        self.model = self.person_model.model
        self.exact = self.person_model.exact
        """Whether the exact joint model is used (else the factored one: see ``exact_max_worlds``)."""
        self.people = [a.id for a in scene.agents if a.kind is AgentKind.PERSON]
        self._changes = 0
        """Bumped whenever a person steps or their chains change (:meth:`_evidence`'s key)."""
        self._evidence_kept: dict[str, tuple[int, FloatArray]] = {}
        self.world: Unseen | None = None
        """The robot's own knowledge of where items rest (``None``: it sees everything): the
        joint branches or the factored world (:mod:`brain.tracking.unseen`)."""
        self.robot = next((a.id for a in scene.agents if a.kind is AgentKind.ROBOT), None)
        if self.settings.perception == Perception.EMBODIED:
            if self.robot is None:
                raise ValueError(
                    f"perception = embodied needs a robot in scene '{scene.name}', which has none"
                )
            self.world = unseen_world(scene, self.settings, self.person_model, self.people, self._evidence)
        count = (lambda _: 1) if self.world is None else self.world.count
        self.tracks = {p: PersonTrack(p, chains=[Chain() for _ in range(count(p))]) for p in self.people}
        self.ticks: list[int] = []
        self.truth: tuple[int, ...] = ()
        self.carriers: tuple[int, ...] = ()
        """Per item, the cell index of whoever carries it now (-1: nobody)."""
        self.carriers_moved: frozenset[int] = frozenset()
        """The items whose carrier moved (or put them down) at the last tick."""
        self.truths: dict[int, tuple[int, ...]] = {}
        """The true item values at every tick observed (for reading false beliefs then)."""
        self.labels: dict[tuple[int, str], str] = {}
        self._online: dict[str, tuple[tuple[object, ...], Estimate]] = {}
        """Person -> the last online estimate and what it was read from (chains are only ever
        dropped, so their count names the set left)."""
        s = self.settings
        self.nested = NestedBeliefs(self.model, self.people, s.r, s.delta, s.nested_peek_per_s)
        """Where each person believes each other believes each item is (:mod:`brain.model.nested`)."""
        self.nested_ticks: dict[int, FloatArray] = {}
        """Tick -> ``(P, K, L)`` the nested beliefs then, per pair of ``self.nested.pairs``."""
        if memory is not None and self.world is not None:
            start_view(self.world.view, self.model, memory, self.settings)
        self.remembered: dict[str, Remembered] = (
            {} if memory is None else remembered_people(memory, self.person_model, self.people, self.settings)
        )
        """Person -> what their model starts from (those the memory holds; graded models)."""

    @property
    def view(self) -> WorldView | None:
        """The joint branches' hypotheses (``None``: the robot sees everything, or keeps the
        factored world)."""
        return self.world.view if isinstance(self.world, JointWorld) else None

    def _evidence(self, person: str) -> FloatArray:
        """``(R,)`` the log-likelihood of ``person``'s decisions in each of their chains (read
        many times a tick by the factored world: kept until anyone steps or their chains
        change, :attr:`_changes`; read-only)."""
        kept = self._evidence_kept.get(person)
        if kept is not None and kept[0] == self._changes:
            return kept[1]
        chains = self.tracks[person].chains
        evidence = np.array([c.estimates[-1].log_evidence if c.estimates else 0.0 for c in chains])
        evidence.flags.writeable = False
        self._evidence_kept[person] = (self._changes, evidence)
        return evidence

    def _truths(self, person: str) -> list[tuple[int, ...]]:
        """The item values of each of ``person``'s chains (the truth, seeing everything)."""
        return [self.truth] if self.world is None else self.world.truths(person)

    def _weights(self, person: str) -> FloatArray:
        """``(R,)`` the weights ``person``'s chains are mixed with."""
        return np.ones(1) if self.world is None else self.world.weights(person)

    def robot_items(self) -> dict[str, dict[str, float]]:
        """Where the robot itself believes each item rests (:func:`.remembering.robot_items`)."""
        return robot_items(self.model, self.truth, [], None) if self.world is None else self.world.items()

    def where(self) -> FloatArray | None:
        """``(K, L)`` the robot's P(each item rests at each location) (``None``: it sees
        everything); a carried item's row is 0, the others are normalised."""
        return None if self.world is None else self.world.where()

    def observe(self, state: State, events: Sequence[Event]) -> None:
        """Take in one tick: the state at its end and the events that happened during it.

        Raises:
            StateError: the state does not say where every item of the scene is (nothing of
                it is taken in)."""
        check_items(self.model, state)
        model = self.model
        cell_of = {a.id: model.cell_index.get((a.cell.col, a.cell.row)) for a in state.agents}
        holders = {i.id: cell_of.get(i.held_by) if i.held_by else None for i in state.items}
        before = self.carriers
        self.carriers = tuple(-1 if (c := holders.get(k)) is None else c for k in model.items)
        self.carriers_moved = frozenset(k for k, c in enumerate(before) if c >= 0 and c != self.carriers[k])
        if self.world is None:
            self.truth = true_values(model, {i.id: i.location for i in state.items}, holders)
        else:
            self._look(state, events, cell_of.get(self.robot or ""), holders)
            self.truth = self.world.truth()
        self.truths[state.tick] = self.truth
        holding = {a.id: a.holding for a in state.agents}
        self.ticks.append(state.tick)
        for event in events:
            if event.kind is EventKind.WAYPOINT and event.label is not None:
                self.labels[(state.tick, event.actor)] = event.label
        cells: dict[str, int] = {}
        percepts: dict[str, Percept] = {}  # each person's, in their likeliest chain
        joint = 0 if self.world is None else self.world.likeliest() if self.world.exact else None
        for person in self.people:
            cell = cell_of.get(person)
            if cell is None:
                continue
            seen = self._observe_person(self.tracks[person], state, cell, holding.get(person), events)
            likeliest = joint if joint is not None else self.world.likeliest(person)  # type: ignore[union-attr]
            cells[person], percepts[person] = cell, seen[likeliest]
        # the nested beliefs: where each person is and what they perceive (likeliest chain)
        self.nested.observe(
            state.time, cells, percepts, lambda p: e.beliefs if (e := self.online(p)) else None
        )
        self.nested_ticks[state.tick] = self.nested.all_locations()

    def _look(
        self, state: State, events: Sequence[Event], robot_cell: int | None, holders: dict[str, int | None]
    ) -> None:
        """The embodied robot's look: its unseen world takes the tick in, and each person
        keeps the chains it keeps. At the first look, before any filter is made, the world is
        checked against the memory budget (:func:`.unseen.checked`)."""
        assert self.world is not None
        if robot_cell is None:
            self.world.settle(holders)
            return
        kept = self.world.observe(state, robot_cell, events, holders)
        if not self.ticks:
            world = checked(
                self.world, self.scene, self.settings, self.person_model, self.people, self._evidence
            )
            if world is not self.world:
                self.world = world
                kept = world.observe(state, robot_cell, events, holders)
            for person, track in self.tracks.items():
                track.chains = [Chain() for _ in range(world.count(person))]
            self._changes += 1
            return
        for person, track in self.tracks.items():
            track.chains = [track.chains[int(h)] for h in kept[person]]
        self._changes += 1

    def branch_weights(self) -> FloatArray:
        """``(H,)`` the posterior of each joint branch of the unseen world: its prior share
        times how well it explains every person's decisions so far (one branch when the robot
        sees all or keeps the factored world, whose weights are each person's: :meth:`_weights`)."""
        return self.world.branch_weights() if isinstance(self.world, JointWorld) else np.ones(1)

    def believed_state(self, state: State) -> State:
        """``state`` with every item resting out of the robot's sight where the likeliest
        branch puts it (``state`` itself when the robot sees everything): what it acts on."""
        return state if self.world is None else believed_state(state, self.model, self.world.believed())

    def _observe_person(
        self,
        track: PersonTrack,
        state: State,
        cell: int,
        holding: str | None,
        events: Sequence[Event],
    ) -> list[Percept]:
        """Take in one tick of one person; returns their percept in each of their chains
        (split first on what the factored world's items their cell shows)."""
        model = self.model
        tick = state.tick
        source = None if self.world is None else self.world.split(track.agent, cell)
        if source is not None:
            track.chains = forked(track.chains, source, self.person_model)
            self._changes += 1
        truths = self._truths(track.agent)
        held = 0 if holding is None else model.items.index(holding) + 1
        seen = [person_percept(model, track.agent, cell, held, t, events, self.carriers) for t in truths]
        track.said = answered(model.items, track.agent, self.robot, events, self.settings, track.said)
        if self.carriers_moved:  # an item they saw carried off: the carrier may take it anywhere
            own, moved = held - 1 if held else None, self.carriers_moved
            seen = [carried_off(c.percept, p, own, moved) for c, p in zip(track.chains, seen, strict=True)]
        if track.cell is None:  # first sight of this person: the percept alone
            self._push(track, tick, seen, None, truths, switch=0.0, now=state.time)
            # no wait is read before their first decision: since when they could act is unknown
            track.last_decision, track.settled = state.time, True
        else:
            action = decided_action(self.model, track.agent, track.cell, cell, events)
            self._wait(track, state, cell, action, truths)  # before this tick's play settles them
            if any(a.id == track.agent and a.activity is Activity.PLAYING for a in state.agents):
                track.settled = True
            if action is not None:
                track.settled = action >= play_action(model.n_items) or bool(model.outside[cell])
                likelihood = self.person_model.likelihood(track.cell, track.held, action)
                # the time since the last decision, less the Stays read in it (one decision time each)
                elapsed = (state.time - (track.last_decision or 0.0)) / self.settings.decision_seconds
                elapsed -= track.stays
                seconds = elapsed * self.settings.decision_seconds
                switch = switch_probability(self.settings.hazard, elapsed)
                decision = (track.cell, track.held, action)
                rumours = self._rumours(track.agent, state, seconds)
                self._push(
                    track, tick, seen, likelihood, truths, switch, decision, rumours, state.time, elapsed
                )
                track.last_decision, track.stays = state.time, 0
            elif (
                any(s != c.percept for s, c in zip(seen, track.chains, strict=True))
                or (
                    self.observer is Observer.TRUEBELIEF
                    and any(t != c.steps[-1].truth for t, c in zip(truths, track.chains, strict=True))
                )
                or self._forgetting_due(track, state.time)
                or track.said is not None
            ):
                # a new percept; to an observer without theory of mind, any change of the world;
                # or, for people who forget, a decision time without a step
                self._push(track, tick, seen, None, truths, switch=0.0, now=state.time)
        if track.cell is not None and cell != track.cell:
            track.moved_from = track.cell
        track.cell, track.held = cell, held
        return seen

    def _forgetting_due(self, track: PersonTrack, now: float) -> bool:
        """Whether a person who forgets has gone a decision time without a step (a percept
        step then lets their beliefs drift, so a long game of play is not a frozen mind)."""
        if self.settings.forget_per_s <= 0 or track.last_step is None:
            return False
        return now - track.last_step >= self.settings.decision_seconds

    def _rumours(self, person: str, state: State, seconds: float) -> tuple[tuple[int, int, float], ...]:
        """What ``person`` may have heard from the others in their region (:func:`.hearsay.rumours`)."""
        return rumours(state, person, self._tracked_online, self.settings.hearsay_per_s, seconds)

    def _tracked_online(self, person: str) -> Estimate | None:
        return self.online(person) if person in self.tracks else None

    def _wait(
        self, track: PersonTrack, state: State, cell: int, action: int | None, truths: list[tuple[int, ...]]
    ) -> None:
        """Read the Stays the person has made by standing on their cell since their last
        decision (:func:`~brain.tracking.waits.stays_due`), before this tick's decision if it
        has one: each one step of its own, of one decision time, on the percept they stood
        with. None while no decision is due (after playing, outside) or after a jump."""
        standing = action is not None or cell == track.cell
        if not standing or track.settled or track.cell is None or self.model.outside[track.cell]:
            return
        due = stays_due(state.time - (track.last_decision or 0.0), self.settings) - track.stays
        if due <= 0:
            return
        likelihood = self.person_model.likelihood(track.cell, track.held, Move.STAY.value)
        switch = switch_probability(self.settings.hazard, 1.0)
        decision = (track.cell, track.held, Move.STAY.value)
        rumours = self._rumours(track.agent, state, self.settings.decision_seconds)
        seen = [p for c in track.chains if (p := c.percept) is not None]  # what they stood seeing
        for _ in range(due):  # (this tick's percept comes after, with its decision or alone)
            self._push(track, state.tick, seen, likelihood, truths, switch, decision, rumours, state.time, 1)
        track.stays += due

    def _push(
        self,
        track: PersonTrack,
        tick: int,
        seen: list[Percept],
        likelihood: FloatArray | None,
        truths: list[tuple[int, ...]],
        switch: float,
        decision: tuple[int, int, int] | None = None,
        rumours: tuple[tuple[int, int, float], ...] = (),
        now: float | None = None,
        elapsed: float = 0.0,
    ) -> None:
        """One step of ``track`` in every branch (``seen`` and ``truths``: one per branch) at
        engine time ``now`` (for forgetting since the last step)."""
        if self.observer is Observer.PERCEPTONLY:
            likelihood, decision = None, None
        seconds = 0.0 if now is None or track.last_step is None else max(now - track.last_step, 0.0)
        forget = float(1.0 - np.exp(-self.settings.forget_per_s * seconds))
        track.last_step, mass = now if now is not None else track.last_step, self.settings.false_belief_mass
        pool = self.world is None or self.world.exact
        records = [
            StepRecord(
                tick=tick,
                percept=percept_,
                truth=truth,
                likelihood=likelihood,
                switch=switch,
                decision=decision,
                forget=forget,
                rumours=rumours,
                elapsed=elapsed,
                away=decision is not None and bool(self.model.outside[decision[0]]),  # from outside
                said=track.said,
            )
            for percept_, truth in zip(seen, truths, strict=True)
        ]
        for chain in track.chains:
            if chain.filter is None:
                chain.filter = self.person_model.new_filter()
                if isinstance(chain.filter, GradedFilter):
                    chain.filter.memory = self.remembered.get(track.agent)
        stepped([cast(PersonFilter, c.filter) for c in track.chains], records)  # every branch at once
        for chain, record in zip(track.chains, records, strict=True):
            chain.steps.append(record)
            est = cast(PersonFilter, chain.filter).estimate(record.truth)  # the factored world's: slim
            add(chain.estimates, est if pool else slim(est, mass), mass)
            chain.percept = record.percept
        self._changes += 1
        track.said, weights = None, self._weights(track.agent)
        track.steps.append(track.chains[int(np.argmax(weights))].steps[-1])
        add(track.estimates, mixed([c.estimates[-1] for c in track.chains], weights, mass, pool), mass)

    # ----- reading ----------------------------------------------------------------------

    def online(self, person: str) -> Estimate | None:
        """The latest online estimate of ``person`` (``None`` before the first sight), its
        false beliefs read against the world as it is now (in every branch, embodied)."""
        track = self.tracks[person]
        if not track.estimates:
            return None
        weights = None if self.world is None else self._weights(person)
        truths = self._truths(person)
        key: tuple[object, ...] = (len(track.estimates), len(track.chains), self.truth)  # what it reads
        key += (tuple(truths), b"" if weights is None else weights.tobytes())
        kept = self._online.get(person)
        if kept is not None and kept[0] == key:  # most ticks: nobody stepped, nothing moved
            return kept[1]
        mass = self.settings.false_belief_mass
        if weights is None:
            est = reread(track.estimates[-1], self.truth, mass)
        else:  # embodied: each chain's latest, mixed by the weights now
            est = read_now(track.chains, truths, weights, mass, self.world.exact)  # type: ignore[union-attr]
        self._online[person] = (key, est)
        return est

    def log_evidence(self, person: str) -> float:
        """The marginal log-likelihood of ``person``'s decisions so far under the model (0
        before any decision; :attr:`Estimate.log_evidence` of each step gives the running sum)."""
        track = self.tracks[person]
        return track.estimates[-1].log_evidence if track.estimates else 0.0

    def smoothed(self, person: str) -> list[Estimate]:
        """Smoothed estimates after each of ``person``'s steps (the factored models'
        approximately, :mod:`brain.model.factoredsmoother`); embodied, each branch smoothed and the
        branches mixed by their weights given everything."""
        chains, mass = self.tracks[person].chains, self.settings.false_belief_mass
        return smoothed_chains(self.person_model, chains, self._weights(person), mass)
