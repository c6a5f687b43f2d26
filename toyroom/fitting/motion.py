"""The motion heuristic as a model ``toyroom fit`` compares (Baker et al. 2017's baseline):
no beliefs, no desires, no planning; only where each person is heading.

As a model of actions: the person's heading is the goal (an item location, or the outside)
whose walking distance fell most over their last :data:`WINDOW` decisions
(:func:`toyroom.evaluation.heuristic.heading`; the last heading while none fell). Each possible
action's utility is how much it shortens the walk to that goal (+1, 0 or -1 for a move, 0 for
every other action), and the choice is ``(1 - epsilon) softmax(beta u) + epsilon / A``, so
``beta`` and ``epsilon`` are fitted like the brain's. Without a heading the choice is uniform
over the possible actions. Actions are possible where the planner's Q-value is finite (every
action but an impossible move for factored scenes).

As a model of judgments it is the evaluation's motion observer
(:class:`toyroom.evaluation.heuristic.MotionHeuristic`), which has no parameters: the desire is
the item at the heading (or ``out``), beliefs are the truth, no false belief; its utility
of a goal is its P(most wanted) (as one favourite's is) and a goal's rank is by that; it has
no smoothed estimate, so it answers a smoothed question with its online one.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping, Sequence

import numpy as np

from brain.model.arrays import BoolArray, FloatArray
from brain.model.person.personinterface import StepRecord
from brain.model.planner import PlanPolicy
from brain.model.world import WorldModel
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge.recording.trace import Trace
from protocol import ItemPlace, Mind, State, Truth
from protocol.carry import carry_locations
from protocol.geometry import GridCell
from toyroom.evaluation.heuristic import OUT, WINDOW, MotionHeuristic, goal_distances, heading

from .evidence import Evidence
from .judged import rank_of
from .judgments import Judgment
from .replay import RecordingModel

MOTION = "motion"
"""The model's name in :data:`toyroom.fitting.search.MODELS`."""
MOVES = 4
"""The first ``MOVES`` actions are the moves of :data:`brain.model.world.MOVE_STEPS`."""


def motion_evidence(
    trace: Trace, settings: ModelSettings, points: Sequence[Mapping[str, float]]
) -> list[Evidence]:
    """The log-likelihood of every person's decisions in ``trace`` under the motion heuristic
    at each of ``points`` (values of ``beta`` and ``epsilon``; the rest from ``settings``)."""
    tracker = MindTracker(trace.info.scene, settings)
    tracker.person_model = RecordingModel(tracker.person_model)
    for state, events in trace:
        tracker.observe(state, events)
    beta = np.array([float(p.get("beta", settings.beta)) for p in points])
    epsilon = np.array([float(p.get("epsilon", settings.epsilon)) for p in points])
    distances = goal_distances(trace.info.scene)
    policy = getattr(tracker.person_model.base, "policy", None)
    total, actions = np.zeros(len(points)), 0
    for person in tracker.people:
        chains = tracker.tracks[person].chains
        steps = chains[0].steps if chains else []
        ll, n = _person(
            tracker.model, policy if isinstance(policy, PlanPolicy) else None, distances, steps, beta, epsilon
        )
        total, actions = total + ll, actions + n
    return [Evidence(float(ll), actions) for ll in total]


def _person(
    model: WorldModel,
    policy: PlanPolicy | None,
    distances: Mapping[str, Mapping[GridCell, int]],
    steps: Sequence[StepRecord],
    beta: FloatArray,
    epsilon: FloatArray,
) -> tuple[FloatArray, int]:
    """``(P,)`` log-likelihoods of one person's decisions, and how many there were."""
    trail: deque[GridCell] = deque(maxlen=WINDOW + 1)
    goal: str | None = None
    ll, n = np.zeros(len(beta)), 0
    for record in steps:
        if record.decision is None:
            continue
        cell, held, action = record.decision
        here = (int(model.cells[cell, 0]), int(model.cells[cell, 1]))
        trail.append(here)
        goal = heading(distances, trail[0], here) or goal
        possible = _possible(model, policy, cell, held)
        utility = _utility(model, distances.get(goal, {}) if goal else {}, cell, possible.shape[0])
        ll += np.log(_choice(utility, possible, action, beta, epsilon))
        n += 1
    return ll, n


def _possible(model: WorldModel, policy: PlanPolicy | None, cell: int, held: int) -> BoolArray:
    """``(A,)`` the actions possible from ``(cell, held)``."""
    if policy is not None:
        q = policy.q[:, policy.state_slice(cell, held), :]
        return np.asarray(np.isfinite(q).any(axis=(0, 1)))
    A = MOVES + 1 + 2 * model.n_items + 2
    possible = np.ones(A, dtype=bool)
    possible[:MOVES] = model.neighbour[cell] >= 0
    return possible


def _utility(model: WorldModel, distance: Mapping[GridCell, int], cell: int, A: int) -> FloatArray:
    """``(A,)`` how much each action shortens the walk to the heading (0 without one)."""
    u = np.zeros(A)
    here = (int(model.cells[cell, 0]), int(model.cells[cell, 1]))
    if here not in distance:
        return u
    for a, n in enumerate(model.neighbour[cell]):
        there = (int(model.cells[n, 0]), int(model.cells[n, 1]))
        if n >= 0 and there in distance:
            u[a] = distance[here] - distance[there]
    return u


def _choice(
    utility: FloatArray, possible: BoolArray, action: int, beta: FloatArray, epsilon: FloatArray
) -> FloatArray:
    """``(P,)`` each point's probability of ``action``."""
    scaled = np.where(possible, beta[:, None] * utility[None], -np.inf)
    weights = np.exp(scaled - scaled.max(axis=1, keepdims=True))
    soft = weights[:, action] / weights.sum(axis=1)
    return (1.0 - epsilon) * soft + epsilon / len(utility)


def truth_of(state: State, places: Mapping[GridCell, str]) -> Truth:
    """Where each item truly is after ``state`` (a carried one at its carrier's location),
    from an omniscient state alone."""
    cells = {a.id: (a.cell.col, a.cell.row) for a in state.agents}
    items = []
    for item in state.items:
        if item.held_by is not None and item.held_by in cells:
            items.append(ItemPlace(item.id, places.get(cells[item.held_by], ""), item.held_by))
        elif item.location is not None:
            items.append(ItemPlace(item.id, item.location))
    return Truth(episode=state.episode, tick=state.tick, agents=(), items=tuple(items))


def motion_predictions(trace: Trace, judgments: Sequence[Judgment]) -> FloatArray:
    """``(N,)`` the motion observer's estimate of each judged quantity after its tick
    (``nan`` before the person was first seen)."""
    scene = trace.info.scene
    heuristic = MotionHeuristic(scene)
    places = carry_locations(scene)
    goals = [*(i.id for i in scene.items), OUT]
    locations = [loc.id for loc in scene.locations]
    ticks = np.array([state.tick for state, _ in trace])
    due: dict[int, list[int]] = {}
    for n, j in enumerate(judgments):
        at = int(np.searchsorted(ticks, j.tick, side="right")) - 1
        if at >= 0:
            due.setdefault(at, []).append(n)
    out = np.full(len(judgments), np.nan)
    for at, (state, _) in enumerate(trace):
        mind = heuristic.mind(state, truth_of(state, places))
        for n in due.get(at, []):
            out[n] = _estimate(mind, judgments[n], goals, locations)
    return out


def _estimate(mind: Mind, j: Judgment, goals: Sequence[str], locations: Sequence[str]) -> float:
    """The heuristic's value of one judged quantity (``nan``: the person is not in ``mind``)."""
    agent = next((a for a in mind.agents if a.agent == j.person), None)
    if agent is None:
        return float("nan")
    if j.quantity in ("desire", "utility"):  # one favourite's utility is P(most wanted)
        return next((p.p for p in agent.preference if p.id == goals[j.index[0]]), 0.0)
    if j.quantity == "rank":
        p = {q.id: q.p for q in agent.preference}
        return float(rank_of(np.array([p.get(g, 0.0) for g in goals]))[j.index[0]])
    if j.quantity == "belief":
        item = goals[j.index[0]]
        belief = next((b for b in agent.beliefs if b.item == item), None)
        where = locations[j.index[1]]
        return next((p.p for p in belief.locations if p.id == where), 0.0) if belief else float("nan")
    return 0.0
