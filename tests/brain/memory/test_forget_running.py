"""``toyroom memory forget`` on a file a running brain holds: a real brain follows a real-time
sim2d engine through day 2 of a household, a real ``toyroom memory forget`` asks it to forget
a person, and after the run the person is gone from the file's rows and bytes, though the
brain saved many times after the request. A file held by a process that does not answer is
refused, with nothing forgotten; a request left unanswered is carried out by the next brain."""

from __future__ import annotations

import re
import signal
import subprocess
import sys
import tempfile
import threading
from pathlib import Path

import msgspec
import pytest
from support import EngineProcess

from brain.memory import MemoryKeeper, PersonMemory, Snapshot, open_memory
from brain.memory.requests import ForgetRequest, answer_of, ask, folder
from brain.outputs.results import mind_message
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge import Bridge, Received
from protocol import Household, Mind
from sim2d.scenario.maps import SCENARIO_DIR
from tests.brain.memory.test_command import memory, refused
from tests.scenes import household_scene, household_state

NAME = "Zelda-Forgotten"
"""A1 of ``paper-auto``, renamed: a name no float's bytes spell by chance."""


def day_two(folder: Path) -> Path:
    """``paper-auto`` as day 2 of household ``h1``, its A1 named :data:`NAME` (at A1's home)."""
    text = (SCENARIO_DIR / "paper-auto.toml").read_text()
    assert text.count('id = "A1"') == 1, "expected A1 named once in paper-auto"
    path = folder / "h1-day2.toml"
    path.write_text(
        text.replace('id = "A1"', f'id = "{NAME}"\nhome = [1, 9]').replace(
            'name = "paper-auto"', 'name = "h1-day2"'
        )
        + '\n[household]\nid = "h1"\nday = 2\n'
    )
    return path


def remembered(household: str, first: str) -> Snapshot:
    people = (
        PersonMemory(first, {"ball": 0.8, "skate": 0.1, "out": 0.1}, {"ball": {"S2": 0.9, "P2": 0.1}}),
        PersonMemory("A2", {"ball": 0.2, "skate": 0.7, "out": 0.1}, {"skate": {"S1": 1.0}}),
    )
    return Snapshot(household, 1, 500, True, people, {"ball": {"S2": 1.0}})


class Ticks:
    """The ticks of the brain's minds on the wire, waited on as they come."""

    def __init__(self) -> None:
        self.seen: list[int] = []
        self._changed = threading.Condition()

    def __call__(self, mind: Mind, _: Received) -> None:
        with self._changed:
            self.seen.append(mind.tick)
            self._changed.notify_all()

    def wait(self, done, what: str, timeout: float = 90) -> None:  # noqa: ANN001
        with self._changed:
            if not self._changed.wait_for(lambda: done(self.seen), timeout):
                raise AssertionError(f"expected {what} within {timeout} s, got ticks {self.seen[-5:]}")


def test_forget_while_a_brain_runs_is_kept_by_every_later_save(world: str, tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as store:
        store.save(remembered("h1", NAME))
        store.save(remembered("h2", "B1"))  # another household: untouched
    day2 = day_two(tmp_path)
    brain_log = tempfile.TemporaryFile()
    command = [sys.executable, "-m", "brain", "--world", world, "--memory", str(path)]
    ticks = Ticks()
    with EngineProcess(world, "--scenario", str(day2), "--realtime", "4"), Bridge(world) as watcher:
        watcher.subscribe(watcher.keys.mind, ticks, expected=Mind)
        brain = subprocess.Popen(
            [*command, "--checkpoint-ticks", "10", "--log-level", "INFO"], stdout=brain_log, stderr=brain_log
        )
        try:
            ticks.wait(lambda seen: len(seen) >= 30, "the brain to follow the day 30 ticks")
            forget = subprocess.run(
                [sys.executable, "-m", "toyroom", "memory", "forget", str(path), NAME, "--household", "h1"],
                capture_output=True,
                text=True,
                timeout=120,
            )
            assert forget.returncode == 0, f"expected exit 0, got {forget.returncode}: {forget.stderr}"
            said = re.search(r"by the running brain \(at tick (\d+)\)", forget.stdout)
            assert said is not None and f"forgot {NAME} in household h1" in forget.stdout, (
                f"expected the running brain to answer, got {forget.stdout!r}"
            )
            asked_at = int(said.group(1))
            ticks.wait(lambda seen: max(seen) >= asked_at + 60, "6 more checkpoints after the forget")
            brain.send_signal(signal.SIGTERM)  # the day's end is saved at the next tick
            assert brain.wait(timeout=60) == 0, "expected the brain to stop cleanly"
        finally:
            if brain.poll() is None:
                brain.kill()
                brain.wait()
    brain_log.seek(0)
    log = brain_log.read().decode(errors="replace")
    said = [line for line in log.splitlines() if "on request" in line]
    assert said and "forgot a person in household 'h1' on request" in said[0] and NAME not in said[0], (
        f"expected the forget logged without the name, got {said} in:\n{log[-3000:]}"
    )
    with open_memory(path, read_only=True) as store:
        held = store.people_by_household()
        saved = {(s.household, s.day): s for s, _ in store.saved()}
        names = store.names()
    assert held == {"h1": ["A2"], "h2": ["A2", "B1"]}, f"expected {NAME} gone from h1 only, got {held}"
    last = saved[("h1", 2)]
    assert last.tick >= asked_at + 60, (
        f"expected saves of day 2 after tick {asked_at} (the forget), the last at tick {last.tick}"
    )
    assert "S1" in names.get("h1", {}), f"expected the scene's place names kept, got {names}"
    left = {
        p.name: p.read_bytes().count(NAME.encode()) for p in tmp_path.glob("memory.sqlite*") if p.is_file()
    }
    assert not any(left.values()), f"expected no byte of {NAME} in the memory's files, found {left}"
    assert not folder(path).exists(), "expected the answered request's folder gone"


def test_a_holder_that_does_not_answer_leaves_nothing_forgotten(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as store:
        store.save(remembered("h1", NAME))
        result = memory(["forget", str(path), NAME, "--wait", "0.3"], capsys, monkeypatch)
        refused(result, "in use by another process", "nothing was forgotten", "--wait")
        assert NAME in store.people(), f"expected {NAME} kept, got {store.people()}"
    assert not folder(path).exists(), f"expected the request withdrawn, found {list(folder(path).iterdir())}"


def test_a_request_left_unanswered_is_carried_out_by_the_next_brain(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as store:
        store.save(remembered("h1", NAME))
    asked = ask(path, ForgetRequest(NAME, "h1"))  # its asker gave up; no brain ran
    unknown = ask(path, ForgetRequest("Nobody", "h1"))
    with open_memory(path) as store:
        MemoryKeeper(store)  # a brain starting with the file
        assert store.people() == ["A2"], (
            f"expected {NAME} forgotten at the brain's start, got {store.people()}"
        )
    answer, other = answer_of(asked), answer_of(unknown)
    assert answer is not None and answer.removed == 5 and not answer.error, f"expected 5 rows, got {answer}"
    assert other is not None and "holds no person 'Nobody'" in other.error, f"expected an error, got {other}"
    assert not folder(path).exists(), "expected the requests' folder gone once answered"


def test_a_person_of_the_scene_followed_is_forgotten_before_their_first_save(tmp_path: Path) -> None:
    """The keeper's side, in-process: ``p`` of the day followed is not in the file yet; asked
    to forget them, the keeper answers 0 rows and leaves them out of every save after."""
    path = tmp_path / "memory.sqlite"
    scene = msgspec.structs.replace(household_scene(), household=Household(id="home", day=1))
    tracker = MindTracker(scene, ModelSettings())
    state = household_state(0, (2, 0))
    tracker.observe(state, [])
    with open_memory(path) as store:
        store.save(remembered("other", "p"))  # a p of another household: not this one
        keeper = MemoryKeeper(store, checkpoint_ticks=1)
        keeper.start(scene, 0)
        asked = ask(path, ForgetRequest("p", "home"))
        nobody = ask(path, ForgetRequest("Nobody"))
        keeper.after_tick(mind_message(tracker, state), tracker.robot_items(), over=True)
        saved = store.morning("home", 2)
        held = store.people_by_household()
    answer, other = answer_of(asked), answer_of(nobody)
    assert answer is not None and (answer.household, answer.removed, answer.error) == ("home", 0, ""), (
        f"expected p forgotten in home with 0 rows, got {answer}"
    )
    assert other is not None and "holds no person 'Nobody'" in other.error, f"expected an error, got {other}"
    assert saved is not None and saved.person("p") is None, f"expected the day's end without p, got {saved}"
    assert held == {"home": [], "other": ["A2", "p"]}, f"expected p of 'other' kept, got {held}"
