"""Shared belief revisions (:mod:`brain.model.revisions`): ``perceptonly`` takes ``btom``'s
revised beliefs instead of computing them again, and every observer's estimates stay the
same to the bit."""

from __future__ import annotations

import numpy as np
import pytest

from brain.model.revisions import SharedRevisions
from brain.outputs.results import mind_message
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Event, EventKind, Observer, State, encode
from tests.scenes import corridor_scene, corridor_state

OBSERVERS = (Observer.BTOM, Observer.TRUEBELIEF, Observer.PERCEPTONLY)


def ticks() -> list[tuple[State, list[Event]]]:
    """A person walks right to the ball at B, takes it, walks back left and puts it down at A."""
    out: list[tuple[State, list[Event]]] = [(corridor_state(t, c), []) for t, c in enumerate((5, 6, 7, 8))]
    take = Event(episode=1, tick=4, time=2.8, kind=EventKind.TAKE, actor="p", item="ball", location="B")
    out.append((corridor_state(4, 8, holding=True), [take]))
    back = zip(range(5, 11), range(7, 1, -1), strict=True)
    out += [(corridor_state(t, c, holding=True), []) for t, c in back]
    drop = Event(episode=1, tick=11, time=7.7, kind=EventKind.DROP, actor="p", item="ball", location="A")
    out.append((corridor_state(11, 2, ball_at="A"), [drop]))
    return out


def minds(settings: ModelSettings, revisions: SharedRevisions | None) -> list[list[bytes]]:
    """Every observer's ``mind`` message at every tick, the trackers fed in turn as a brain does."""
    trackers = [MindTracker(corridor_scene(), settings, o, revisions) for o in OBSERVERS]
    out: list[list[bytes]] = [[] for _ in OBSERVERS]
    for state, events in ticks():
        for tracker, messages in zip(trackers, out, strict=True):
            tracker.observe(state, events)
            messages.append(encode(mind_message(tracker, state)))
    return out


@pytest.mark.parametrize("perception", ["omniscient", "embodied"])
def test_sharing_changes_no_estimate_and_saves_perceptonly_its_revisions(perception: str) -> None:
    settings = ModelSettings(perception=perception)
    revisions = SharedRevisions()
    shared, alone = minds(settings, revisions), minds(settings, None)
    for observer, a, b in zip(OBSERVERS, shared, alone, strict=True):
        assert a == b, f"{observer.value}: the shared run's minds differ from the unshared run's"
    assert revisions.hits > 0 and revisions.hits == revisions.misses, (
        f"expected perceptonly to take every one of btom's revisions, got {revisions.hits} taken "
        f"and {revisions.misses} computed"
    )


def test_shared_beliefs_are_read_only_and_other_settings_do_not_share() -> None:
    revisions = SharedRevisions()
    btom = MindTracker(corridor_scene(), ModelSettings(), Observer.BTOM, revisions)
    other = MindTracker(corridor_scene(), ModelSettings(r=4.0), Observer.PERCEPTONLY, revisions)
    for state, events in ticks()[:3]:
        btom.observe(state, events)
        other.observe(state, events)
    assert revisions.hits == 0, "a model with another r revises otherwise: nothing is shared"
    chain = btom.tracks["p"].chains[0]
    assert chain.filter is not None
    beliefs = chain.filter.beliefs  # type: ignore[attr-defined]
    with pytest.raises(ValueError, match="read-only"):
        beliefs[0, 0] = 0.5
    assert np.allclose(beliefs.sum(axis=1), 1.0)


def test_what_is_read_off_a_shared_array_is_computed_once_per_array() -> None:
    """``SharedRevisions.read``: the second model holding the very same array gets the first
    one's result (read-only) without computing it; another array, even an equal one, is
    computed anew, and so is the same array under another key."""
    shared = SharedRevisions()
    calls: list[int] = []

    def marginals(beliefs: np.ndarray) -> np.ndarray:
        calls.append(id(beliefs))
        return beliefs.sum(axis=1)

    beliefs = np.full((3, 4), 0.25)
    first = shared.read("marginals", beliefs, marginals)
    again = shared.read("marginals", beliefs, marginals)
    assert again is first and len(calls) == 1, f"expected the kept result, computed {len(calls)} times"
    assert not first.flags.writeable, "a shared result must be read-only"
    shared.read("marginals", beliefs.copy(), marginals)
    shared.read("other", beliefs, marginals)
    assert len(calls) == 3, f"an equal copy and another key should each be computed, got {len(calls)} calls"
