"""``toyroom play``'s command line: bad input is one line naming what is wrong (exit 2),
and serving beyond loopback prints the address with a warning."""

from __future__ import annotations

import subprocess
import sys

import pytest


def _play(*args: str) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, "-m", "toyroom", "play", "--listen", "127.0.0.1:0", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize(
    ("args", "expected"),
    [
        (("--scenario", "nope"), "--scenario nope: "),
        (("--as", "A7"), "--as A7: no such person in 'paper-robot' (people: A1, A2)"),
        (("--participants", "0"), "--participants must be at least 1, got 0"),
        (("--participants", "ann,ann"), "--participants: give a count or distinct ids"),
        (("--rate", "0"), "--rate must be > 0, got 0.0"),
        (("--listen", "nope"), "--listen takes HOST:PORT"),
    ],
)
def test_bad_input_is_named(args: tuple[str, ...], expected: str) -> None:
    result = _play(*args)
    assert result.returncode == 2, f"exit {result.returncode}, want 2: {result.stdout}{result.stderr}"
    assert expected in result.stderr and "Traceback" not in result.stderr, result.stderr


def test_a_lab_network_address_is_printed_with_a_warning() -> None:
    command = [sys.executable, "-m", "toyroom", "play", "--listen", "0.0.0.0:0", "--participants", "ann,bob"]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert process.stderr is not None and process.stdout is not None
        warning = process.stderr.readline()
        lines = [process.stdout.readline() for _ in range(4)]  # the scenario, the study's terms, two links
        links = [line for line in lines if line.startswith("toyroom play: participant")]
    finally:
        process.terminate()
        process.wait(timeout=30)
    assert "warning: serving on 0.0.0.0:0 (http://" in warning and "other machines can reach it" in warning, (
        warning
    )
    assert [line.split(":")[0:2] for line in links] == [
        ["toyroom play", " participant ann"],
        ["toyroom play", " participant bob"],
    ], links
    assert all("/play/" in line and "?token=" in line for line in links), links
