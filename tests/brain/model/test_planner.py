"""The vectorised planner against a brute-force value iteration written with plain loops."""

from __future__ import annotations

import math

import numpy as np
from scenes import tiny_scene

from brain.model.planner import Move, plan
from brain.model.world import MOVE_STEPS, build_world_model
from brain.settings import ModelSettings


def brute_force_q(settings: ModelSettings) -> tuple[list[tuple[int, int, int]], dict]:
    """Q[d][(cell, held, world)][action] by looping over every state (the model's rules
    restated independently: moves along walkable cells, Take at a spot where the item rests,
    Drop at a spot, Play at a play spot, reaching the outside ends the episode)."""
    scene = tiny_scene()
    cells = sorted({(c.col, c.row) for r in scene.regions for c in r.cells} | {(3, 0)})
    outside = {(4, 0)}
    spots = {(0, 0): 0, (2, 0): 1}
    play = {(0, 0)}
    nearest = {(0, 0): 0, (1, 0): 0, (2, 0): 1, (3, 0): 1, (4, 0): 1}
    values = range(4)  # 2 * location + held
    states = [(c, h, w) for c in range(len(cells)) for h in (0, 1) for w in values]
    actions = 5 + 1 + 2 + 1  # moves, stay, take(ball), drop, play, use(ball): no use place here

    def step(state: tuple[int, int, int], a: int) -> tuple[str, tuple[int, int, int] | None]:
        c, h, w = state
        cell = cells[c]
        if a < 4:
            nxt = (cell[0] + MOVE_STEPS[a][0], cell[1] + MOVE_STEPS[a][1])
            if nxt not in cells:
                return "infeasible", None
            w2 = 2 * nearest[nxt] + 1 if h else w
            return ("leave" if nxt in outside else "go"), (cells.index(nxt), h, w2)
        if a == Move.STAY:
            return ("leave" if cell in outside else "go"), (c, h, w)
        if a == 5:  # take the ball
            if h == 0 and cell in spots and w == 2 * spots[cell]:
                return "go", (c, 1, 2 * spots[cell] + 1)
            return "infeasible", None
        if a == 6:  # drop
            if h == 1 and cell in spots:
                return "go", (c, 0, 2 * spots[cell])
            return "infeasible", None
        if a == 7 and h == 1 and cell in play:
            return "play", None
        return "infeasible", None

    q_all = {}
    for d in (0, 1):  # the ball, or out
        leave = settings.leave_utility_out if d == 1 else settings.leave_utility_item
        fun = settings.other_utility if d == 1 else settings.preferred_utility
        value = dict.fromkeys(states, 0.0)
        for _ in range(2000):
            q = {}
            for s in states:
                row = []
                for a in range(actions):
                    kind, nxt = step(s, a)
                    if kind == "infeasible":
                        row.append(-math.inf)
                    elif kind == "leave":
                        row.append(leave)
                    elif kind == "play":
                        row.append(fun)
                    else:
                        row.append(-settings.step_cost + settings.discount * value[nxt])
                q[s] = row
            new = {s: max(q[s]) for s in states}
            done = max(abs(new[s] - value[s]) for s in states) < 1e-12
            value = new
            if done:
                break
        q_all[d] = q
    return cells, q_all


def test_planner_matches_brute_force_value_iteration() -> None:
    settings = ModelSettings()
    policy = plan(build_world_model(tiny_scene()), settings)
    cells, expected = brute_force_q(settings)
    model = policy.model
    assert [tuple(c) for c in model.cells] == cells
    for d in (0, 1):
        for (c, h, w), row in expected[d].items():
            got = policy.q[d, (c * 2 + h) * 4 + w]
            assert np.allclose(got, row, atol=1e-9, equal_nan=False), (
                f"d={d} state {(cells[c], h, w)}: {got} vs {row}"
            )


def test_boltzmann_likelihoods_are_distributions_with_a_floor() -> None:
    settings = ModelSettings()
    policy = plan(build_world_model(tiny_scene()), settings)
    assert np.allclose(policy.likelihood.sum(axis=2), 1.0)
    assert policy.likelihood.min() >= settings.epsilon / policy.likelihood.shape[2] - 1e-15


def test_a_decisions_likelihood_block_is_the_whole_tables_to_the_bit() -> None:
    """The graded models read one ``(cell, held)`` block per decision, built on demand; the
    whole table is built only when asked for, and agrees with every block exactly."""
    policy = plan(build_world_model(tiny_scene()), ModelSettings())
    model = policy.model
    blocks = {
        (cell, held, action): policy.action_likelihood(cell, held, action)
        for cell in range(model.n_cells)
        for held in range(model.n_items + 1)
        for action in range(policy.q.shape[2])
    }
    for (cell, held, action), block in blocks.items():
        whole = policy.likelihood[:, policy.state_slice(cell, held), action].T
        assert np.array_equal(block, whole), f"block {(cell, held, action)} differs from the whole table's"


def test_solved_values_are_shared_through_a_folder(tmp_path, monkeypatch, caplog) -> None:
    """A second process (here: an emptied cache) reads what the first solved instead of
    solving again; an unreadable file is solved again, with a warning naming it."""
    import numpy as np

    from brain.model import planner
    from brain.outputs.valuestore import ValueDirectory
    from brain.settings import ModelSettings
    from sim2d.engine import Engine

    solved = []
    real_solve = planner.solve
    monkeypatch.setattr(planner, "solve", lambda *a: solved.append(1) or real_solve(*a))
    scene = Engine("paper-1").scene()
    try:
        planner.use_store(ValueDirectory(tmp_path))
        first = planner.cached_policy(scene, ModelSettings())
        assert len(solved) == 1 and len(list(tmp_path.glob("*.npz"))) == 1, (solved, list(tmp_path.iterdir()))
        planner.use_store(ValueDirectory(tmp_path))  # as a new process: nothing cached in memory
        second = planner.cached_policy(scene, ModelSettings(beta=3.0))  # beta is not planning
        assert len(solved) == 1, "the stored values should have been read, not solved again"
        assert np.array_equal(first.q, second.q)
        (stored,) = tmp_path.glob("*.npz")
        stored.write_bytes(b"not a zip")
        planner.use_store(ValueDirectory(tmp_path))
        with caplog.at_level("WARNING"):
            third = planner.cached_policy(scene, ModelSettings())
        assert len(solved) == 2 and np.array_equal(first.q, third.q)
        assert "cannot read the stored Q-values" in caplog.text and stored.name in caplog.text, caplog.text
    finally:
        planner.use_store(None)
