"""Graded beliefs held as a mixture of point-start beliefs (:mod:`brain.model.mixture`): the
same numbers as the dense ``(G, W)`` array to rounding, revision by revision and estimate by
estimate on recorded episodes (a generated house's 512 worlds among them), with the dense
array's rule where a hypothesis's percept is impossible."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from brain.model.belief import NOT_IN_VIEW, Percept
from brain.model.estimates import Estimate
from brain.model.mixture import Mixture, mixture_of
from brain.model.person import gradedperson
from brain.model.person.gradedperson import GradedModel
from brain.model.person.personinterface import StepRecord
from brain.model.revisions import SharedRevisions
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Event, Observer, Scene, State
from sim2d.engine import Engine
from sim2d.generation import write_episode
from sim2d.scenario import load_scenario

OBSERVERS = (Observer.BTOM, Observer.TRUEBELIEF, Observer.PERCEPTONLY)
Stream = tuple[Scene, list[tuple[State, tuple[Event, ...]]]]


def recorded(engine: Engine, ticks: int) -> Stream:
    """The engine's first ``ticks`` ticks, as the brain receives them."""
    stream: list[tuple[State, tuple[Event, ...]]] = [(engine.state(), ())]
    while not engine.done and len(stream) < ticks:
        result = engine.step()
        stream.append((result.state, result.events))
    return engine.scene(), stream


@pytest.fixture(scope="module")
def paper() -> Stream:
    return recorded(Engine("paper-2", robot="observe"), 400)


@pytest.fixture(scope="module")
def house(tmp_path_factory: pytest.TempPathFactory) -> Stream:
    folder = Path(tmp_path_factory.mktemp("house"))
    scenario = load_scenario(str(write_episode(folder, "house-a", 5)))
    return recorded(Engine(scenario, robot="observe"), 250)


def estimates(stream: Stream, settings: ModelSettings) -> list[dict[str, Estimate | None]]:
    """Every observer's online estimate of every person at every tick, the trackers sharing
    revisions as a brain's do, then ``btom``'s smoothed ones."""
    scene, ticks = stream
    revisions = SharedRevisions()
    trackers = [MindTracker(scene, settings, o, revisions) for o in OBSERVERS]
    out: list[dict[str, Estimate | None]] = []
    for state, events in ticks:
        for tracker in trackers:
            tracker.observe(state, events)
            out.append({p: tracker.online(p) for p in tracker.people})
    for person in trackers[0].people:
        out += [{person: est} for est in trackers[0].smoothed(person)]
    return out


def assert_same(mixed: list[dict[str, Estimate | None]], dense: list[dict[str, Estimate | None]]) -> None:
    """Every estimate's every number within 1e-9, and the same picks."""
    assert len(mixed) == len(dense)
    for t, (a, b) in enumerate(zip(mixed, dense, strict=True)):
        for person, x in a.items():
            y = b[person]
            assert (x is None) == (y is None), f"row {t}, {person}"
            if x is None or y is None:
                continue
            assert x.intention[:2] == y.intention[:2], f"row {t}, {person}: {x.intention} vs {y.intention}"
            for name in ("beliefs", "preference", "false_belief", "worlds"):
                got, want = getattr(x, name), getattr(y, name)
                assert np.allclose(got, want, atol=1e-9, rtol=0), f"row {t}, {person}: {name}"
            assert x.log_evidence == pytest.approx(y.log_evidence, abs=1e-9)
            if x.hypotheses is None or y.hypotheses is None:  # a slimmed history (brain.model.estimates.slim)
                assert x.false_table is not None and y.false_table is not None, f"row {t}, {person}"
                assert np.allclose(x.false_table, y.false_table, atol=1e-9, rtol=0), f"row {t}, {person}"
                continue
            for got, want in zip(x.hypotheses, y.hypotheses, strict=True):
                assert np.allclose(got, want, atol=1e-9, rtol=0), f"row {t}, {person}: hypotheses"


def dense_estimates(monkeypatch: pytest.MonkeyPatch, stream: Stream, settings: ModelSettings) -> list:
    """:func:`estimates` with every filter holding the dense ``(G, W)`` array."""
    with monkeypatch.context() as patch:
        patch.setattr(gradedperson, "mixture_of", lambda beliefs: None)
        return estimates(stream, settings)


@pytest.mark.parametrize(
    "settings",
    [
        ModelSettings(),
        ModelSettings(forget_per_s=0.05, belief_update="paper"),
        ModelSettings(person_planner="belief", desire_model="graded"),
        ModelSettings(perception="embodied"),
        ModelSettings(miss=0.1, hearsay_per_s=0.05),
    ],
    ids=["default", "forget-paper", "lookahead-desires", "embodied", "lapses"],
)
def test_the_mixture_estimates_as_the_dense_array_on_the_paper_map(
    monkeypatch: pytest.MonkeyPatch, paper: Stream, settings: ModelSettings
) -> None:
    assert_same(estimates(paper, settings), dense_estimates(monkeypatch, paper, settings))


def test_the_mixture_estimates_as_the_dense_array_on_a_house(
    monkeypatch: pytest.MonkeyPatch, house: Stream
) -> None:
    """The evaluation's houses: ``G = 1331`` hypotheses as mixtures of at most 64 components."""
    model = GradedModel(house[0], ModelSettings(), true_world=False)
    assert isinstance(model.start, Mixture) and model.start.weights.shape == (1331, 64)
    assert_same(estimates(house, ModelSettings()), dense_estimates(monkeypatch, house, ModelSettings()))


def test_a_revised_mixture_is_the_revised_array(paper: Stream) -> None:
    """Revision by revision, percepts in and out of view, with forgetting: the mixture's
    beliefs are the dense array's, and its rows stay distributions."""
    model = GradedModel(paper[0], ModelSettings(), true_world=False)
    world = model.model
    mixed = mixture_of(model.initial)
    assert mixed is not None and np.allclose(mixed.dense, model.initial, atol=1e-15)
    dense, rng = model.initial.copy(), np.random.default_rng(5)
    for tick in range(40):
        cell = int(rng.integers(world.n_cells))
        seen = tuple(
            int(v) if world.sees[cell, v // 2] else NOT_IN_VIEW
            for v in world.worlds[int(rng.integers(world.n_worlds))]
        )
        record = StepRecord(
            tick, Percept(cell, seen), (0,) * world.n_items, None, 0.0, forget=0.02 * (tick % 3)
        )
        revised = model.revise(mixed, record)
        dense = model.revise(dense, record)
        assert isinstance(revised, Mixture), f"tick {tick}: left the mixture"
        mixed = revised
        assert np.allclose(mixed.dense, dense, atol=1e-12, rtol=0), f"tick {tick}"
        assert np.allclose(mixed.weights.sum(axis=1), 1.0) and np.allclose(mixed.vectors.sum(axis=1), 1.0)
        for matrix in (model.place_of.reshape(world.n_worlds, -1), model.rest_of):
            assert np.allclose(mixed @ matrix, dense @ matrix, atol=1e-12, rtol=0)


def test_an_impossible_percept_takes_the_dense_rule(monkeypatch: pytest.MonkeyPatch, paper: Stream) -> None:
    """A percept no world of a hypothesis explains (possible with ``delta = 0``) leaves its
    belief as it was: no mixture says that, so the revision is the dense array's, by that rule."""
    from brain.model import graded

    model = GradedModel(paper[0], ModelSettings(), true_world=False)
    mixed = mixture_of(model.initial)
    assert mixed is not None
    dead = int(np.flatnonzero(mixed.vectors[0])[0])  # the first component's world
    linear = graded.unnormalised_update

    def update(rows: np.ndarray, *args: object) -> np.ndarray:  # nothing explains a belief certain of it
        out = linear(rows, *args)  # type: ignore[arg-type]
        out[rows[:, dead] == 1.0] = 0.0
        return out

    monkeypatch.setattr(graded, "unnormalised_update", update)
    monkeypatch.setattr(gradedperson, "unnormalised_update", update)
    unseen = Percept(0, (NOT_IN_VIEW,) * model.model.n_items)
    record = StepRecord(0, unseen, (0,) * model.model.n_items, None, 0.0)
    got = model.revise(mixed, record)
    want = model.revise(model.initial.copy(), record)
    assert isinstance(got, np.ndarray), "a hypothesis certain of the dead world has no mixture"
    assert np.allclose(got, want, atol=1e-15, rtol=0)
    assert np.array_equal(got[model.initial[:, dead] == 1.0], model.initial[model.initial[:, dead] == 1.0])


def test_truebelief_collapses_to_one_component(paper: Stream) -> None:
    model = GradedModel(paper[0], ModelSettings(), true_world=True)
    world = model.model
    mixed = mixture_of(model.initial)
    assert mixed is not None
    truth = tuple(int(v) for v in world.worlds[5])
    record = StepRecord(0, Percept(0, (NOT_IN_VIEW,) * world.n_items), truth, None, 0.0)
    got = model.revise(mixed, record)
    assert isinstance(got, Mixture) and got.one_world() and len(got.vectors) == 1
    assert np.array_equal(got.dense, model.revise(model.initial.copy(), record))


def test_the_filter_shows_its_beliefs_as_a_read_only_array(paper: Stream) -> None:
    tracker = MindTracker(paper[0], ModelSettings())
    for state, events in paper[1][:60]:
        tracker.observe(state, events)
    chain = next(t.chains[0] for t in tracker.tracks.values() if t.chains[0].filter is not None)
    held = chain.filter
    assert isinstance(held, gradedperson.GradedFilter) and isinstance(held.state, Mixture)
    with pytest.raises(ValueError, match="read-only"):
        held.beliefs[0, 0] = 0.5
    assert np.allclose(held.beliefs.sum(axis=1), 1.0)
    assert dataclasses.replace(held, state=held.beliefs).estimate(tracker.truth).preference == pytest.approx(
        held.estimate(tracker.truth).preference, abs=1e-12
    )


def test_a_pick_among_equal_probabilities_does_not_hang_on_rounding() -> None:
    """The likeliest of (nearly) equal probabilities is the first, whatever the last bit (two
    sums of the same terms in another order, as the mixture's and the array's, may differ
    there); a real difference still decides."""
    from brain.model.arrays import first_max

    assert first_max(np.array([0.3, 0.3 + 5e-17, 0.2])) == 0
    assert first_max(np.array([0.2, 0.3 - 5e-17, 0.3])) == 1
    assert first_max(np.array([0.3, 0.3 + 1e-9])) == 1
    est = Estimate(np.zeros((2, 2)), np.zeros(3), (None, None, 0.0), np.array([0.5 + 1e-16, 0.5 + 1e-6]))
    assert est.false_beliefs == (1,), "an even chance, to rounding, is not a false belief"
