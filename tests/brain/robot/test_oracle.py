"""The ``oracle`` policy's minds, read off the engine's truth by hand (:mod:`brain.robot.oracle`),
its wire (:mod:`brain.oracle`: a tick's truth awaited, an engine without truth refused), and
``tom``'s tree acting on them for a person with a false belief."""

from __future__ import annotations

import threading
import time
from typing import Any

import msgspec
import numpy as np
import pytest
from scenes import tiny_scene, tiny_state

from brain.model.world import build_world_model
from brain.oracle import OracleError, TruthFeed, oracle_minds
from brain.robot.oracle import oracle_estimates
from brain.robot.situation import Inform, Situation, inform_tasks, put_back_tasks
from brain.settings import RobotSettings
from protocol import Capability, ItemBelief, ItemPlace, ItemShape, ItemSpec, Prob, Pursuit, TrueMind, Truth

SCENE = msgspec.structs.replace(
    tiny_scene(),
    items=(ItemSpec(id="ball", shape=ItemShape.BALL), ItemSpec(id="skate", shape=ItemShape.BOARD)),
)
MODEL = build_world_model(SCENE)
A, B = MODEL.locations.index("A"), MODEL.locations.index("B")
BALL, SKATE = MODEL.items.index("ball"), MODEL.items.index("skate")


def mind(preference: str = "ball", pursuit: Pursuit | None = None) -> TrueMind:
    """``p`` is all but sure the ball is at B (it is at A: a false belief), and torn between A
    and B for the skate (it is at B: ignorance, not a false belief)."""
    return TrueMind(
        agent="p",
        beliefs=(
            ItemBelief(item="ball", locations=(Prob("A", 0.05), Prob("B", 0.95))),
            ItemBelief(item="skate", locations=(Prob("A", 0.5), Prob("B", 0.5))),
        ),
        preference=preference,
        pursuit=pursuit,
    )


def truth(*minds: TrueMind, tick: int = 3) -> Truth:
    places = (ItemPlace(item="ball", location="A"), ItemPlace(item="skate", location="B"))
    return Truth(episode=1, tick=tick, agents=minds, items=places)


def test_true_beliefs_preference_false_beliefs_and_want_by_hand() -> None:
    est = oracle_estimates(truth(mind()), MODEL)["p"]
    expected = np.zeros((2, MODEL.n_locations))
    expected[BALL, [A, B]] = 0.05, 0.95
    expected[SKATE, [A, B]] = 0.5, 0.5
    assert np.allclose(est.beliefs, expected), est.beliefs
    assert est.preference.tolist() == [1.0, 0.0, 0.0], "one-hot on the ball, then out"
    # 0.05 < 0.1 x 0.95: false; 0.5 against 0.5: ignorance
    assert est.false_belief[BALL] == 1.0 and est.false_belief[SKATE] == 0.0, est.false_belief
    assert est.intention == (BALL, B, 0.95), "no pursuit: where they most believe what they want is"


def test_the_pursuit_is_the_want_and_out_is_no_item() -> None:
    after_skate = oracle_estimates(truth(mind(pursuit=Pursuit(item="skate", location="A"))), MODEL)["p"]
    assert after_skate.intention == (SKATE, A, 1.0), after_skate.intention
    leaving = oracle_estimates(truth(mind(preference="out")), MODEL)["p"]
    assert leaving.preference.tolist() == [0.0, 0.0, 1.0] and leaving.intention == (None, None, 1.0)
    wandering = oracle_estimates(truth(mind(pursuit=Pursuit())), MODEL)["p"]
    assert wandering.intention == (None, None, 1.0), "a pursuit of no item: after nothing"
    assert wandering.preference.tolist() == [1.0, 0.0, 0.0], "the want stays the true preference"


def test_toms_finders_act_on_the_true_false_belief() -> None:
    """On the oracle's estimates, ``tom``'s finders tell ``p`` where the ball is as they head
    for B; and, ``p`` having left it at B, put it back there from A unless that lengthens
    their way: in this room A is in view from every cell (and a play spot), so it stays."""
    state = tiny_state(3, (1, 0), ball_at="A")
    snap = Situation(
        scene=SCENE,
        model=MODEL,
        state=state,
        estimates=oracle_estimates(truth(mind()), MODEL),
        owners={"ball": "p"},
        moved_from={"p": MODEL.cell_index[(0, 0)]},  # came from A's cell: heading for B
    )
    settings = RobotSettings(put_back_harm=1.0)
    assert list(inform_tasks(snap, settings)) == [Inform(person="p", item="ball", location="A")]
    assert list(put_back_tasks(snap, settings)) == [], "the ball at A lies in p's view: moving it costs p"


class Wire:
    """What :class:`TruthFeed` uses of a bridge: the truth key and a subscription."""

    def __init__(self) -> None:
        self.keys = type("Keys", (), {"truth": "toyroom/w/engine/truth"})()
        self.deliver: Any = None

    def subscribe(self, key: str, callback: Any, expected: Any = None) -> Any:
        self.deliver = callback
        return type("Sub", (), {"close": lambda self: None})()


def test_the_feed_waits_for_the_ticks_own_truth_and_fails_when_none_comes() -> None:
    wire = Wire()
    feed = TruthFeed(wire, wait=5.0)  # type: ignore[arg-type]
    wire.deliver(truth(mind(), tick=2), None)

    def later() -> None:
        time.sleep(0.2)
        wire.deliver(truth(mind(preference="skate"), tick=3), None)

    threading.Thread(target=later).start()
    got = feed.at(1, 3)
    assert (got.tick, got.agents[0].preference) == (3, "skate"), "the truth of tick 3, not the older one"
    feed.wait = 0.05
    with pytest.raises(OracleError, match="no truth of episode 1 tick 4"):
        feed.at(1, 4)


def test_an_engine_without_truth_is_refused_at_its_handshake() -> None:
    from support import golden_examples

    info = golden_examples()["engine_info"]
    feed = TruthFeed(Wire(), wait=1.0)  # type: ignore[arg-type]
    tracker = type("Tracker", (), {"model": MODEL})()
    bare = msgspec.structs.replace(info, capabilities=(Capability.LOCKSTEP, Capability.ROBOT))
    with pytest.raises(OracleError, match="publishes none .no 'truth' capability"):
        oracle_minds(feed, bare, tracker)  # type: ignore[arg-type]
    truthful = msgspec.structs.replace(info, capabilities=(Capability.LOCKSTEP, Capability.TRUTH))
    assert oracle_minds(feed, truthful, tracker) is not None  # type: ignore[arg-type]
    assert oracle_minds(None, bare, tracker) is None, "no feed (another policy): the inferred minds"  # type: ignore[arg-type]
