"""A run's bookkeeping: a run whose minds miss ticks of the truth fails (to be tried again)
instead of being scored on fewer ticks."""

from __future__ import annotations

import msgspec
import pytest
from support import golden_examples

from protocol import Mind, Truth
from toyroom.evaluation.metrics import Counts, EpisodeOutcome, score_tick
from toyroom.evaluation.nestedscore import score_nested
from toyroom.evaluation.runs import TruthView, _score, check_complete, missing_ticks
from toyroom.evaluation.wantread import score_want


def _ticks(ticks: range, kind: type[Mind] | type[Truth]) -> dict:
    example = golden_examples()[kind.__name__.lower()]
    return {t: msgspec.structs.replace(example, tick=t) for t in ticks}


def test_missing_ticks_names_the_truths_without_a_mind() -> None:
    truths = _ticks(range(10), Truth)
    minds = _ticks(range(3, 10), Mind)
    del minds[6]
    assert missing_ticks(minds, truths) == [0, 1, 2, 6]
    assert missing_ticks(_ticks(range(10), Mind), truths) == []


def test_a_run_missing_minds_fails_with_what_is_missing() -> None:
    truths = _ticks(range(100), Truth)
    minds = _ticks(range(7, 100), Mind)
    with pytest.raises(RuntimeError) as caught:
        check_complete("ep-btom-observe", "perceptonly", minds, truths)
    message = str(caught.value)
    expected = ("perceptonly", "7 of 100 ticks", "(ticks 0, 1, 2, 3, 4, ...)")
    assert all(part in message for part in expected), f"expected {expected} in: {message}"
    check_complete("ep-btom-observe", "btom", _ticks(range(100), Mind), truths)  # complete: no error


def test_scores_reused_from_the_tick_before_equal_scoring_every_tick() -> None:
    truth, mind = golden_examples()["truth"], golden_examples()["mind"]
    others = (
        msgspec.structs.replace(truth, agents=truth.agents[:1]),
        msgspec.structs.replace(mind, agents=mind.agents[::-1]),
    )
    pattern = [0, 0, 0, 1, 1, 0, 2, 2, 2, 0]  # runs of equal ticks, and changes of each kind
    truths = {
        t: msgspec.structs.replace(others[0] if k == 1 else truth, tick=t) for t, k in enumerate(pattern)
    }
    minds = {t: msgspec.structs.replace(others[1] if k == 2 else mind, tick=t) for t, k in enumerate(pattern)}
    took = {4: {truth.agents[0].agent}}
    view = TruthView(truths, took, [])
    expected, seen = Counts(), set()
    for tick in sorted(truths):
        seen |= took.get(tick, set())
        where = {place.item: place.location for place in truths[tick].items}
        counts = score_tick(minds[tick], truths[tick], where, seen, view.causes[tick], view.known[tick])
        score_nested(minds[tick], truths[tick], counts)
        counts.add_want(score_want(minds[tick], truths[tick], view.wanting[tick]))
        expected.add(counts)
    got = _score(minds, view, EpisodeOutcome()).counts
    assert got == expected, f"expected {expected}, got {got}"
    assert got.tv_n > 0, "expected some beliefs scored"
    assert got.want_n > 0, "expected some wants scored (the golden truth holds a false belief)"
