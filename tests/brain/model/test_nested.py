"""Nested beliefs (:mod:`brain.model.nested`) on the second-order Sally-Anne room: A's model
of B follows what B sees while A sees B, and stays put while A does not."""

from __future__ import annotations

import numpy as np
import pytest

from brain.model.belief import percept, true_values
from brain.model.nested import NestedBeliefs, item_transitions, smoothed_nested
from brain.model.world import build_world_model
from sim2d.engine import Engine


@pytest.fixture(scope="module")
def model():
    return build_world_model(Engine("sally-anne-window").scene())


def at(model, col: int, row: int) -> int:
    return model.cell_index[(col, row)]


def where(model, location: str) -> np.ndarray:
    """``(K, L)``: certain the marble rests at ``location``."""
    out = np.zeros((model.n_items, model.n_locations))
    out[0, model.locations.index(location)] = 1.0
    return out


def step(model, nested: NestedBeliefs, time: float, cells: dict[str, int], marble: str) -> None:
    truth = true_values(model, {"marble": marble}, {})
    percepts = {p: percept(model, c, truth, None) for p, c in cells.items()}
    beliefs = {p: where(model, marble) for p in cells}  # what each sees (enough for these steps)
    nested.observe(time, cells, percepts, beliefs.get)


def test_the_transition_of_a_seen_item_is_certain_and_columns_sum_to_one(model) -> None:
    truth = true_values(model, {"marble": "box"}, {})
    t = item_transitions(model, percept(model, at(model, 2, 3), truth, None), r=8.0, delta=1e-4)
    assert np.allclose(t.sum(axis=1), 1.0), "columns of T[k] must sum to one"
    box = 2 * model.locations.index("box")
    assert t[0, box, :].min() > 0.99, (
        f"seeing the marble in the box: P(box) after any belief, got {t[0, box]}"
    )


def test_anne_thinks_sally_thinks_basket_until_she_sees_sally_back(model) -> None:
    nested = NestedBeliefs(model, ["sally", "anne"], r=8.0, delta=1e-4)
    room_s, room_a, outside = at(model, 1, 3), at(model, 3, 3), at(model, 2, 0)
    step(model, nested, 0.0, {"sally": room_s, "anne": room_a}, "basket")
    step(model, nested, 0.1, {"sally": room_s, "anne": room_a}, "basket")
    assert nested.sees(room_a, room_s) and not nested.sees(room_a, outside), "the room does not see outside"
    assert nested.sees(outside, room_a), "outside sees the room through the window"
    step(model, nested, 5.0, {"sally": outside, "anne": room_a}, "box")  # Anne moved it; Sally watched
    basket, box = model.locations.index("basket"), model.locations.index("box")
    anne_on_sally = nested.locations("anne", "sally")[0]
    sally_on_anne = nested.locations("sally", "anne")[0]
    assert anne_on_sally[basket] > 0.99, f"Anne did not see Sally look: expected basket, got {anne_on_sally}"
    assert sally_on_anne[box] > 0.99, f"Sally saw Anne see the box: expected box, got {sally_on_anne}"
    step(model, nested, 9.0, {"sally": room_s, "anne": room_a}, "box")
    anne_on_sally = nested.locations("anne", "sally")[0]
    assert anne_on_sally[box] > 0.99, f"Anne sees Sally back in the room: expected box, got {anne_on_sally}"


def test_a_peek_rate_makes_an_unseen_other_drift_toward_what_one_believes(model) -> None:
    nested = NestedBeliefs(model, ["sally", "anne"], r=8.0, delta=1e-4, peek=0.1)
    room_s, room_a, outside = at(model, 1, 3), at(model, 3, 3), at(model, 2, 0)
    step(model, nested, 0.0, {"sally": room_s, "anne": room_a}, "basket")
    step(model, nested, 10.0, {"sally": outside, "anne": room_a}, "box")
    p = nested.locations("anne", "sally")[0]
    expected = 1.0 - np.exp(-0.1 * 10.0)
    assert p[model.locations.index("box")] == pytest.approx(expected), (
        f"expected {expected:.3f} on box, got {p}"
    )


def test_the_backward_pass_leans_on_smoothed_first_order_beliefs(model) -> None:
    """:func:`smoothed_nested` runs the filter again over the same percepts: with the online
    beliefs it gives the online values exactly; with what the robot learned later of A's own
    belief (A knew of the box all along), A's model of an unseen B drifts toward that instead."""
    nested = NestedBeliefs(model, ["sally", "anne"], r=8.0, delta=1e-4, peek=0.1)
    room_s, room_a, outside = at(model, 1, 3), at(model, 3, 3), at(model, 2, 0)
    online = []
    for time, cells, marble in (
        (0.0, {"sally": room_s, "anne": room_a}, "basket"),
        (10.0, {"sally": outside, "anne": room_a}, "box"),
        (20.0, {"sally": outside, "anne": room_a}, "box"),
    ):
        step(model, nested, time, cells, marble)
        online.append(nested.all_locations().copy())
    beliefs = [where(model, m) for m in ("basket", "box", "box")]
    again = smoothed_nested(nested, lambda n, person: beliefs[n])
    assert all(np.array_equal(a, b) for a, b in zip(again, online, strict=True)), (
        "the same inputs: the same values"
    )
    # what the robot learned later: Anne never knew of the box (online it read her as knowing)
    unaware = smoothed_nested(
        nested, lambda n, person: where(model, "basket") if person == "anne" else beliefs[n]
    )
    box = model.locations.index("box")
    pair = nested.pairs.index(("anne", "sally"))
    assert unaware[0][pair, 0, box] == online[0][pair, 0, box], "the start is B's (Sally's) own belief"
    assert unaware[2][pair, 0, box] < online[2][pair, 0, box] - 0.05, (
        f"Anne's model of the unseen Sally drifts to Anne's smoothed belief: {unaware[2][pair, 0]}, "
        f"online {online[2][pair, 0]}"
    )
