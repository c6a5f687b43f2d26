"""The planner: one MDP per preference over (cell, held item, world), solved by value
iteration, and the Boltzmann action likelihood the inference uses.

States ``s = (c * (K + 1) + h) * W + w`` for cell ``c``, held item ``h`` (0: nothing, else
item ``h - 1``) and world ``w``; ``S = C (K + 1) W``. Actions ``Up, Down, Left, Right, Stay,
Take(0..K-1), Drop, Play, Use(0..K-1)``; ``A = 2 K + 7``; ``Take(k)`` of a fixed item
(``ItemSpec.portable`` false) is infeasible everywhere. Use(k) ends the episode with
``k``'s utility on a ``use`` location where ``k`` rests; a Drop into a world that a
location's ``capacity`` rules out is impossible. Preferences ``d`` are the items, then ``out``;
``D = K + 1``. Everything is vectorised over states: one value-iteration sweep is a gather
and a max over an ``(S, A)`` array.
"""

from __future__ import annotations

import dataclasses
import enum
import logging
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property, lru_cache
from typing import Protocol

import msgspec
import numpy as np
import numpy.typing as npt

from protocol import Scene

from ..settings import ModelSettings
from .arrays import FloatArray, IntArray
from .desires import utilities
from .goalvalues import solve_goals
from .world import WorldModel, build_world_model, value_of

log = logging.getLogger(__name__)

INFEASIBLE = -1
TERMINAL = -2
HAVE = 4
"""``Transitions.terminal_kind`` of a Take that is the goal itself (``WorldModel.have_goals``)."""


class Move(enum.IntEnum):
    """The movement actions; ``Take(k)`` is ``TAKE + k``, then ``Drop``, ``Play`` and ``Use(k)``."""

    UP = 0
    DOWN = 1
    LEFT = 2
    RIGHT = 3
    STAY = 4


TAKE = 5


def n_actions(n_items: int) -> int:
    """``A = 2 K + 7``: the number of actions with ``n_items`` items."""
    return TAKE + 2 * n_items + 2


def drop_action(n_items: int) -> int:
    """``Drop``'s action index with ``n_items`` items."""
    return TAKE + n_items


def play_action(n_items: int) -> int:
    """``Play``'s action index with ``n_items`` items."""
    return TAKE + n_items + 1


def use_action(n_items: int, item: int) -> int:
    """``Use(k)``: use item ``k``, resting at the person's ``use`` location, in place."""
    return TAKE + n_items + 2 + item


@dataclass(frozen=True)
class Transitions:
    """The MDP's deterministic dynamics, shared by every preference.

    Attributes:
        next_state: ``(S, A)`` successor, or ``INFEASIBLE`` / ``TERMINAL``.
        terminal_kind: ``(S, A)`` 1 for reaching the outside, 2 for Play, 3 for Use, 4
            (:data:`HAVE`) for a Take that is the goal ("have it"), else 0.
        held: ``(S,)`` held item code ``h`` of each state.
    """

    next_state: IntArray
    terminal_kind: npt.NDArray[np.int8]
    held: IntArray


def fill_moves(
    model: WorldModel,
    cells: IntArray,
    nxt: IntArray,
    kind: npt.NDArray[np.int8],
    successor: Callable[[IntArray], IntArray],
) -> None:
    """Fill the Up/Down/Left/Right columns of ``nxt`` and ``kind`` (``(S, A)``) for states
    on ``cells`` (``(S,)``): a wall is infeasible, stepping outside is terminal, else the
    state ``successor(new cells)``."""
    for a in range(4):
        c2 = model.neighbour[cells, a]
        ok = c2 >= 0
        safe = np.where(ok, c2, 0)
        nxt[:, a] = np.where(ok, successor(safe), INFEASIBLE)
        out = ok & model.outside[safe]
        nxt[out, a] = TERMINAL
        kind[out, a] = 1


def transitions(model: WorldModel) -> Transitions:
    """Build the successor table of every (state, action)."""
    C, K, W = model.n_cells, model.n_items, model.n_worlds
    H = K + 1
    A = n_actions(K)
    c, h, w = (a.reshape(-1) for a in np.indices((C, H, W)))
    S = C * H * W

    def index(cells: IntArray, held: IntArray, worlds: IntArray) -> IntArray:
        return (cells * H + held) * W + worlds

    def carry(cells: IntArray, worlds: IntArray) -> IntArray:
        """Worlds after the own carried item follows the carrier to ``cells``."""
        out = worlds.copy()
        for k in range(K):
            mask = h == k + 1
            out[mask] = model.with_value(worlds[mask], k, value_of(model.nearest[cells[mask]], held=True))
        return out

    nxt = np.full((S, A), INFEASIBLE, dtype=np.int64)
    kind = np.zeros((S, A), dtype=np.int8)
    fill_moves(model, c, nxt, kind, lambda cells: index(cells, h, carry(cells, w)))
    nxt[:, Move.STAY] = np.where(model.outside[c], TERMINAL, index(c, h, w))
    kind[model.outside[c], Move.STAY] = 1
    spot = model.spot_at[c]
    on_spot = spot >= 0
    for k in [int(i) for i in np.flatnonzero(model.portable)]:  # a fixed item is never taken
        ok = (h == 0) & on_spot & (model.worlds[w, k] == value_of(spot))
        if model.have_goals:  # taking it is the goal: "have it"
            nxt[ok, TAKE + k] = TERMINAL
            kind[ok, TAKE + k] = HAVE
            continue
        nxt[ok, TAKE + k] = index(
            c[ok], np.full(ok.sum(), k + 1), model.with_value(w[ok], k, value_of(spot[ok], held=True))
        )
    allowed = model.allowed
    for k in range(K):
        ok = (h == k + 1) & on_spot
        after = model.with_value(w[ok], k, value_of(spot[ok]))
        ok[ok] = allowed[after]  # a drop on a full spot is impossible
        nxt[ok, drop_action(K)] = index(
            c[ok], np.zeros(ok.sum(), dtype=np.int64), model.with_value(w[ok], k, value_of(spot[ok]))
        )
    play = (h > 0) & model.play_at[c]
    nxt[play, play_action(K)] = TERMINAL
    kind[play, play_action(K)] = 2
    for k in range(K):
        use = model.use_at[c] & on_spot & (model.worlds[w, k] == value_of(spot))
        nxt[use, use_action(K, k)] = TERMINAL
        kind[use, use_action(K, k)] = 3
    return Transitions(next_state=nxt, terminal_kind=kind, held=h)


def rewards(
    model: WorldModel, trans: Transitions, settings: ModelSettings, utility: FloatArray
) -> FloatArray:
    """``(S, A)`` reward of each action for a person with the ``(D,)`` goal utilities
    ``utility`` (playing with each item, then reaching the outside;
    :mod:`brain.model.desires`)."""
    K = model.n_items
    play_value = np.concatenate([[0.0], utility[:K]])  # by held code h (0: nothing)
    reward = np.full(trans.next_state.shape, -settings.step_cost)
    reward[trans.terminal_kind == 1] = utility[K]
    play = trans.terminal_kind == 2
    reward[play] = np.broadcast_to(play_value[trans.held][:, None], reward.shape)[play]
    for k in range(K):
        column = reward[:, use_action(K, k)]
        column[trans.terminal_kind[:, use_action(K, k)] == 3] = utility[k]
        column = reward[:, TAKE + k]
        column[trans.terminal_kind[:, TAKE + k] == HAVE] = utility[k]
    return reward


def value_iteration(
    trans: Transitions, reward: FloatArray, discount: float, tolerance: float, max_sweeps: int = 10_000
) -> FloatArray:
    """``(S, A)`` optimal Q-values (hard max); infeasible actions are ``-inf``.

    A sweep only touches the (state, action) pairs that continue: their Q is refreshed in
    place by a gather of the successors' values; the rest (terminal rewards, ``-inf``) is fixed.
    """
    nxt = trans.next_state
    feasible = nxt != INFEASIBLE
    flat = np.flatnonzero(nxt >= 0)  # continuing pairs, as flat indices into (S, A)
    target = nxt.reshape(-1)[flat]
    step_reward = reward.reshape(-1)[flat]
    q = np.where(feasible, reward, -np.inf)
    q_flat = q.reshape(-1)
    value = np.zeros(len(nxt))
    for _ in range(max_sweeps):
        q_flat[flat] = step_reward + discount * value[target]
        new = q.max(axis=1)
        converged = np.max(np.abs(new - value)) <= tolerance
        value = new
        if converged:
            break
    q_flat[flat] = step_reward + discount * value[target]
    return q


def boltzmann(q: FloatArray, beta: float, epsilon: float) -> FloatArray:
    """``(S, A)`` action likelihoods: softmax of ``beta * Q`` over feasible actions, mixed
    with a floor ``epsilon`` spread over all actions."""
    finite = np.isfinite(q)
    scaled = np.where(finite, beta * q, -np.inf)
    top = scaled.max(axis=1, keepdims=True)
    weights = np.where(finite, np.exp(scaled - top), 0.0)
    soft = weights / weights.sum(axis=1, keepdims=True)
    return (1.0 - epsilon) * soft + epsilon / q.shape[1]


@dataclass(frozen=True)
class PlanPolicy:
    """The planner's output for one map.

    Attributes:
        model: the world model.
        utilities: ``(U, D)`` the candidate desires, one MDP each (:mod:`brain.model.desires`).
        q: ``(U, S, A)`` Q-values.
        beta, epsilon: the choice rule's (:func:`boltzmann`).
    """

    model: WorldModel
    utilities: FloatArray
    q: FloatArray
    beta: float
    epsilon: float
    _blocks: dict[tuple[int, int], FloatArray] = field(default_factory=dict, compare=False, repr=False)

    @cached_property
    def likelihood(self) -> FloatArray:
        """``(U, S, A)`` Boltzmann action likelihoods (built on first use: the graded models
        read one ``(cell, held)`` block per decision, :meth:`action_likelihood`)."""
        return np.stack([boltzmann(q, self.beta, self.epsilon) for q in self.q])

    def state_slice(self, cell: int, held: int) -> slice:
        """States of ``(cell, held)`` over all worlds (a contiguous block of ``W``)."""
        W = self.model.n_worlds
        base = (cell * (self.model.n_items + 1) + held) * W
        return slice(base, base + W)

    def action_likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        """``(W, U)`` likelihood of ``action`` from ``(cell, held)`` for every world and desire
        (the block's Boltzmann rows, the same to the bit as the whole table's: each state's
        row is its own softmax)."""
        block = self._blocks.get((cell, held))
        if block is None:
            rows = self.state_slice(cell, held)
            block = np.stack([boltzmann(q[rows], self.beta, self.epsilon) for q in self.q])  # (U, W, A)
            self._blocks[(cell, held)] = block
        return block[:, :, action].T


def solve(model: WorldModel, settings: ModelSettings) -> tuple[FloatArray, FloatArray]:
    """``(U, D)`` the candidate desires and ``(U, S, A)`` their Q-values (no cache): from one
    pass over the goals (:mod:`brain.model.goalvalues`), or by value iteration per candidate
    when some goal is worth less than standing forever (the closed form assumes none is)."""
    trans = transitions(model)
    u = utilities(settings, model.n_items, leaves=bool(model.outside.any()))
    if u.min() >= -settings.step_cost / (1.0 - settings.discount):
        qs = solve_goals(
            trans.next_state,
            trans.terminal_kind,
            trans.held,
            use_action(model.n_items, 0),
            TAKE,
            u,
            settings.step_cost,
            settings.discount,
        )
        return u, qs
    log.info("planning %d candidate desires by value iteration (a goal is worth less than standing)", len(u))
    qs = np.stack(
        [
            value_iteration(
                trans, rewards(model, trans, settings, row), settings.discount, settings.vi_tolerance
            )
            for row in u
        ]
    )
    return u, qs


def plan(model: WorldModel, settings: ModelSettings) -> PlanPolicy:
    """Solve the MDP of every candidate desire (no cache; see :func:`cached_policy`)."""
    u, qs = solve(model, settings)
    return _policy(model, u, qs, settings)


def _policy(model: WorldModel, u: FloatArray, qs: FloatArray, settings: ModelSettings) -> PlanPolicy:
    return PlanPolicy(model=model, utilities=u, q=qs, beta=settings.beta, epsilon=settings.epsilon)


PLANNING = (
    "desire_model",
    "desire_levels",
    "preferred_utility",
    "other_utility",
    "leave_utility_item",
    "leave_utility_out",
    "step_cost",
    "discount",
    "vi_tolerance",
)
"""The settings value iteration reads: policies that agree on them share Q-values."""


class ValueStore(Protocol):
    """Solved Q-values kept beyond this process (:class:`brain.outputs.valuestore.ValueDirectory`),
    by the scene without its agents and the :data:`PLANNING` settings."""

    def load(self, scene: Scene, key: tuple[object, ...]) -> tuple[FloatArray, FloatArray] | None: ...

    def save(self, scene: Scene, key: tuple[object, ...], u: FloatArray, qs: FloatArray) -> None: ...


_store: list[ValueStore] = []


def use_store(store: ValueStore | None) -> None:
    """Look solved Q-values up in ``store`` before solving, and keep them there after (the
    brains of one evaluation then solve each map once); ``None``: this process's cache only."""
    _store[:] = [] if store is None else [store]
    _cached_values.cache_clear()
    cached_policy.cache_clear()


@lru_cache(maxsize=16)
def _cached_values(scene: Scene, key: tuple[object, ...]) -> tuple[WorldModel, FloatArray, FloatArray]:
    model = build_world_model(scene)
    settings: ModelSettings = dataclasses.replace(ModelSettings(), **dict(zip(PLANNING, key, strict=True)))  # type: ignore[arg-type]
    store = _store[0] if _store else None
    stored = store.load(scene, key) if store is not None else None
    if stored is not None:
        u, qs = stored
        expected = (model.n_cells * (model.n_items + 1) * model.n_worlds, n_actions(model.n_items))
        if u.shape[1:] == (model.n_items + 1,) and qs.shape[0] == len(u) and qs.shape[1:] == expected:
            return model, u, qs
        log.warning("stored Q-values of shape %s do not fit this scene %s: solving again", qs.shape, expected)
    u, qs = solve(model, settings)
    if store is not None:
        store.save(scene, key, u, qs)
    return model, u, qs


@lru_cache(maxsize=8)
def cached_policy(scene: Scene, settings: ModelSettings) -> PlanPolicy:
    """The policy of a scene, computed once per (scene, settings) in this process; value
    iteration once per (scene without its agents, :data:`PLANNING` settings), so a fit over
    ``beta`` or over belief models solves each map once (and each day of a household alike)."""
    key = tuple(getattr(settings, name) for name in PLANNING)
    model, u, qs = _cached_values(msgspec.structs.replace(scene, agents=(), household=None), key)
    return _policy(model, u, qs, settings)
