"""The run log: every state handled and its events, and the live observer's minds, one
protocol message per line, in order, as the evaluator reads them back."""

from __future__ import annotations

from pathlib import Path

import msgspec
import pytest
from support import golden_examples

from brain.__main__ import episode_folders, main
from brain.outputs.runlog import RunLog, inputs_path
from brain.outputs.shadows import shadow_path
from brain.tracking.tracker import Observer
from protocol import EngineInfo, Event, Mind, State, decode


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


def test_the_log_begins_with_the_engines_handshake(tmp_path: Path) -> None:
    """The scene a run followed travels with its log (a brain running several episodes
    resets the engine to each, so the evaluator cannot ask the engine for it)."""
    examples = golden_examples()
    info, state = examples["engine_info"], examples["state"]
    assert isinstance(info, EngineInfo) and isinstance(state, State)
    log = RunLog(tmp_path, Observer.BTOM)
    log.engine(info)
    log.inputs(state, [])
    log.close()
    inputs = [decode(line) for line in inputs_path(tmp_path).read_bytes().splitlines()]
    assert inputs == [info, state], f"expected the handshake, then the state; got {inputs}"


def test_episodes_sharing_a_folder_are_refused(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``python -m brain --episodes``: each episode's outputs go to a folder named by its
    scenario's stem, so two scenarios of one stem are refused before anything runs."""
    assert episode_folders(["a/one.toml", "b/two.toml"]) == [("a/one.toml", "one"), ("b/two.toml", "two")]
    code = main(["--episodes", "a/one.toml", "b/one.toml", "--run-log", str(tmp_path / "log")])
    assert code == 2
    err = capsys.readouterr().err
    assert "two scenarios named 'one'" in err, f"expected the clash named, got: {err}"
    assert not (tmp_path / "log").exists(), "nothing ran"
