"""Waiting is a decision, and evidence in proportion to its length: a person who stands on
their cell while a decision is due has chosen the planner's Stay once for every decision time
beyond what a move takes (``brain/tracking/waits.py``), each with its likelihood.

Most paths are on the tiny corridor of ``tests/scenes.py`` in the grid engine's timing (one
move per 0.7 s tick): the person comes in from the outside to B, may stand there, and goes
back. sim2d's people are checked on its own runs."""

from __future__ import annotations

import msgspec
import numpy as np
import pytest

from brain.model.planner import Move
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from brain.tracking.waits import stays_due
from protocol import Activity, Observer
from sim2d.engine import Engine
from tests.scenes import tiny_scene, tiny_state

IN = [(4, 0), (3, 0), (2, 0)]
"""Ticks 0-2: from the outside to B (arriving at tick 2)."""


def paused(ticks: int) -> list[tuple[int, int]]:
    """In to B, ``ticks`` ticks standing there (0.7 s each), then back to the door."""
    return IN + [(2, 0)] * ticks + [(3, 0)]


def run(path: list[tuple[int, int]], seconds: float = 0.7, **settings: float | str) -> MindTracker:
    """The tiny corridor, one state every ``seconds`` (0.7: the grid engine's tick)."""
    tracker = MindTracker(tiny_scene(), ModelSettings(**settings), Observer.BTOM)  # type: ignore[arg-type]
    for tick, cell in enumerate(path):
        state = tiny_state(tick, cell, "A")
        tracker.observe(msgspec.structs.replace(state, time=round(tick * seconds, 9)), ())
    return tracker


def decisions(tracker: MindTracker, person: str = "p") -> list[tuple[int, int | None]]:
    return [(s.tick, s.decision[2] if s.decision else None) for s in tracker.tracks[person].steps]


def stays(tracker: MindTracker, person: str = "p") -> list[int]:
    """The ticks of the Stays read (one per Stay: a tick may have several)."""
    return [tick for tick, action in decisions(tracker, person) if action == Move.STAY]


def odds_out(tracker: MindTracker) -> float:
    """The posterior odds of ``out`` against the ball."""
    est = tracker.online("p")
    assert est is not None
    return float(est.preference[1] / est.preference[0])


def stay_ratio(tracker: MindTracker, cell: tuple[int, int]) -> float:
    """The likelihood ratio of Stay on ``cell`` (empty-handed, in the true world): out : ball."""
    model = tracker.model
    truth = model.world_index(np.array(tracker.truth))
    stay = tracker.person_model.policy.action_likelihood(model.cell_index[cell], 0, Move.STAY)[truth]
    return float(stay[1] / stay[0])


@pytest.mark.parametrize(
    ("seconds", "expected"),
    [(0.3, 0), (0.8, 0), (1.0, 0), (1.05, 1), (1.4, 1), (1.7, 1), (1.75, 2), (2.1, 2), (4.2, 5), (4.9, 6)],
)
def test_a_stay_for_every_decision_time_beyond_a_move_and_half_of_one(seconds: float, expected: int) -> None:
    """The rule itself (decision time 0.7 s): a move takes one decision time, half of one more
    is tolerance, and every further one is a Stay. ``wait_decisions`` is where the first is."""
    got = stays_due(seconds, ModelSettings())
    assert got == expected, f"{seconds} s standing: expected {expected} Stays, got {got}"
    assert stays_due(seconds * 100, ModelSettings(wait_decisions=0.0)) == 0, "wait_decisions = 0 read a wait"
    assert stays_due(2.1, ModelSettings(wait_decisions=3.0)) == 1
    assert stays_due(2.7, ModelSettings(wait_decisions=3.0)) == 1
    assert stays_due(2.8, ModelSettings(wait_decisions=3.0)) == 2
    with pytest.raises(ValueError, match="wait_decisions"):
        ModelSettings(wait_decisions=1.0)  # every move would come with a Stay


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_a_one_step_stop_on_the_grid_is_one_stay_and_evidence(belief_model: str) -> None:
    """Arriving at B at tick 2, standing at tick 3, leaving at tick 4: one Stay on B, read at
    tick 4 before the move. With preference switches off (hazard 0), it multiplies the
    posterior odds of ``out`` against the ball by exactly Stay's likelihood ratio on B."""
    stopped = run(paused(1), belief_model=belief_model, hazard=0.0)
    steps = decisions(stopped)
    assert stays(stopped) == [4], (
        f"expected one Stay at tick 4, got Stays at {stays(stopped)} (steps {steps})"
    )
    stay_step = next(s for s in stopped.tracks["p"].steps if s.decision and s.decision[2] == Move.STAY)
    assert stay_step.decision is not None and stay_step.decision[0] == stopped.model.cell_index[(2, 0)]
    assert steps[-1] == (4, Move.RIGHT), f"expected the move back last, at tick 4; steps {steps}"
    walked = run(paused(0), belief_model=belief_model, hazard=0.0)
    assert stays(walked) == [], f"walking in and straight back read Stays at {stays(walked)}"
    expected = stay_ratio(stopped, (2, 0))
    assert abs(expected - 1.0) > 0.2, f"Stay on B should tell ball from out apart; ratio {expected:.3f}"
    got = odds_out(stopped) / odds_out(walked)
    assert got == pytest.approx(expected, rel=0.02), (
        f"expected the one-step stop to multiply the odds of out by {expected:.3f}, got {got:.3f}"
    )


@pytest.mark.parametrize("belief_model", ["point", "graded"])
@pytest.mark.parametrize("ticks", [2, 3, 6])
def test_a_longer_pause_is_as_many_stays_as_decision_times(belief_model: str, ticks: int) -> None:
    """Standing ``n`` ticks is ``n`` Stays: read while standing once each is certain (from 1.05 s
    on), the last with the move back; ``n`` times the one-step stop's evidence (hazard 0)."""
    tracker = run(paused(ticks), belief_model=belief_model, hazard=0.0)
    expected = list(range(4, 4 + ticks))
    assert stays(tracker) == expected, (
        f"{ticks} ticks on B: expected Stays at ticks {expected}, got {stays(tracker)} ({decisions(tracker)})"
    )
    walked = run(paused(0), belief_model=belief_model, hazard=0.0)
    ratio = stay_ratio(tracker, (2, 0)) ** ticks
    got = odds_out(tracker) / odds_out(walked)
    assert got == pytest.approx(ratio, rel=0.02 * ticks), (
        f"expected {ticks} Stays to multiply the odds of out by {ratio:.4g}, got {got:.4g}"
    )
    ignored = run(paused(ticks), belief_model=belief_model, wait_decisions=0.0)
    assert stays(ignored) == [], f"wait_decisions = 0 read Stays at {stays(ignored)}"


def test_walking_at_sim2d_pace_is_no_wait() -> None:
    """Ticks of 0.1 s, a change of cell every 0.3-0.8 s as sim2d's people walk (0.3-0.4 s
    setting off, mostly 0.7 s) and up to 1.0 s: no Stay. Standing a little longer then
    (1.1 s between changes of cell) is one."""
    rng = np.random.default_rng(3)
    route = [(4, 0), (3, 0), (2, 0), (1, 0), (0, 0), (1, 0), (2, 0), (1, 0), (0, 0), (1, 0), (2, 0)]
    gaps = rng.choice([3, 4, 6, 7, 7, 7, 8, 10], size=len(route) - 1)  # in 0.1 s ticks
    path = [route[0]] * 5
    for cell, gap in zip(route[1:], gaps, strict=True):
        path += [path[-1]] * (int(gap) - 1) + [cell]
    tracker = run(path, seconds=0.1)
    assert stays(tracker) == [], f"walking with gaps {gaps.tolist()} (x 0.1 s) read Stays at {stays(tracker)}"
    moves = [tick for tick, action in decisions(tracker) if action is not None]
    assert len(moves) == len(route) - 1, f"expected {len(route) - 1} moves, read {decisions(tracker)}"
    longer = run(path + [path[-1]] * 10 + [(3, 0)], seconds=0.1)
    assert stays(longer) == [len(path) + 10], f"1.1 s then a move: expected one Stay, got {stays(longer)}"


@pytest.mark.parametrize("scenario", ["paper-1", "food-trucks"])
def test_sim2d_walkers_make_no_waits(scenario: str) -> None:
    """sim2d's scripted people walk, play, eat and wait outside: none of it is a wait."""
    engine = Engine(scenario, robot="observe")
    tracker = MindTracker(engine.scene(), ModelSettings(belief_model="point"))
    tracker.observe(engine.state(), ())
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
    for person in tracker.people:
        assert stays(tracker, person) == [], f"{scenario}: {person}'s Stays at {stays(tracker, person)}"


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_checking_and_staying_is_a_stay_per_decision_time(belief_model: str) -> None:
    """Paper Fig. 5 (``paper-robot``, the robot only watching): A1 comes back, checks S1 (the
    ball, not the skate) and stays there. Every decision time she stands is a Stay, none
    while she walks, and they make the skate (held by A2: waiting for it) likelier, not less."""
    out, end = {}, 0.0
    for wait in (1.5, 0.0):
        engine = Engine("paper-robot", robot="observe")
        tracker = MindTracker(engine.scene(), ModelSettings(belief_model=belief_model, wait_decisions=wait))
        tracker.observe(engine.state(), ())
        while not engine.done:
            result = engine.step()
            tracker.observe(result.state, result.events)
            end = result.state.time
        out[wait] = tracker
    tracker = out[1.5]
    checked = next(t for (t, who), name in tracker.labels.items() if who == "A1" and name == "6")
    steps = tracker.tracks["A1"].steps
    last = max(s.tick for s in steps if s.decision is not None and s.decision[2] != Move.STAY)
    standing = end - (tracker.tracks["A1"].last_decision or 0.0)
    expected = stays_due(standing, tracker.settings)
    read = stays(tracker, "A1")
    assert expected >= 5, (
        f"A1 should stand in S1 a while after checking it (tick {checked}): {standing:.1f} s"
    )
    assert len(read) == expected and min(read) > last, (
        f"A1 checked S1 at tick {checked}, moved last at tick {last} and stood {standing:.1f} s: "
        f"expected {expected} Stays after tick {last}, got {len(read)} at {read}"
    )
    skate = tracker.model.items.index("skate")
    waited, ignored = (float(out[w].online("A1").preference[skate]) for w in (1.5, 0.0))  # type: ignore[union-attr]
    assert waited > 0.9 and waited >= ignored, (
        f"P(A1 wants the skate) after waiting in S1: {waited:.3f} (ignoring waits {ignored:.3f}); "
        "expected > 0.9 and no less"
    )


def test_standing_outside_before_acting_or_after_playing_is_not_a_wait() -> None:
    outside = run([(4, 0)] * 8)
    assert stays(outside) == [], f"standing outside counted: {decisions(outside)}"
    before = run([(2, 0)] * 8 + [(3, 0)])  # first seen on B, standing: no decision seen yet
    assert stays(before) == [], f"standing before any decision counted: {decisions(before)}"
    tracker = MindTracker(tiny_scene(), ModelSettings(), Observer.BTOM)
    for tick, cell in enumerate([(4, 0), (3, 0), (2, 0), (1, 0), (0, 0)]):
        tracker.observe(tiny_state(tick, cell, "A"), ())
    for tick in range(5, 12):  # holding the ball on A and playing with it
        state = tiny_state(tick, (0, 0), None, holding=True)
        person = msgspec.structs.replace(state.agents[0], activity=Activity.PLAYING)
        tracker.observe(msgspec.structs.replace(state, agents=(person,)), ())
    assert stays(tracker) == [], f"playing counted as waiting: {decisions(tracker)}"
