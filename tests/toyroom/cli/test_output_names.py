"""An output named in bytes that are not UTF-8 is refused in one line, exit 2, before anything
is written (issue 64, item 18): ``eval --out`` and ``run --out`` used to give tracebacks, and
``run`` left its ``.lock`` and ``.running-PID`` behind (the outputs name their folder in text:
notes, reports, the commands that recover a run). Real ``toyroom`` processes."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

BAD = b"r\xffsults"
"""A name that is no UTF-8 (0xff starts no UTF-8 character)."""


@pytest.fixture
def recordings(tmp_path: Path) -> Path:
    """A folder holding a recording for ``infer`` and ``fit`` to read (never reached)."""
    folder = tmp_path / "in"
    folder.mkdir()
    (folder / "run.mcap").write_bytes(b"")
    return folder


@pytest.mark.parametrize(
    "argv",
    [
        ["run", "--scenario", "sally-anne", "--no-live", "--out", "{bad}"],
        ["run", "--scenario", "sally-anne", "--no-live", "--out", "{ok}", "--record", "{bad}.mcap"],
        ["eval", "--episodes", "1", "--out", "{bad}"],
        ["infer", "{in}/run.mcap", "--out", "{bad}"],
        ["fit", "{in}/run.mcap", "{in}/run.mcap", "--out", "{bad}"],
    ],
    ids=lambda argv: " ".join(a for a in argv[:1]) + (" --record" if "--record" in argv else ""),
)
def test_an_output_name_that_is_not_utf8_is_refused_and_nothing_is_left(
    tmp_path: Path, recordings: Path, argv: list[str]
) -> None:
    bad = os.fsencode(tmp_path) + b"/" + BAD
    words = {b"{bad}": bad, b"{ok}": os.fsencode(tmp_path / "ok"), b"{in}": os.fsencode(recordings)}
    args = [os.fsencode(a) for a in argv]
    for word, value in words.items():
        args = [a.replace(word, value) for a in args]
    result = subprocess.run(
        [os.fsencode(sys.executable), b"-m", b"toyroom", *args], capture_output=True, timeout=120
    )
    stderr = result.stderr.decode(errors="replace")
    lines = stderr.strip().splitlines()
    assert result.returncode == 2 and len(lines) == 1, (
        f"expected exit 2 and one line, got {result.returncode}:\n{stderr}"
    )
    assert "the name is not valid UTF-8" in lines[0] and "\\xff" in lines[0], lines[0]
    left = sorted(os.listdir(os.fsencode(tmp_path)))
    assert left == [b"in"], f"a refused command left {left}"
