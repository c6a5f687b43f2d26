"""A run's bookkeeping: a run whose minds miss ticks of the truth fails (to be tried again)
instead of being scored on fewer ticks."""

from __future__ import annotations

import msgspec
import pytest
from support import golden_examples

from bridge.evaluation.runs import check_complete, missing_ticks
from protocol import Mind, Truth


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
