"""The rating server without a browser: answers survive a restart (the CSV is read back and
the links stay valid), a file of another kind is refused, and ``--listen`` on every interface
prints the lab address and a warning."""

from __future__ import annotations

import json
import subprocess
import sys
import urllib.request
from pathlib import Path

import pytest

from bridge.rating import QuestionsError, RatingServer, RatingSettings, load_study
from bridge.rating.server import read_or_make_secret
from bridge.recording import read_trace

QUESTIONS = """
[[questions]]
recording = "robot"
tick = 100
person = "A1"
ask = "desire"

[[questions]]
recording = "robot"
tick = 150
person = "A2"
ask = "desire"
"""


def settings(recordings: list[Path], folder: Path) -> RatingSettings:
    (folder / "q.toml").write_text(QUESTIONS, encoding="utf-8")
    traces = [read_trace(p) for p in recordings]
    study = load_study(folder / "q.toml", traces, [p.stem for p in recordings])
    secret = read_or_make_secret(folder / "a.csv.secret")
    return RatingSettings(study, traces, ("p1",), folder / "a.csv", secret)


def post(server: RatingServer, body: dict[str, object]) -> int:
    url = server.link("p1").replace("/p1?", "/p1/answer?")
    request = urllib.request.Request(
        url,
        data=json.dumps(body).encode(),
        headers={"Origin": server.url, "Content-Type": "application/json"},
    )
    with urllib.request.urlopen(request, timeout=10) as reply:
        return int(reply.status)


def test_answers_survive_a_restart(recordings: list[Path], tmp_path: Path) -> None:
    with RatingServer(settings(recordings, tmp_path)) as first:
        assert post(first, {"question": "q1", "values": {"skate": 0.25, "ball": 0.75}}) == 200
        link = first.link("p1")
    again = settings(recordings, tmp_path)
    with RatingServer(again) as second:
        assert second.link("p1").split("?")[1] == link.split("?")[1], (
            "a restart should keep the links' tokens"
        )
        question, answered = second.next_question("p1")
        assert (question.id if question else None, answered) == ("q2", 1), f"got {question}, {answered}"
        with urllib.request.urlopen(second.link("p1"), timeout=10) as reply:
            page = reply.read().decode()
        assert "question 2 of 2" in page, "the page after a restart should be the next question"
    lines = (tmp_path / "a.csv").read_text().splitlines()
    assert lines[1:] == [
        "robot,100,A1,desire,skate,0.2500,online,p1,q1",
        "robot,100,A1,desire,ball,0.7500,online,p1,q1",
    ]


def test_a_csv_of_another_kind_is_refused(recordings: list[Path], tmp_path: Path) -> None:
    (tmp_path / "a.csv").write_text("episode,tick,person,quantity,target,value\n", encoding="utf-8")
    with pytest.raises(QuestionsError, match="not an answers file of toyroom rate"):
        RatingServer(settings(recordings, tmp_path))


def test_listening_on_every_interface_warns(recordings: list[Path], tmp_path: Path) -> None:
    (tmp_path / "q.toml").write_text(QUESTIONS, encoding="utf-8")
    command = [
        sys.executable,
        "-m",
        "bridge",
        "rate",
        *map(str, recordings),
        "--questions",
        str(tmp_path / "q.toml"),
    ]
    command += ["--out", str(tmp_path / "a.csv"), "--listen", "http://0.0.0.0:0"]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert process.stdout is not None
    printed = []
    for line in process.stdout:
        printed.append(line)
        if line.startswith("toyroom rate: ready"):
            break
    process.terminate()
    _, err = process.communicate(timeout=20)
    assert "WARNING: listening on 0.0.0.0" in err, f"expected a warning, stderr was {err!r}"
    link = next(line for line in printed if "p1:" in line)
    assert "0.0.0.0" not in link and "token=" in link, (
        f"the link should name this machine's address: {link!r}"
    )
