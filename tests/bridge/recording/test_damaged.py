"""Recordings that are missing, not recordings at all, or cut off, under one policy for both
formats: a missing file or garbage is one line naming the file (exit 2, nothing written); a
cut-off ``trace.jsonl`` or MCAP file is used as far as it can be read, with a warning naming
the byte offset where it broke and the ticks kept, and refused with ``--strict``. And
``toyroom infer`` writes ``events.csv`` as ``toyroom run`` does."""

from __future__ import annotations

import re
import subprocess
import sys
import uuid
from pathlib import Path

import pytest
from mcap.writer import Writer
from support import toyroom_run

WARNING = re.compile(r"unreadable from byte (\d+) of (\d+) \(.+\); kept ticks (\d+)-(\d+) \((\d+) messages")


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A real run of paper-2 (an observing robot), with its MCAP recording as run.mcap."""
    root = tmp_path_factory.mktemp("damaged")
    toyroom_run(
        root / "run", "paper-2", "--robot", "observe", "--no-live", "--record", str(root / "run.mcap")
    )
    return root


def toyroom(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "bridge", *map(str, args)], capture_output=True, text=True, timeout=240
    )


def cut(source: Path, target: Path, fraction: float) -> int:
    """Copy the first ``fraction`` of ``source`` to ``target``; the byte offset of the cut."""
    data = source.read_bytes()
    offset = int(len(data) * fraction)
    target.write_bytes(data[:offset])
    return offset


def last_tick(events_or_mind: Path) -> int:
    lines = events_or_mind.read_text().splitlines()[1:]
    return max(int(line.split(",", 1)[0]) for line in lines)


@pytest.mark.parametrize("name", ["run.mcap", "run/trace.jsonl"])
def test_a_cut_recording_is_used_up_to_the_break_with_a_warning(
    recorded: Path, tmp_path: Path, name: str
) -> None:
    whole = recorded / name
    damaged = tmp_path / f"half{whole.suffix}"
    offset = cut(whole, damaged, 0.5)
    out = tmp_path / "out"
    result = toyroom("infer", damaged, "--out", out)
    assert result.returncode == 0, f"a cut {name} was refused:\n{result.stderr[-2000:]}"
    found = WARNING.search(result.stderr)
    assert found is not None and str(damaged) in result.stderr, f"no warning with the break:\n{result.stderr}"
    broke, size, first, last, _ = map(int, found.groups())
    assert size == offset and offset - 20_000 < broke <= offset, (broke, offset)
    assert first == 0 and 20 < last < last_tick(recorded / "run" / "mind.csv"), (first, last)
    assert last_tick(out / "mind.csv") == last, "mind.csv does not end where the readable part ends"
    assert (out / "events.csv").is_file() and (out / "report.md").is_file()

    strict = tmp_path / "strict"
    refused = toyroom("infer", damaged, "--out", strict, "--strict")
    assert refused.returncode == 1 and WARNING.search(refused.stderr), refused.stderr
    assert "--strict" in refused.stderr and not strict.exists(), "--strict left outputs behind"


@pytest.mark.parametrize("command", ["infer", "replay"])
@pytest.mark.parametrize("kind", ["missing", "garbage", "empty"])
def test_no_recording_is_one_line_and_leaves_nothing(tmp_path: Path, command: str, kind: str) -> None:
    path = tmp_path / f"{kind}.mcap"
    if kind == "garbage":
        path.write_bytes(bytes(range(256)) * 40)
    elif kind == "empty":
        path.write_bytes(b"")
    out = tmp_path / "out"
    extra = (
        ["--out", str(out)] if command == "infer" else ["--world", f"w{uuid.uuid4().hex[:8]}", "--speed", "0"]
    )
    result = toyroom(command, path, *extra)
    says = {"missing": "no such file", "garbage": "not an MCAP recording", "empty": "an empty file"}[kind]
    assert result.returncode == 2, f"exit {result.returncode}:\n{result.stdout}\n{result.stderr}"
    line = f"toyroom {command}: {path}: {says}"
    assert result.stderr.count("\n") == 1 and result.stderr.startswith(line), result.stderr
    assert "Traceback" not in result.stderr and not out.exists(), "something was left behind"
    assert list(tmp_path.iterdir()) == ([path] if kind != "missing" else [])


def test_an_mcap_file_without_an_episode_is_named_and_nothing_is_left(tmp_path: Path) -> None:
    other = tmp_path / "other.mcap"
    with other.open("wb") as handle:
        writer = Writer(handle)
        writer.start(profile="", library="someone else")
        schema = writer.register_schema(name="note", encoding="jsonschema", data=b"{}")
        channel = writer.register_channel(topic="/notes", message_encoding="json", schema_id=schema)
        writer.add_message(channel_id=channel, log_time=1, data=b'{"text": "hello"}', publish_time=1)
        writer.finish()
    out = tmp_path / "out"
    result = toyroom("infer", other, "--out", out)
    assert result.returncode == 2 and result.stderr.startswith(
        f"toyroom infer: {other}: no engine handshake"
    ), result.stderr
    assert not out.exists(), f"infer left {sorted(p.name for p in out.iterdir())} behind"


def test_replay_warns_of_a_cut_recording_and_refuses_it_with_strict(recorded: Path, tmp_path: Path) -> None:
    damaged = tmp_path / "half.mcap"
    cut(recorded / "run.mcap", damaged, 0.4)
    world = ["--world", f"w{uuid.uuid4().hex[:8]}", "--speed", "0"]
    used = toyroom("replay", damaged, *world)
    assert used.returncode == 0 and WARNING.search(used.stderr), used.stderr
    refused = toyroom("replay", damaged, *world, "--strict")
    assert refused.returncode == 1 and WARNING.search(refused.stderr), refused.stderr
    assert "messages from" not in refused.stdout, "--strict still replayed the recording"


def test_infer_writes_the_runs_events_csv(recorded: Path, tmp_path: Path) -> None:
    out = tmp_path / "again"
    result = toyroom("infer", recorded / "run.mcap", "--out", out)
    assert result.returncode == 0, result.stderr
    inferred, live = ((d / "events.csv").read_text().splitlines() for d in (out, recorded / "run"))
    assert len(live) > 10 and inferred[0] == live[0]
    assert sorted(inferred) == sorted(live), "events.csv differs (two recorders may order a tick apart)"
