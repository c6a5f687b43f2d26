"""Days in sequence on a hand-built household (:func:`tests.scenes.household_scene`): what the
brain learned of a person on one day is where its estimate of them starts the next."""

from __future__ import annotations

from brain.memory import Snapshot, snapshot_of
from brain.outputs.results import mind_message
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Event, EventKind, State
from tests.scenes import household_scene, household_state


def preference(tracker: MindTracker, goal: str) -> float:
    estimate = tracker.online("p")
    assert estimate is not None, "p was seen"
    goals = [*tracker.model.items, "out"]
    return float(estimate.preference[goals.index(goal)])


def false_belief(tracker: MindTracker, item: str) -> float:
    estimate = tracker.online("p")
    assert estimate is not None, "p was seen"
    return float(estimate.false_belief[tracker.model.items.index(item)])


def day_end(tracker: MindTracker, state: State, day: int = 1) -> Snapshot:
    """The snapshot a brain saves at the end of ``day``."""
    mind = mind_message(tracker, state)
    return snapshot_of("home", day, mind, tracker.robot_items(), final=True)


def a_day_with_the_ball(settings: ModelSettings) -> tuple[MindTracker, State]:
    """Day 1: p, in R1 beside the ball (A), walks to it, takes it and plays with it there;
    the skate rests at B."""
    tracker = MindTracker(household_scene(), settings)
    for tick, col in enumerate((2, 1, 0)):
        tracker.observe(household_state(tick, (col, 0)), [])
    take = Event(episode=1, tick=3, time=2.1, kind=EventKind.TAKE, actor="p", item="ball", location="A")
    tracker.observe(household_state(3, (0, 0), holding="ball"), [take])
    play = Event(episode=1, tick=4, time=2.8, kind=EventKind.PLAY, actor="p", item="ball", location="A")
    last = household_state(4, (0, 0), holding="ball")
    tracker.observe(last, [play])
    return tracker, last


def test_a_favourite_learned_on_day_one_is_the_prior_of_day_two() -> None:
    settings = ModelSettings()
    day1, last = a_day_with_the_ball(settings)
    learned = preference(day1, "ball")
    assert learned > 0.8, f"expected day 1 to read that p wants the ball, got P = {learned:.2f}"
    memory = day_end(day1, last)
    remembered = memory.person("p")
    assert remembered is not None and abs(remembered.preference["ball"] - learned) < 1e-5
    morning = household_state(0, (2, 0))  # day 2: p stands in R1, the ball back at A
    fresh = MindTracker(household_scene(), settings)
    fresh.observe(morning, [])
    day2 = MindTracker(household_scene(), settings, memory=memory)
    day2.observe(morning, [])
    drift = settings.memory_drift
    expected = (1 - drift) * learned + drift / 3
    assert abs(preference(day2, "ball") - expected) < 0.02, (
        f"expected day 2 to start from day 1's {learned:.2f} with drift {drift} ({expected:.2f}), "
        f"got {preference(day2, 'ball'):.2f}"
    )
    assert abs(preference(fresh, "ball") - 1 / 3) < 0.02, "without memory the prior is even"


def test_an_item_moved_overnight_in_the_robots_view_is_a_stale_false_belief_at_the_first_tick() -> None:
    """Day 1 ends with p having seen the ball at A. Overnight the ball goes to B. Day 2 starts
    with p outside (seeing nothing): the brain reads at its first tick, before p does
    anything, that p believes the ball at A: a false belief."""
    settings = ModelSettings()
    day1, last = a_day_with_the_ball(settings)
    drop = Event(episode=1, tick=5, time=3.5, kind=EventKind.DROP, actor="p", item="ball", location="A")
    end = household_state(5, (1, 0))
    day1.observe(end, [drop])
    memory = day_end(day1, end)
    morning = household_state(0, (5, 2), items=("B", "B"))  # the ball moved to B overnight
    day2 = MindTracker(household_scene(), settings, memory=memory)
    day2.observe(morning, [])
    stale = false_belief(day2, "ball")
    assert stale > 0.5, (
        f"expected P(false belief about the ball) > 0.5 at day 2's first tick, got {stale:.2f}"
    )
    fresh = MindTracker(household_scene(), settings)
    fresh.observe(morning, [])
    assert false_belief(fresh, "ball") < 0.5, "a brain without memory cannot know it"


def test_an_overnight_move_the_robot_did_not_see_is_found_when_it_sees_the_place() -> None:
    """Embodied: the robot remembers the ball at A and starts day 2 outside, seeing nothing;
    the ball went to B overnight. Until the robot sees B it believes the ball at A, as p
    does (no false belief read); once it sees the ball at B, p's belief reads as false."""
    settings = ModelSettings(perception="embodied")
    day1, last = a_day_with_the_ball(settings)
    drop = Event(episode=1, tick=5, time=3.5, kind=EventKind.DROP, actor="p", item="ball", location="A")
    end = household_state(5, (1, 0))
    day1.observe(end, [drop])
    memory = day_end(day1, end)
    assert memory.items["ball"]["A"] > 0.99, f"the robot saw the ball put down at A: {memory.items}"
    day2 = MindTracker(household_scene(), settings, memory=memory)
    day2.observe(household_state(0, (5, 2), robot=(5, 2), items=("B", "B")), [])
    before = false_belief(day2, "ball")
    assert before < 0.5, f"the robot believes the ball at A, as p does: got P(false belief) {before:.2f}"
    day2.observe(household_state(1, (5, 2), robot=(5, 1), items=("B", "B")), [])  # the robot sees B
    after = false_belief(day2, "ball")
    assert after > 0.5, f"expected P(false belief) > 0.5 once the robot sees the ball at B, got {after:.2f}"


def test_a_switch_redraws_from_the_remembered_desires() -> None:
    """With a memory, a preference switch redraws from what the person was remembered to want
    (their lasting preferences), not uniformly: a person who turned to something else for a
    while drifts back toward their favourite as time passes, at the hazard's rate."""
    import numpy as np

    from brain.model.inference import switched

    base = np.array([0.8, 0.1, 0.1])
    alpha = np.array([[0.0, 0.0, 0.5], [0.0, 0.0, 0.5]])  # two hypotheses, both read as "out"
    after = alpha
    for _ in range(60):
        after = switched(after, 0.1, base)
    assert np.isclose(after.sum(), 1.0), "a switch keeps the mass"
    assert np.allclose(after / after.sum(axis=1, keepdims=True), base, atol=0.01), after
    uniform = switched(alpha, 0.1)
    # a redraw from every goal evenly gives the ball 0.1 x 0.5 / 3; from the memory 0.1 x 0.5 x 0.8
    assert np.isclose(uniform[0, 0], 0.1 * 0.5 / 3) and np.isclose(switched(alpha, 0.1, base)[0, 0], 0.04)
