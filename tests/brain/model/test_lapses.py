"""Lapses of attention (``ModelSettings.miss``): a person who walks back to where an item
used to be, after it was moved in plain view, probably overlooked the move."""

from __future__ import annotations

from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker, Observer
from tests.scenes import corridor_scene, corridor_state


def false_belief_after_walking_to_the_old_spot(miss: float, observer: Observer = Observer.BTOM) -> float:
    """The ball rests at B, in the person's view; it is moved to A, in view too; the person
    then walks right, towards B (away from A and from the door). The robot sees everything."""
    tracker = MindTracker(corridor_scene(), ModelSettings(miss=miss), observer)
    tracker.observe(corridor_state(0, 5, robot=3, ball_at="B"), [])
    tracker.observe(corridor_state(1, 5, robot=3, ball_at="A"), [])
    for tick, col in enumerate((6, 7), start=2):
        tracker.observe(corridor_state(tick, col, robot=3, ball_at="A"), [])
    estimate = tracker.online("p")
    assert estimate is not None
    return float(estimate.false_belief[0])


def test_walking_to_where_it_was_reveals_the_overlooked_move() -> None:
    with_lapses = false_belief_after_walking_to_the_old_spot(0.2)
    assert with_lapses > 0.5, f"expected a likely false belief with lapses allowed, got {with_lapses:.3f}"
    without = false_belief_after_walking_to_the_old_spot(0.0)
    assert without < 0.1, f"without lapses the person saw the move, got {without:.3f}"


def test_percepts_alone_cannot_tell_a_lapse() -> None:
    """``perceptonly`` has no action likelihood: its rows keep their prior weights."""
    alone = false_belief_after_walking_to_the_old_spot(0.2, Observer.PERCEPTONLY)
    assert 0.05 < alone < 0.5, f"expected about the prior chance of a lapse, got {alone:.3f}"


def test_log_evidence_is_the_mixtures() -> None:
    """A lapse makes the walk likelier, so the evidence of the same moves is higher with lapses."""
    scores = {}
    for miss in (0.0, 0.2):
        tracker = MindTracker(corridor_scene(), ModelSettings(miss=miss))
        tracker.observe(corridor_state(0, 5, robot=3, ball_at="B"), [])
        tracker.observe(corridor_state(1, 5, robot=3, ball_at="A"), [])
        for tick, col in enumerate((6, 7), start=2):
            tracker.observe(corridor_state(tick, col, robot=3, ball_at="A"), [])
        scores[miss] = tracker.log_evidence("p")
    assert scores[0.2] > scores[0.0], scores


def test_a_rumour_splits_off_a_told_row_with_its_chance() -> None:
    """Outside, the person has no idea where the ball is (half A, half B); someone in their
    region believes it is at B, and told them since the last step with chance 0.25: a told
    row (certain of B) of weight 0.25 beside the untold one."""
    import numpy as np

    from brain.model.belief import NOT_IN_VIEW, Percept
    from brain.model.person.lapses import LapseModel
    from brain.model.person.personinterface import StepRecord
    from brain.model.person.personmodel import base_person_model

    settings = ModelSettings(hearsay_per_s=1.0)
    scene = corridor_scene()
    model = LapseModel(base_person_model(scene, settings), miss=0.0)
    world = model.model
    outside = world.cell_index[(0, 0)]
    b = world.locations.index("B")
    filt = model.new_filter()
    truth = (2 * b,)
    filt.step(
        StepRecord(tick=0, percept=Percept(outside, (NOT_IN_VIEW,)), truth=truth, likelihood=None, switch=0.0)
    )
    assert len(filt.rows) == 1
    rumour = ((0, 2 * b, 0.25),)
    filt.step(
        StepRecord(
            tick=1,
            percept=Percept(outside, (NOT_IN_VIEW,)),
            truth=truth,
            likelihood=None,
            switch=0.0,
            rumours=rumour,
        )
    )
    weights = np.exp([r.log_weight for r in filt.rows])
    assert sorted(np.round(weights, 6)) == [0.25, 0.75], weights
    believed = filt.estimate(truth).beliefs[0, b]
    assert abs(believed - (0.25 + 0.75 * 0.5)) < 0.01, believed


def test_forgetting_drifts_each_item_toward_uniform() -> None:
    import numpy as np

    from brain.model.graded import drift

    # one item, two locations: values 0 (A), 1 (A, held), 2 (B), 3 (B, held)
    certain_b = np.array([[0.0, 0.0, 1.0, 0.0]])
    assert np.allclose(drift(certain_b, 1, 4, 0.2), [[0.1, 0.0, 0.9, 0.0]])
    carried = np.array([[0.0, 1.0, 0.0, 0.0]])
    assert np.allclose(drift(carried, 1, 4, 0.2), carried), "a carried item stays carried"


def test_a_forgetful_person_outside_grows_unsure() -> None:
    """The person sees the ball at B, then, outside, takes a step whose record says 0.3 of
    each belief drifted: the robot expects them to give B 0.7 + 0.3 / 2."""
    from brain.model.belief import NOT_IN_VIEW, Percept
    from brain.model.person.personinterface import StepRecord
    from brain.model.person.personmodel import base_person_model

    scene = corridor_scene()
    model = base_person_model(scene, ModelSettings())
    world = model.model
    b = world.locations.index("B")
    truth = (2 * b,)
    filt = model.new_filter()
    filt.step(
        StepRecord(
            tick=0,
            percept=Percept(world.cell_index[(5, 0)], (2 * b,)),
            truth=truth,
            likelihood=None,
            switch=0.0,
        )
    )
    outside = Percept(world.cell_index[(0, 0)], (NOT_IN_VIEW,))
    filt.step(StepRecord(tick=1, percept=outside, truth=truth, likelihood=None, switch=0.0, forget=0.3))
    believed = float(filt.estimate(truth).beliefs[0, b])
    assert abs(believed - 0.85) < 0.01, believed


def test_rumours_come_from_the_others_in_the_region() -> None:
    """A second person in the room believes the ball at B; by sim2d's rule (issue 53) they
    tell the first only what the two place differently, the teller surer: nothing while both
    believe B, the ball at B (with the chance a telling came, half of it from them, over the
    one item) once the first believes A."""
    import math
    from types import SimpleNamespace

    import msgspec
    import numpy as np

    from brain.tracking.hearsay import rumours, tellable
    from protocol import AgentKind, AgentSpec, Cell

    scene = corridor_scene()
    scene = msgspec.structs.replace(
        scene, agents=(*scene.agents, AgentSpec(id="q", kind=AgentKind.PERSON, home=Cell(6, 0)))
    )

    def state(tick: int, col: int) -> object:
        base = corridor_state(tick, col, robot=3, ball_at="B")
        q = msgspec.structs.replace(base.agents[0], id="q", cell=Cell(6, 0), holding=None)
        return msgspec.structs.replace(base, agents=(*base.agents, q))

    tracker = MindTracker(scene, ModelSettings(hearsay_per_s=0.5))
    tracker.observe(state(0, 4), [])
    assert tracker._rumours("p", state(1, 5), 2.0) == (), "both believe B: nothing to tell"
    b = tracker.model.locations.index("B")
    believes = {"p": np.array([[0.8, 0.2]]), "q": np.array([[0.02, 0.98]])}
    estimates = {who: SimpleNamespace(beliefs=b) for who, b in believes.items()}
    told = rumours(state(1, 5), "p", estimates.get, 0.5, 2.0)  # type: ignore[arg-type]
    assert told == ((0, 2 * b, (1 - math.exp(-0.5 * 2.0)) / 2),), told
    assert tellable(np.array([[0.6, 0.4]]), np.array([[0.3, 0.7]])) == [], "a teller less sure tells nothing"
    assert tellable(np.array([[0.4, 0.6]]), None) == [(0, 2 * b)], "an unknown listener is told what is sure"


def test_a_forgetful_person_standing_still_still_steps() -> None:
    """With ``forget_per_s`` a person who stands still gets a percept step every decision time,
    so their beliefs drift while they play or wait (not only when they next move)."""
    counts = {}
    for rate in (0.0, 0.1):
        tracker = MindTracker(corridor_scene(), ModelSettings(forget_per_s=rate))
        for tick in range(12):  # 0.7 s a tick: 7.7 s standing at the same cell
            tracker.observe(corridor_state(tick, 5, robot=3, ball_at="B"), [])
        counts[rate] = len(tracker.tracks["p"].steps)
    assert counts[0.1] >= counts[0.0] + 5, counts
