"""What a robot's task is worth (pure): the expected steps it saves the people it concerns,
over their inferred minds and the robot's own knowledge of where items rest, less its costs.

Unit: a *step* is one grid cell of walking (people and the robot walk at the same speed, so
a step is a fixed number of engine ticks). Each candidate is scored for one person and one
item ``k`` resting at ``t``:

- that person's expected steps to reach the item with no help, ``T_none``: they go to the
  place their belief puts it (location ``l`` with the robot's estimate ``B[l]`` of their belief)
  and, when it is not there, search on to ``t`` (``search_factor`` times the distance);
- an **inform** reaches them after the robot's walk into earshot (``r`` steps): from then on
  they go straight to ``t``; it saves ``max(T_via(l) - (r + d(p, t)), 0)`` for each wrong
  ``l``, and costs ``interruption_cost`` plus ``tell_item_cost``;
- a **tell** names several items at once (:func:`tell_worth`): what each inform would save,
  summed, for one interruption and ``tell_item_cost`` per item named;
- a **put-back** to ``b`` lands after the robot's walk to the item and on to ``b``: it saves the
  owner's way to the item and on to where they use it, with it at ``t`` against at ``b``, when
  it lands before they reach ``b``; a person sees an item on their way (:func:`sighted_steps`),
  so one moved off their way, or away from where they use it, costs them (harm); it misleads
  everyone else who wants the item and believes it at ``t`` (their search from ``t``);
- an **ask** ("what are you looking for?", :func:`ask_worth`): the value of what the answer
  would teach, the robot's best help for the person after each answer weighted by its odds,
  against its best help now, less one interruption;
- a **look** at an unseen place (the robot is not sure where the item rests): its worth is
  the inform it makes possible, against informing now of the likeliest place (a wrong word
  sends the person to an empty place).

Every figure is weighted by P(the person wants the item). ``robot_step_cost`` charges each
step the robot walks. No I/O; numpy on the world model's distance tables.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import shortest_path

from ..model.arrays import FloatArray
from ..model.estimates import Estimate
from ..model.world import WorldModel
from ..settings import RobotSettings

MANIPULATION_STEPS = 2.0
"""Steps' worth of a pick or a place (the engine's few ticks of handling)."""

_CELL_DISTANCES: dict[int, tuple[WorldModel, FloatArray]] = {}


def cell_distances(model: WorldModel) -> FloatArray:
    """``(C, C)`` walking steps between every two walkable cells (the model's neighbours, so
    walls count; ``inf`` where no path), computed once per world model."""
    cached = _CELL_DISTANCES.get(id(model))
    if cached is not None and cached[0] is model:
        return cached[1]
    n = len(model.cells)
    rows, cols = np.nonzero(model.neighbour >= 0)
    graph = coo_matrix((np.ones(len(rows)), (rows, model.neighbour[rows, cols])), shape=(n, n)).tocsr()
    table = shortest_path(graph, unweighted=True, directed=False)
    _CELL_DISTANCES[id(model)] = (model, table)
    return table


def location_cells(model: WorldModel) -> np.ndarray:
    """``(L,)`` the cell index of each location (the cell its distance row is zero at)."""
    return np.argmin(model.distance, axis=1)


@dataclass(frozen=True)
class Worth:
    """A candidate's expected worth, in steps: ``saved`` for the people it helps, ``harm`` to
    others it would mislead, ``cost`` of the robot's walk and interruptions; ``net`` is what
    decides (positive: worth doing)."""

    saved: float
    harm: float
    cost: float

    @property
    def net(self) -> float:
        return self.saved - self.harm - self.cost


def wants(est: Estimate, k: int, lasting: bool = True) -> float:
    """P(the person wants item ``k``) as help is weighed: with ``lasting``
    (``RobotSettings.lasting_want``), given that they want some item, so that going out (an
    errand) reads as passing and leaves the want for an item where it was; else the preference
    posterior as it is."""
    if not lasting:
        return float(est.preference[k])
    items = est.preference[: len(est.preference) - 1]
    return float(items[k] / max(float(items.sum()), 1e-12))


def lasting_preference(preference: FloatArray, before: FloatArray | None) -> FloatArray:
    """``(D,)`` the preference as help is weighed with ``RobotSettings.lasting_want``: going out
    reads as an errand, after which the person wants what they wanted before they set out, so
    P(out) goes back to the items in the shares of ``before`` (``(D - 1,)``, what they wanted
    over the items the last time they were not heading out; ``None``: in proportion to the
    items' own posterior)."""
    items, out = preference[:-1], float(preference[-1])
    share = before if before is not None else items / max(float(items.sum()), 1e-12)
    return np.append(items + out * share, 0.0)


def _via(model: WorldModel, person_cell: int, t: int, search: float) -> FloatArray:
    """``(L,)`` steps for a person at ``person_cell`` to reach an item at location ``t`` when
    they first go to location ``l``: straight there when ``l`` is ``t``, else on to ``t``."""
    here = model.distance[:, person_cell].astype(float)
    between = model.distance[:, location_cells(model)[t]].astype(float)
    return here + search * between


def _found(model: WorldModel, person_cell: int, t: int, search: float) -> FloatArray:
    """``(L,)`` :func:`_via`, sooner where they see ``t`` on the way to ``l`` (a cell of a
    shortest way there, ``l``'s own included, from which ``t`` is in view): then straight to it
    (:func:`sighted_steps`). Informs are weighed by :func:`_via` (a person may overlook an item
    on their way, and a word is cheap); moving an item is weighed by this (moving it off their
    way is sure to cost them)."""
    return np.minimum(_via(model, person_cell, t, search), sighted_steps(model, person_cell, t))


def sighted_steps(model: WorldModel, person_cell: int, t: int) -> FloatArray:
    """``(L,)`` steps for a person at ``person_cell`` walking to location ``l`` to reach an item
    resting at ``t`` that they see on the way: the fewest, over the cells of a shortest way
    from their cell to ``l`` from which ``t`` is in view (``WorldModel.sees``), of the steps to
    that cell and from it to ``t``; ``inf`` where ``t`` is in view from none of them. People
    take in what they see as they walk (sim2d's, and the model's percepts), so an item moved
    onto a person's way is found there, and moving it off their way costs them the search."""
    walk = cell_distances(model)[person_cell]  # (C,)
    to_l = model.distance.astype(float)  # (L, C)
    on_way = np.isclose(walk[None, :] + to_l, to_l[:, person_cell][:, None])  # (L, C)
    seen = on_way & model.sees[:, t][None, :]
    onward = walk + model.distance[t].astype(float)  # (C,): to the cell, then to t
    return np.where(seen, onward[None, :], np.inf).min(axis=1)


def play_steps(model: WorldModel) -> FloatArray:
    """``(L,)`` steps from each location to the nearest play spot (where people use what they
    fetched: the goal is reached there), zeros when the scene has none."""
    if not model.play_at.any():
        return np.zeros(model.n_locations)
    return model.distance[:, model.play_at].min(axis=1).astype(float)


def owner_steps(model: WorldModel, est: Estimate, k: int, person_cell: int, t: int, search: float) -> float:
    """Expected steps for the person to have item ``k`` resting at ``t`` where they use it:
    over the robot's estimate of where they believe it, to the item (:func:`_found`) and on to
    the nearest play spot (:func:`play_steps`)."""
    belief = est.beliefs[k, : model.n_locations]
    found = float(belief @ np.nan_to_num(_found(model, person_cell, t, search), posinf=1e6))
    return found / max(float(belief.sum()), 1e-12) + float(play_steps(model)[t])


def steps_unhelped(
    model: WorldModel, est: Estimate, k: int, person_cell: int, t: int, search: float
) -> float:
    """Expected steps for the person to reach item ``k`` at location ``t`` with no help, over
    the robot's estimate of where they believe it."""
    belief = est.beliefs[k, : model.n_locations]
    return float(belief @ _via(model, person_cell, t, search) / max(belief.sum(), 1e-12))


def steps_told(model: WorldModel, person_cell: int, t: int, told: float, search: float) -> FloatArray:
    """``(L,)`` steps for a person at ``person_cell`` to reach an item at ``t`` when, heading
    first for location ``l``, they are told after ``told`` steps where it is: until told they
    walk towards ``l`` (their distance to ``t`` moving in proportion from ``d(p, t)`` to
    ``d(l, t)``), or search on from ``l`` (closing on ``t`` at ``1 / search`` per step); then they
    go straight to ``t``. Never more than :func:`_via` (they would have found it anyway)."""
    to_l = model.distance[:, person_cell].astype(float)
    to_t = float(model.distance[t, person_cell])
    between = model.distance[:, location_cells(model)[t]].astype(float)
    share = np.clip(told / np.maximum(to_l, 1.0), 0.0, 1.0)
    walking = told + (1.0 - share) * to_t + share * between
    searching = told + np.maximum(between - (told - to_l) / search, 0.0)
    steps = np.where(told <= to_l, walking, searching)
    return np.minimum(steps, _via(model, person_cell, t, search))


def inform_worth(
    model: WorldModel,
    est: Estimate,
    k: int,
    person_cell: int,
    t: int,
    robot_steps: float,
    settings: RobotSettings,
) -> Worth:
    """Telling the person that item ``k`` is at ``t``, heard after ``robot_steps`` of the
    robot's walk into earshot: the steps it saves them over where they may believe it
    (:func:`steps_told` against :func:`_via`), times P(they want it)."""
    belief = est.beliefs[k, : model.n_locations] / max(est.beliefs[k, : model.n_locations].sum(), 1e-12)
    search = settings.search_factor
    via = _via(model, person_cell, t, search)
    saved_if = np.maximum(via - steps_told(model, person_cell, t, robot_steps, search), 0.0)
    saved_if[t] = 0.0
    saved = wants(est, k, settings.lasting_want) * float(belief @ np.nan_to_num(saved_if, posinf=0.0))
    cost = settings.interruption_cost + settings.tell_item_cost + settings.robot_step_cost * robot_steps
    return Worth(saved, 0.0, cost)


def tell_worth(singles: Sequence[Worth], settings: RobotSettings) -> Worth:
    """One utterance telling the person where several items are, each of whose single
    :func:`inform_worth` is in ``singles`` (every one heard after the same walk): the steps
    saved add up, and so does ``tell_item_cost`` per item; the interruption and the walk are
    paid once. Every item's figure is already weighted by P(they want it), so a person heading
    for a wrong place is told even while the robot cannot say which item they are after."""
    if not singles:
        return Worth(0.0, 0.0, 0.0)
    shared = singles[0].cost - settings.tell_item_cost  # the interruption and the walk
    return Worth(sum(w.saved for w in singles), 0.0, shared + settings.tell_item_cost * len(singles))


def put_back_worth(
    model: WorldModel,
    estimates: Mapping[str, Estimate],
    cells: Mapping[str, int],
    owner: str,
    k: int,
    t: int,
    b: int,
    robot_steps: float,
    settings: RobotSettings,
) -> Worth:
    """Carrying item ``k`` from ``t`` to ``b`` for ``owner`` (``robot_steps``: the robot's walk
    to the item, then on to ``b``): what it saves the owner, when it lands before they reach
    ``b``, is their expected steps to have the item where they use it (:func:`owner_steps`) with
    it at ``t`` less with it at ``b``; where that is negative (the item lies on their way, or
    nearer where they use it) it is harm. Everyone else who wants it and believes it at ``t``
    would search from there."""
    search = settings.search_factor
    between = float(model.distance[b, location_cells(model)[t]])
    est, cell = estimates.get(owner), cells.get(owner)
    saved = owner_harm = 0.0
    if est is not None and cell is not None:
        gain = owner_steps(model, est, k, cell, t, search) - owner_steps(model, est, k, cell, b, search)
        gain *= wants(est, k, settings.lasting_want)
        if not put_back_late(model, robot_steps, cell, b, settings.put_back_slack):
            saved = max(gain, 0.0)
        owner_harm = max(-gain, 0.0)
    harm = owner_harm
    for person, other in estimates.items():
        if person != owner:
            there = other.beliefs[k, t] / max(other.beliefs[k, : model.n_locations].sum(), 1e-12)
            harm += wants(other, k, settings.lasting_want) * float(there) * search * between
    return Worth(saved, harm, settings.robot_step_cost * robot_steps)


def put_back_walk(model: WorldModel, robot_cell: int, t: int, b: int) -> float:
    """Steps of the robot's walk to put an item back from location ``t`` to ``b``: to the item,
    then on to ``b`` (each stop taken from next to the spot)."""
    steps = cell_distances(model)
    at, to = location_cells(model)[t], location_cells(model)[b]
    return float(steps[robot_cell, at]) + float(steps[at, to]) - 1.0


def put_back_late(model: WorldModel, robot_steps: float, person_cell: int, b: int, slack: float) -> bool:
    """Whether a put-back to ``b`` that takes the robot ``robot_steps`` (and its two handlings)
    lands after the person on ``person_cell`` could reach ``b`` (by more than ``slack`` steps):
    they would find ``b`` empty and search on, and the item would no longer be where they
    searched."""
    return robot_steps + 2 * MANIPULATION_STEPS > float(model.distance[b, person_cell]) + slack


def put_back_lengthens(model: WorldModel, cell: int, t: int, b: int, search: float) -> bool:
    """Whether moving an item from ``t`` to ``b`` lengthens the way to it of a person on
    ``cell`` who believes it at ``b``. Left at ``t``, they walk towards ``b`` and on to ``t``
    (sooner where they see ``t`` on the way, :func:`sighted_steps`), then to where they use it
    (:func:`play_steps`); moved to ``b``, they walk to ``b`` and from there to where they use
    it. An item on their way, or nearer where they use it, is best left where it is; a tie is
    put back (the person's belief is then true again)."""
    play = play_steps(model)
    left = float(_found(model, cell, t, search)[b]) + play[t]
    moved = float(model.distance[b, cell]) + play[b]
    return moved > left


def look_or_guess(
    model: WorldModel,
    est: Estimate,
    k: int,
    person_cell: int,
    where: FloatArray,
    robot_to_person: float,
    robot_to_look: float,
    settings: RobotSettings,
) -> tuple[Worth, Worth]:
    """``(look, guess)`` for telling the person where item ``k`` is when the robot knows only
    ``where`` ``(L,)``, P(the item rests at each location): **guess** tells them the likeliest
    place now (right with its probability; wrong, it sends them to an empty place and on);
    **look** first walks ``robot_to_look`` steps to see the likeliest place, then tells them
    where the item is (wherever it is: a place seen empty rules it out)."""
    guess_at = int(np.argmax(where))
    places = [t for t in range(model.n_locations) if where[t] > 0]
    right = inform_worth(model, est, k, person_cell, guess_at, robot_to_person, settings)
    sent = float(model.distance[guess_at, person_cell])  # a wrong word sends them there ...
    wrong = 0.0
    for t in places:
        if t != guess_at:  # ... and on from there, against going straight to t
            on = settings.search_factor * float(model.distance[t, location_cells(model)[guess_at]])
            lost = max(sent + on - float(model.distance[t, person_cell]), 0.0)
            wrong += float(where[t]) * wants(est, k, settings.lasting_want) * lost
    guess = Worth(float(where[guess_at]) * right.saved, wrong, right.cost)
    walk = robot_to_look + robot_to_person
    saved = sum(
        float(where[t]) * inform_worth(model, est, k, person_cell, t, walk, settings).saved for t in places
    )
    look = Worth(saved, 0.0, settings.interruption_cost + settings.robot_step_cost * walk)
    return look, guess


def ask_worth(odds: FloatArray, after: FloatArray, now: float, settings: RobotSettings) -> Worth:
    """Asking a person what they are looking for, as the value of information: ``odds`` ``(A,)``
    P(each answer), ``after`` ``(A,)`` the net worth (steps) of the robot's best help for them
    once it has heard that answer (0 when nothing is worth doing), ``now`` that of its best
    help without asking. Saves the expected gain of acting on the answer; costs one
    interruption (the walk to the person is charged in ``after``: the help that follows the
    answer walks there too)."""
    gain = float(odds @ np.maximum(after, 0.0)) - max(now, 0.0)
    return Worth(gain, 0.0, settings.interruption_cost)
