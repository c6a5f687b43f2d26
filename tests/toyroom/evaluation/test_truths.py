"""The evaluator's truth decoding: a truth that repeats the one before but for its tick is
read from the tick alone, and equals decoding it whole; anything else is decoded whole."""

from __future__ import annotations

import msgspec
import pytest
from support import golden_examples

from protocol import ItemPlace, ProtocolError, Truth, decode, encode
from toyroom.evaluation.truths import TruthDecoder


def _payloads() -> list[bytes]:
    example: Truth = golden_examples()["truth"]
    moved = msgspec.structs.replace(example, items=(ItemPlace(item="ball", location="S2"),))
    fewer = msgspec.structs.replace(example, agents=example.agents[:1])
    sequence = [example] * 3 + [moved] * 2 + [fewer, example]
    out = [encode(msgspec.structs.replace(t, tick=n, episode=1 + n // 4)) for n, t in enumerate(sequence)]
    return out


def test_each_truth_equals_decoding_it_whole() -> None:
    decoder = TruthDecoder()
    for data in _payloads():
        got, expected = decoder.decode(data), decode(data, Truth)
        assert got == expected, f"expected {expected}, got {got}"
        assert encode(got) == data, "expected the truth to encode back to its payload"


def test_a_repeated_truth_reuses_the_people_it_decoded_before() -> None:
    decoder = TruthDecoder()
    first, second = _payloads()[:2]
    a, b = decoder.decode(first), decoder.decode(second)
    assert (a.tick, b.tick) == (0, 1), f"expected ticks 0 and 1, got {a.tick} and {b.tick}"
    assert b.agents is a.agents, "expected the second truth to reuse the first one's decoded people"


def test_a_bad_head_is_checked_even_when_the_rest_repeats() -> None:
    decoder = TruthDecoder()
    first, second = _payloads()[:2]
    decoder.decode(first)
    negative = second.replace(b'"tick":1', b'"tick":-1')
    newer = second.replace(b'"protocol":"1.', b'"protocol":"9.')
    padded = second.replace(b'"tick":1', b'"tick":01')
    assert second not in (negative, newer, padded), "expected the payload to be altered"
    for bad in (negative, newer, padded):
        with pytest.raises(ProtocolError):
            decoder.decode(bad)
