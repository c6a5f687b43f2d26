"""The run log: every state handled and its events, and the live observer's minds, one
protocol message per line, in order, as the evaluator reads them back."""

from __future__ import annotations

from pathlib import Path

import msgspec
from support import golden_examples

from brain.outputs.runlog import RunLog, inputs_path
from brain.outputs.shadows import shadow_path
from brain.tracking.tracker import Observer
from protocol import Event, Mind, State, decode


def test_the_log_holds_each_tick_in_order(tmp_path: Path) -> None:
    examples = golden_examples()
    state, event, mind = examples["state"], examples["event"], examples["mind"]
    assert isinstance(state, State) and isinstance(event, Event) and isinstance(mind, Mind)
    log = RunLog(tmp_path / "run", Observer.BTOM)
    written: list[object] = []
    for tick in range(3):
        s = msgspec.structs.replace(state, tick=tick)
        events = [msgspec.structs.replace(event, tick=tick)] * tick  # none, one, two
        log.inputs(s, events)
        log.mind(msgspec.structs.replace(mind, tick=tick))
        written += [s, *events]
    log.close()
    log.close()  # twice is fine
    inputs = [decode(line) for line in inputs_path(tmp_path / "run").read_bytes().splitlines()]
    assert inputs == written, f"expected the states and events as written, got {inputs}"
    lines = shadow_path(tmp_path / "run", Observer.BTOM).read_bytes().splitlines()
    minds = [decode(line, Mind) for line in lines]
    assert [m.tick for m in minds] == [0, 1, 2], [m.tick for m in minds]
