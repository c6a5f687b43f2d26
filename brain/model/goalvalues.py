"""Every candidate desire's Q-values from one pass per goal: the exact planner's solver.

The planner's MDP is deterministic, every non-terminal action costs ``c = step_cost`` and a
non-terminal ``Stay`` is open wherever the episode has not ended, so a person either ends
the episode on some goal ``d`` (play with, use or, where that is the goal, take an item;
reach the outside), by the fewest
actions that get there, or stands forever (value ``V_stay = -c / (1 - gamma)``). Reaching
goal ``d`` after ``n`` non-terminal actions is worth ``V_stay + gamma**n (u_d - V_stay)``,
so with ``G[d, s] = gamma**n_d(s)`` (0 when ``d`` cannot be reached from ``s``):

    V_u(s) = V_stay + max(0, max_d G[d, s] (u_d - V_stay))

exactly, for every candidate ``u`` at once. ``G`` is found by one batched value iteration
over the ``D`` goals (as many sweeps as the longest shortest path, each value an exact power
of ``gamma``, so it stops on equality); each candidate's ``Q`` is then one gather:
``u_d`` for a terminal action of goal ``d``, ``-c + gamma V_u(s')`` for a continuing one.
The result is the fixed point value iteration converges to (within ``vi_tolerance`` of it);
it is the same for 3 candidates or 80 but for the final gather, which is what makes graded
desires about as cheap to plan as one favourite (``docs/model.md``, "Desires").

Shapes: ``S`` states, ``A`` actions, ``D = K + 1`` goals (the items, then ``out``), ``U``
candidates.
"""

from __future__ import annotations

import logging
import time

import numpy as np
import numpy.typing as npt

from .arrays import FloatArray, IntArray

log = logging.getLogger(__name__)

OUT_KIND, PLAY_KIND, USE_KIND, HAVE_KIND = 1, 2, 3, 4
"""``Transitions.terminal_kind`` of reaching the outside, Play, Use(k) and a Take(k) that is
the goal ("have it")."""

CHUNK_ELEMENTS = 4_000_000
"""The most ``Q`` entries built in one gather (``U_chunk * S * A``): bounds the temporaries,
and a progress line is logged between chunks."""

PROGRESS_SECONDS = 2.0
"""At most one progress line per this many seconds while candidates are solved."""


def terminal_goals(
    next_state: IntArray, kind: npt.NDArray[np.integer], held: IntArray, first_use: int, first_take: int
) -> IntArray:
    """``(S, A)`` the goal each terminal pair ends the episode on, ``-1`` for the rest.

    Args:
        next_state: ``(S, A)`` the next state of the planner's
            :class:`~brain.model.planner.Transitions`.
        kind: ``(S, A)`` the kind of each pair, of the same transitions.
        held: ``(S,)`` held code (0: nothing, else item index + 1).
        first_use: the action index of ``Use(0)``.
        first_take: the action index of ``Take(0)``.
    """
    S, A = next_state.shape
    n_items = A - first_use  # Use(0..K-1) are the last K actions
    goal = np.full((S, A), -1, dtype=np.int64)
    goal[kind == OUT_KIND] = n_items
    play = kind == PLAY_KIND
    goal[play] = np.broadcast_to(held[:, None] - 1, (S, A))[play]
    use = kind == USE_KIND
    goal[use] = np.broadcast_to(np.arange(A)[None, :] - first_use, (S, A))[use]
    have = kind == HAVE_KIND
    goal[have] = np.broadcast_to(np.arange(A)[None, :] - first_take, (S, A))[have]
    return goal


def goal_reach(next_state: IntArray, goal: IntArray, n_goals: int, discount: float) -> FloatArray:
    """``(D, S)`` ``gamma**n`` for the fewest non-terminal actions ``n`` from each state before
    a terminal action of each goal (0: unreachable), by value iteration batched over goals."""
    S, A = next_state.shape
    reach = np.zeros((n_goals, S))
    terminal = goal >= 0
    states, actions = np.nonzero(terminal)
    reach[goal[states, actions], states] = 1.0  # the goal's terminal action from here: n = 0
    moves = [(np.flatnonzero(next_state[:, a] >= 0), next_state[next_state[:, a] >= 0, a]) for a in range(A)]
    fixed = reach.copy()
    for _ in range(S + 1):  # at most S sweeps: a shortest path visits each state once
        new = fixed.copy()
        for source, target in moves:  # one gather per action, over all goals and states
            new[:, source] = np.maximum(new[:, source], discount * reach[:, target])
        if np.array_equal(new, reach):
            break
        reach = new
    return reach


def candidate_values(reach: FloatArray, u: FloatArray, stay: float) -> FloatArray:
    """``(U, S)`` ``V_u(s) = V_stay + max(0, max_d G[d, s] (u_d - V_stay))`` for ``(U, D)``
    candidates ``u`` and ``(D, S)`` reach ``G``."""
    gain = np.zeros((len(u), reach.shape[1]))
    for d in range(reach.shape[0]):  # D passes over (U, S)
        np.maximum(gain, (u[:, d] - stay)[:, None] * reach[d][None, :], out=gain)
    return stay + gain


def solve_goals(
    next_state: IntArray,
    kind: npt.NDArray[np.integer],
    held: IntArray,
    first_use: int,
    first_take: int,
    u: FloatArray,
    step_cost: float,
    discount: float,
) -> FloatArray:
    """``(U, S, A)`` the optimal Q-values of every candidate (``-inf``: infeasible), as value
    iteration finds them, from one pass over the goals; progress is logged at INFO."""
    started = time.perf_counter()
    S, A = next_state.shape
    stay = -step_cost / (1.0 - discount)
    goal = terminal_goals(next_state, kind, held, first_use, first_take)
    reach = goal_reach(next_state, goal, u.shape[1], discount)
    log.info(
        "planning %d candidate desires over %d states: goal distances in %.2f s",
        len(u),
        S,
        time.perf_counter() - started,
    )
    flat = np.flatnonzero(next_state >= 0)
    target = next_state.reshape(-1)[flat]
    tflat = np.flatnonzero(goal >= 0)
    tgoal = goal.reshape(-1)[tflat]
    q = np.full((len(u), S * A), -np.inf)
    chunk = max(1, CHUNK_ELEMENTS // max(1, S * A))
    said = time.perf_counter()
    for lo in range(0, len(u), chunk):
        part = u[lo : lo + chunk]
        values = candidate_values(reach, part, stay)
        q[lo : lo + chunk, flat] = -step_cost + discount * values[:, target]
        q[lo : lo + chunk, tflat] = part[:, tgoal]
        if time.perf_counter() - said > PROGRESS_SECONDS and lo + chunk < len(u):
            log.info(
                "planned %d of %d candidate desires in %.1f s",
                lo + chunk,
                len(u),
                time.perf_counter() - started,
            )
            said = time.perf_counter()
    log.info("planned %d of %d candidate desires in %.2f s", len(u), len(u), time.perf_counter() - started)
    return q.reshape(len(u), S, A)
