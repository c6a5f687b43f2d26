"""The rating server without a browser: answers survive a restart (the CSV is read back and
the links stay valid), a file of another kind is refused, and ``--listen`` on every interface
prints the lab address and a warning; an answer is taken only after consent and only to the
question the page shows, a body nested too deep is answered 400, and ``toyroom rate`` refuses
participant ids a link cannot carry and an ``--out`` that is no file (issue 64)."""

from __future__ import annotations

import json
import logging
import socket
import struct
import subprocess
import sys
import urllib.error
import urllib.request
from pathlib import Path

import pytest

from bridge.recording import read_trace
from tests.toyroom.devtools import wait_until
from toyroom.rating import AnswerBook, QuestionsError, RatingServer, RatingSettings, load_study
from toyroom.rating.server import read_or_make_secret
from toyroom.rating.serving import ServerLimits

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


def send(server: RatingServer, body: dict[str, object], what: str = "answer") -> tuple[int, str]:
    """POST ``body`` to p1's ``what`` (``answer`` or ``consent``) from the page's origin: the
    reply's status and text."""
    url = server.link("p1").replace("/p1?", f"/p1/{what}?")
    request = urllib.request.Request(
        url,
        data=json.dumps(body).encode(),
        headers={"Origin": server.url, "Content-Type": "application/json"},
    )
    try:
        with urllib.request.urlopen(request, timeout=10) as reply:
            return int(reply.status), reply.read().decode()
    except urllib.error.HTTPError as err:
        return err.code, err.read().decode()


def post(server: RatingServer, body: dict[str, object]) -> int:
    return send(server, body)[0]


def load_page(server: RatingServer) -> str:
    """p1's page, as their browser loads it (the server records the question it shows)."""
    with urllib.request.urlopen(server.link("p1"), timeout=10) as reply:
        return str(reply.read().decode())


def agree(server: RatingServer) -> None:
    """p1 agrees on their page, which then loads their question."""
    assert send(server, {"consent": True}, "consent") == (200, "consent recorded")
    load_page(server)


def test_answers_survive_a_restart(recordings: list[Path], tmp_path: Path) -> None:
    with RatingServer(settings(recordings, tmp_path)) as first:
        agree(first)
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
        "robot,100,A1,utility,skate,0.2500,online,p1,q1",
        "robot,100,A1,utility,ball,0.7500,online,p1,q1",
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
        "toyroom",
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


Q1 = {"question": "q1", "values": {"skate": 0.25, "ball": 0.75}}
Q2 = {"question": "q2", "values": {"skate": 0.5, "ball": 0.5}}


def test_an_answer_before_consent_is_refused(recordings: list[Path], tmp_path: Path) -> None:
    with RatingServer(settings(recordings, tmp_path)) as server:
        before = (tmp_path / "a.csv").read_bytes()
        load_page(server)  # the page shows q1, but p1 has not agreed
        status, text = send(server, Q1)
        assert (status, "has not agreed" in text) == (409, True), (
            f"expected 409 saying p1 has not agreed, got {status} {text!r}"
        )
        assert (tmp_path / "a.csv").read_bytes() == before, "a refused answer must write nothing"
        agree(server)
        assert send(server, Q1) == (200, "saved"), "after consent the shown question's answer is saved"


def test_an_answer_to_a_question_not_shown_is_refused(recordings: list[Path], tmp_path: Path) -> None:
    with RatingServer(settings(recordings, tmp_path)) as server:
        before = (tmp_path / "a.csv").read_bytes()
        assert send(server, {"consent": True}, "consent")[0] == 200
        never_loaded = send(server, Q1)  # no page loaded: no question shown
        assert never_loaded[0] == 409 and "no question" in never_loaded[1], (
            f"expected 409 (the page shows no question), got {never_loaded}"
        )
        load_page(server)  # shows q1
        last_first = send(server, Q2)
        assert last_first[0] == 409 and "(question q1)" in last_first[1], (
            f"expected 409 naming q1 as the question shown, got {last_first}"
        )
        assert (tmp_path / "a.csv").read_bytes() == before, "refused answers must write nothing"
        assert send(server, Q1) == (200, "saved")
        assert send(server, Q2)[0] == 409, "q2 is not shown until the page is loaded again"
        assert "question 2 of 2" in load_page(server)
        assert send(server, Q2) == (200, "saved")
    rows = (tmp_path / "a.csv").read_text().splitlines()[1:]
    assert [r.rsplit(",", 1)[1] for r in rows] == ["q1", "q1", "q2", "q2"], f"rows written: {rows}"


def rate_command(recordings: list[Path], folder: Path, *extra: str) -> list[str]:
    (folder / "q.toml").write_text(QUESTIONS, encoding="utf-8")
    command = [sys.executable, "-m", "toyroom", "rate", *map(str, recordings)]
    return command + ["--questions", str(folder / "q.toml"), *extra]


@pytest.mark.parametrize("ids", ["ann,..", ".", "p.1"])
def test_rate_refuses_ids_a_link_cannot_carry(recordings: list[Path], tmp_path: Path, ids: str) -> None:
    out = tmp_path / "a.csv"
    done = subprocess.run(
        rate_command(recordings, tmp_path, "--out", str(out), "--participants", ids),
        capture_output=True,
        text=True,
        timeout=120,
    )
    lines = done.stderr.strip().splitlines()
    assert done.returncode == 2 and len(lines) == 1 and "--participants" in lines[0], (
        f"expected exit 2 and one line naming --participants, got {done.returncode}: {done.stderr!r}"
    )
    assert not out.exists() and not out.with_name("a.csv.secret").exists(), "a refused start wrote files"


def test_rate_refuses_an_out_that_is_no_file(recordings: list[Path], tmp_path: Path) -> None:
    secret = tmp_path / "secret"  # so that the old code made no /dev/full.secret
    for out in ("/dev/full", str(tmp_path)):
        done = subprocess.run(
            rate_command(recordings, tmp_path, "--out", out, "--secret", str(secret)),
            capture_output=True,
            text=True,
            timeout=120,
        )
        lines = done.stderr.strip().splitlines()
        assert done.returncode == 2 and len(lines) == 1 and f"{out}: cannot keep the answers" in lines[0], (
            f"--out {out}: expected exit 2 and one line, got {done.returncode}: {done.stderr[-2000:]!r}"
        )
    assert not secret.exists(), "a refused --out should make no secret"


# ----- the server's limits: bad headers, idle and vanished clients, too many connections -----

CLIENT_WAIT = 30.0
"""Seconds a test's socket waits for the server: generous, for a loaded 2-core machine."""


def raw_request(server: RatingServer, head: str, body: bytes = b"") -> socket.socket:
    """A socket that has sent an answer's POST with the headers ``head`` (and ``body``)."""
    host = server.url.removeprefix("http://")
    path = server.link("p1").replace("/p1?", "/p1/answer?").removeprefix(server.url)
    sock = socket.create_connection(("127.0.0.1", int(host.rsplit(":", 1)[1])), timeout=CLIENT_WAIT)
    request = f"POST {path} HTTP/1.1\r\nHost: {host}\r\nOrigin: {server.url}\r\n{head}\r\n"
    sock.sendall(request.encode() + body)
    return sock


def read_all(sock: socket.socket) -> bytes:
    """Everything the server sends until it closes the connection."""
    data = b""
    while chunk := sock.recv(65536):
        data += chunk
    return data


def test_a_bad_content_length_is_answered_400_in_one_line(
    recordings: list[Path],
    tmp_path: Path,
    caplog: pytest.LogCaptureFixture,
    capfd: pytest.CaptureFixture[str],
) -> None:
    caplog.set_level(logging.INFO, logger="toyroom.rating")
    with RatingServer(settings(recordings, tmp_path)) as server:
        with raw_request(server, "Content-Length: abc\r\n", b'{"question": "q1"}') as sock:
            reply = read_all(sock).decode(errors="replace")
    assert reply.startswith("HTTP/1.0 400") and "Content-Length 'abc'" in reply, (
        f"expected a 400 naming Content-Length 'abc', got {reply[:300]!r}"
    )
    lines = [r.getMessage() for r in caplog.records if "Content-Length" in r.getMessage()]
    assert len(lines) == 1 and "Traceback" not in capfd.readouterr().err, (
        f"expected one log line, got {lines}"
    )


def test_an_idle_connection_is_closed_after_the_idle_timeout(recordings: list[Path], tmp_path: Path) -> None:
    limits = ServerLimits(idle_timeout=0.5, max_connections=4)
    with RatingServer(settings(recordings, tmp_path), limits=limits) as server:
        port = int(server.url.rsplit(":", 1)[1])
        with socket.create_connection(("127.0.0.1", port), timeout=CLIENT_WAIT) as idle:
            try:
                closed = idle.recv(1) == b""
            except TimeoutError:
                closed = False
    assert closed, (
        f"expected the server to close a silent connection after 0.5 s; still open after {CLIENT_WAIT} s"
    )


def test_connections_beyond_the_limit_are_answered_503(recordings: list[Path], tmp_path: Path) -> None:
    limits = ServerLimits(idle_timeout=120.0, max_connections=2)
    with RatingServer(settings(recordings, tmp_path), limits=limits) as server:
        port = int(server.url.rsplit(":", 1)[1])
        idle = [socket.create_connection(("127.0.0.1", port), timeout=CLIENT_WAIT) for _ in range(2)]
        with socket.create_connection(("127.0.0.1", port), timeout=CLIENT_WAIT) as third:
            busy = read_all(third).decode(errors="replace")
        assert busy.startswith("HTTP/1.0 503"), (
            f"expected the third connection answered 503, got {busy[:200]!r}"
        )
        for sock in idle:
            sock.close()

        def served() -> int:
            try:
                with urllib.request.urlopen(server.link("p1"), timeout=CLIENT_WAIT) as reply:
                    return int(reply.status)
            except urllib.error.HTTPError as err:
                return 0 if err.code == 503 else err.code

        assert wait_until(served, CLIENT_WAIT, "a page once the idle connections closed") == 200


def test_a_client_that_goes_away_is_one_line_without_a_traceback(
    recordings: list[Path],
    tmp_path: Path,
    caplog: pytest.LogCaptureFixture,
    capfd: pytest.CaptureFixture[str],
) -> None:
    caplog.set_level(logging.INFO, logger="toyroom.rating")
    with RatingServer(settings(recordings, tmp_path)) as server:
        sock = raw_request(server, "Content-Length: 1000\r\n", b'{"question": ')
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
        sock.close()  # a reset mid-body, as a closed tab or a dropped network does
        gone = wait_until(
            lambda: [r.getMessage() for r in caplog.records if "went away" in r.getMessage()],
            CLIENT_WAIT,
            "a log line saying the client went away",
        )
    err = capfd.readouterr().err
    assert len(gone) == 1 and "Traceback" not in err, f"expected one line and no traceback: {gone}\n{err}"


def test_a_body_nested_too_deep_is_answered_400(
    recordings: list[Path], tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    caplog.set_level(logging.INFO, logger="toyroom.rating")
    body = b"[" * 30_000 + b"]" * 30_000  # 60 KB, under the 64 KB a body may have
    with RatingServer(settings(recordings, tmp_path)) as server:
        with raw_request(server, f"Content-Length: {len(body)}\r\n", body) as sock:
            reply = read_all(sock).decode(errors="replace")
    assert reply.startswith("HTTP/1.0 400") and "nested too deep" in reply, (
        f"expected a 400 saying the JSON is nested too deep, got {reply[:300]!r}"
    )
    failures = [r.getMessage() for r in caplog.records if r.levelno >= logging.ERROR]
    assert failures == [], f"a deep body should fail no request; logged {failures}"


def test_a_partial_last_row_is_dropped_on_start(
    recordings: list[Path], tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    """A row cut off by a full disk (as an older version left one) is dropped when the file is
    read back, so the next answer is a line of its own instead of glued onto it."""
    caplog.set_level(logging.WARNING, logger="toyroom.rating")
    header = "episode,tick,person,quantity,target,value,estimate,participant,question\r\n"
    whole = (
        "robot,100,A1,utility,skate,0.2500,online,p9,q1\r\nrobot,100,A1,utility,ball,0.7500,online,p9,q1\r\n"
    )
    (tmp_path / "a.csv").write_text(header + whole + "robot,150,A2,util", encoding="utf-8", newline="")
    study = settings(recordings, tmp_path).study
    book = AnswerBook(tmp_path / "a.csv")
    assert book.add("p1", study.questions[0], {"skate": 0.25, "ball": 0.75}), "p1's answer should be saved"
    text = (tmp_path / "a.csv").read_bytes().decode("utf-8")
    expected = header + whole + whole.replace("p9", "p1")
    assert text == expected, (
        f"expected the partial row dropped and the new rows whole:\n{expected!r}\ngot\n{text!r}"
    )
    dropped = [r.getMessage() for r in caplog.records if "partial last row" in r.getMessage()]
    assert len(dropped) == 1 and "robot,150,A2,util" in dropped[0], f"expected one warning, got {dropped}"
