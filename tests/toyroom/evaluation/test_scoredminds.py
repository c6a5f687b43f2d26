"""The evaluation reads only what it scores of the brain's minds: the same beliefs,
preferences and flagged false beliefs as the whole message, and the same scores."""

from __future__ import annotations

from pathlib import Path

import msgspec
import pytest
from support import golden_examples

from protocol import Mind, Truth, encode
from toyroom.evaluation.metrics import score_tick
from toyroom.evaluation.scoredminds import ScoredMind, read_scored_minds


def _example() -> tuple[Mind, Truth]:
    examples = golden_examples()
    mind, truth = examples["mind"], examples["truth"]
    assert isinstance(mind, Mind) and isinstance(truth, Truth)
    return mind, truth


def test_the_scored_part_is_the_whole_messages(tmp_path: Path) -> None:
    mind, _ = _example()
    path = tmp_path / "minds-btom.jsonl"
    path.write_bytes(b"".join(encode(msgspec.structs.replace(mind, tick=t)) + b"\n" for t in range(3)))
    read = read_scored_minds(path)
    assert sorted(read) == [0, 1, 2], sorted(read)
    for whole, part in zip(mind.agents, read[1].agents, strict=True):
        assert part.agent == whole.agent and part.false_beliefs == whole.false_beliefs
        assert [(b.item, [(p.id, p.p) for p in b.locations]) for b in part.beliefs] == [
            (b.item, [(p.id, p.p) for p in b.locations]) for b in whole.beliefs
        ], f"beliefs of {whole.agent} read differently"
        assert [(p.id, p.p) for p in part.preference] == [(p.id, p.p) for p in whole.preference]


def test_the_scored_part_scores_as_the_whole(tmp_path: Path) -> None:
    mind, truth = _example()
    path = tmp_path / "minds-btom.jsonl"
    path.write_bytes(encode(mind) + b"\n")
    part = read_scored_minds(path)[mind.tick]
    where = {place.item: place.location for place in truth.items}
    took = {a.agent for a in truth.agents}
    whole = score_tick(mind, truth, where, took)
    assert whole.tv_n > 0 and whole.tp + whole.fn > 0 and whole.pref_n > 0, f"scored nothing: {whole}"
    assert score_tick(part, truth, where, took) == whole


def test_a_line_that_is_no_mind_is_an_error(tmp_path: Path) -> None:
    path = tmp_path / "minds-btom.jsonl"
    path.write_bytes(b'{"type":"mind","tick":"soon"}\n')
    with pytest.raises(ValueError, match="tick"):
        read_scored_minds(path)


def test_a_line_ending_as_the_one_before_reads_as_decoded_in_full(tmp_path: Path) -> None:
    """A line whose agents are byte for byte the previous line's takes its agents from that
    line (only its tick is decoded): the minds read are those a full decode of every line
    gives, through runs of repeats, a change and a change back, and a repeat with a bad tick
    is still an error."""
    mind, _ = _example()
    anne = msgspec.structs.replace(mind.agents[0], agent="anne")
    other = msgspec.structs.replace(mind, agents=(anne, *mind.agents[1:]))
    sequence = [mind, mind, mind, other, other, mind, mind]
    lines = [encode(msgspec.structs.replace(m, tick=t)) for t, m in enumerate(sequence)]
    path = tmp_path / "minds-btom.jsonl"
    path.write_bytes(b"".join(line + b"\n" for line in lines))
    full = {m.tick: m for m in map(msgspec.json.Decoder(ScoredMind).decode, lines)}
    read = read_scored_minds(path)
    assert read == full, f"ticks read differently: {[t for t in full if read.get(t) != full[t]]}"
    names = [read[t].agents[0].agent for t in range(len(sequence))]
    assert names == [m.agents[0].agent for m in sequence], f"agents read by tick: {names}"
    bad = lines[-1].replace(b'"tick":6', b'"tick":"6"')
    assert bad != lines[-1], 'the example\'s tick should be written as "tick":6'
    path.write_bytes(b"".join(line + b"\n" for line in [*lines[:-1], bad]))
    with pytest.raises(ValueError, match="tick"):
        read_scored_minds(path)
