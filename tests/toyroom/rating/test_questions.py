"""The questions file of ``toyroom rate``: a good one read against the recordings, and each
kind of mistake an error naming the file, the line of the question's table and the key."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from bridge.recording import Trace, read_trace
from toyroom.rating import QuestionsError, load_study

GOOD = """
title = "T"
consent = "C"

[[questions]]
recording = "robot"
tick = 10
person = "A1"
ask = "belief"
item = "skate"
locations = ["S1", "S2"]

[[questions]]
id = "later"
recording = "paper-robot-decline"
tick = 5
person = "A2"
ask = "desire"
goals = ["ball", "out"]
retrospective = true
"""


@pytest.fixture(scope="module")
def traces(recordings: list[Path]) -> tuple[list[Trace], list[str]]:
    return [read_trace(p) for p in recordings], [p.stem for p in recordings]


def load(text: str, tmp_path: Path, traces: tuple[list[Trace], list[str]]) -> object:
    path = tmp_path / "q.toml"
    path.write_text(text, encoding="utf-8")
    return load_study(path, *traces)


def test_a_good_file_is_read(tmp_path: Path, traces: tuple[list[Trace], list[str]]) -> None:
    study = load(GOOD, tmp_path, traces)
    first, second = study.questions  # type: ignore[attr-defined]
    assert (first.id, first.targets, first.estimate, first.show_until) == (
        "q1",
        ("skate@S1", "skate@S2"),
        "online",
        10,
    ), f"got {first}"
    last = traces[0][1].ticks[-1][0].tick
    assert (second.targets, second.labels, second.estimate, second.show_until) == (
        ("ball", "out"),
        ("ball", "leave"),
        "smoothed",
        last,
    ), f"a retrospective question is shown to the end (tick {last}): got {second}"


@pytest.mark.parametrize(
    ("change", "expected"),
    [
        (("tick = 10", "tik = 10"), "line 5 (questions[0] 'q1'): unknown key 'tik' (did you mean 'tick'?)"),
        (('person = "A2"', 'person = "B7"'), "line 13 (questions[1] 'later'): person 'B7' is not in"),
        (("tick = 5", "tick = 99999"), "tick = 99999 is outside the recording"),
        (('item = "skate"', 'item = "kite"'), "item 'kite' is unknown (items: skate, ball)"),
        (('"robot"', '"nowhere"'), "recording 'nowhere' is no recording given"),
        (('ask = "desire"', 'ask = "hope"'), "ask must be one of belief, desire, got 'hope'"),
        (('"S2"]', '"S9"]'), "locations: 'S9' is unknown"),
        (('title = "T"', 'titel = "T"'), "unknown key 'titel' (did you mean 'title'?)"),
        (('title = "T"', "title = "), "not TOML"),
    ],
)
def test_mistakes_are_named(
    change: tuple[str, str], expected: str, tmp_path: Path, traces: tuple[list[Trace], list[str]]
) -> None:
    assert change[0] in GOOD
    with pytest.raises(QuestionsError) as err:
        load(GOOD.replace(change[0], change[1], 1), tmp_path, traces)
    assert expected in str(err.value), f"expected {expected!r} in the error, got {err.value}"


def test_the_command_says_what_is_wrong(recordings: list[Path], tmp_path: Path) -> None:
    (tmp_path / "q.toml").write_text(GOOD.replace("tick = 10", "tik = 10"), encoding="utf-8")
    done = subprocess.run(
        [
            sys.executable,
            "-m",
            "toyroom",
            "rate",
            *map(str, recordings),
            "--questions",
            str(tmp_path / "q.toml"),
        ],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=tmp_path,
    )
    assert done.returncode == 2, f"expected exit 2, got {done.returncode}: {done.stderr}"
    assert "unknown key 'tik'" in done.stderr and not (tmp_path / "ratings.csv").exists(), done.stderr


def test_a_scenario_several_recordings_share_or_a_glob_asks_each(
    tmp_path: Path, traces: tuple[list[Trace], list[str]]
) -> None:
    """Issue 55: two participants of one scenario made the example's ``recording =
    "paper-robot"`` an error ("is no recording given (known: p1, p2)"); it now asks each."""
    robot = traces[0][0]
    two = ([robot, robot], ["p1", "p2"])  # two participants' recordings of paper-robot
    text = GOOD.replace('recording = "robot"', 'recording = "paper-robot"').split("[[questions]]\nid")[0]
    study = load(text, tmp_path, two)
    asked = [(q.id, q.episode) for q in study.questions]  # type: ignore[attr-defined]
    assert asked == [("q1-p1", "p1"), ("q1-p2", "p2")], asked
    globbed = load(GOOD.replace('recording = "robot"', 'recording = "*"'), tmp_path, traces)
    asked = [(q.id, q.episode) for q in globbed.questions]  # type: ignore[attr-defined]
    assert asked == [("q1-robot", "robot"), ("q1-decline", "decline"), ("later", "paper-robot-decline")], (
        asked
    )


MOMENT = """
[[questions]]
id = "out"
recording = "robot"
at = "{at}"
{extra}
person = "A1"
ask = "belief"
item = "skate"
"""


def _events(trace: Trace, kind: str, actor: str) -> list[tuple[int, object]]:
    return [
        (state.tick, e)
        for state, events in trace.ticks
        for e in events
        if e.kind == kind and e.actor == actor
    ]


def test_a_question_at_a_moment_of_the_run(tmp_path: Path, traces: tuple[list[Trace], list[str]]) -> None:
    """``at`` names a moment by what happens (issue 55: fixed ticks did not match a played run)."""
    robot = traces[0][0]
    takes = next(t for t, e in _events(robot, "take", "A2") if e.item == "skate")  # type: ignore[attr-defined]
    leaves = [t for t, e in _events(robot, "leave", "A1") if e.location == "S1"]  # type: ignore[attr-defined]
    cases = {
        ("A2 takes skate", "offset = 20"): takes + 20,
        ("a2 TAKES the skate".replace("the ", ""), ""): takes,  # case does not matter
        ("A1 leaves Storage 1", ""): leaves[0],
        ("A1 leaves S1", "nth = 2"): leaves[1],
        ("Agent 1 leaves S1", "offset = -5"): leaves[0] - 5,
    }
    for (at, extra), want in cases.items():
        study = load(MOMENT.format(at=at, extra=extra), tmp_path, traces)
        tick = study.questions[0].tick  # type: ignore[attr-defined]
        assert tick == want, f"at = {at!r} {extra}: tick {tick}, expected {want}"


@pytest.mark.parametrize(
    ("at", "extra", "says"),
    [
        ("A1 flies to S1", "", "is not 'PERSON VERB THING'"),
        ("A9 enters S1", "", "no person 'A9'"),
        ("A1 enters Attic", "", "no room 'Attic' in the recording (rooms: E, O, P1, P2, S1, S2)"),
        ("A1 takes kite", "", "no item 'kite'"),
        ("A1 leaves S1", "nth = 9", "happens only 2 times in this recording (wanted time 9)"),
        ("A1 gets ball", "", "happens never in this recording"),
        ("A1 leaves S1", "offset = -99999", "is outside the recording"),
        ("A1 leaves S1", "tick = 5", "give tick or at"),
    ],
)
def test_a_wrong_moment_is_refused(
    tmp_path: Path, traces: tuple[list[Trace], list[str]], at: str, extra: str, says: str
) -> None:
    with pytest.raises(QuestionsError) as caught:
        load(MOMENT.format(at=at, extra=extra), tmp_path, traces)
    assert says in str(caught.value) and "questions[0] 'out'" in str(caught.value), str(caught.value)


def test_replays_carry_what_was_said_and_run_at_the_stated_rate(
    traces: tuple[list[Trace], list[str]],
) -> None:
    """Issue 55: a 4042-tick clip replayed in 3 s, without the robot's words."""
    from toyroom.rating.drawing import FRAMES_PER_SECOND, captions, frames

    robot = traces[0][0]
    last = robot.ticks[-1][0].tick
    said = [c["text"] for c in captions(robot, last)]
    assert any(t.startswith("Robot to Agent 1, of the skate") for t in said), said
    assert any(t.startswith("Robot asks Agent 2 for the") for t in said), said
    assert all(c["tick"] <= 100 for c in captions(robot, 100)), "captions past the question's tick"
    for rate in (1.0, 4.0):
        shown = frames(robot, 300, rate)
        seconds = 300 * robot.info.tick_seconds / rate
        assert abs(len(shown) - seconds * FRAMES_PER_SECOND) <= 2, (
            f"300 ticks at {rate}x: about {seconds * FRAMES_PER_SECOND:.0f} frames expected, got {len(shown)}"
        )
        assert shown[-1]["tick"] == 300, shown[-1]["tick"]
