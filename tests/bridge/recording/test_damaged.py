"""Recordings that are missing, not recordings at all, or cut off, under one policy for both
formats: a missing file or garbage is one line naming the file (exit 2, nothing written); a
cut-off ``trace.jsonl`` or MCAP file is used as far as it can be read, with a warning naming
the byte offset where it broke and the ticks kept, and refused with ``--strict``. And
``toyroom infer`` writes ``events.csv`` as ``toyroom run`` does."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import uuid
from pathlib import Path

import pytest
from mcap.reader import make_reader
from mcap.writer import Writer
from support import golden_examples, toyroom_run

from bridge import Bridge
from protocol import encode
from tests.toyroom.devtools import wait_until

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
        [sys.executable, "-m", "toyroom", *map(str, args)], capture_output=True, text=True, timeout=240
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
        f"toyroom infer: {other}: not a toyroom recording: none of its topics is a toyroom key"
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


# ----- damage inside a recording, foreign recordings ---------------------------------------

DAMAGED_TICK = 50
"""The tick whose state the damaged copies spoil."""


def spoiled(source: Path, target: Path, how: str) -> bytes:
    """Copy the MCAP ``source`` to ``target`` with the state of :data:`DAMAGED_TICK` spoiled
    (``tick``: its tick the string 'abc'; ``nan``: a person's x NaN); the spoiled payload."""
    with source.open("rb") as handle:
        reader = make_reader(handle)
        records = list(reader.iter_messages(log_time_order=False))
    bad = b""
    with target.open("wb") as handle:
        writer = Writer(handle, use_chunking=False)
        writer.start(profile="", library="test")
        schemas: dict[int, int] = {}
        channels: dict[int, int] = {}
        for schema, channel, message in records:
            if schema is not None and schema.id not in schemas:
                schemas[schema.id] = writer.register_schema(schema.name, schema.encoding, schema.data)
            if channel.id not in channels:
                sid = schemas[schema.id] if schema is not None else 0
                channels[channel.id] = writer.register_channel(channel.topic, channel.message_encoding, sid)
            data = message.data
            payload = json.loads(data)
            if channel.topic.endswith("/engine/state") and payload["tick"] == DAMAGED_TICK and not bad:
                if how == "tick":
                    payload["tick"] = "abc"
                else:
                    payload["agents"][0]["x"] = float("nan")
                data = bad = json.dumps(payload).encode()  # NaN written as the bare word NaN
            writer.add_message(channels[channel.id], message.log_time, data, message.publish_time)
        writer.finish()
    assert bad, f"no state of tick {DAMAGED_TICK} in {source}"
    return bad


DAMAGE = re.compile(
    r"damaged: dropped 1 message that cannot be decoded \(byte (\d+): engine/state tick (\S+): "
    r"(.+)\); kept ticks (\d+)-(\d+) \((\d+) messages\)"
)


@pytest.mark.parametrize(("how", "tick", "says"), [("tick", "'abc'", "$.tick"), ("nan", "50", "not a JSON")])
def test_an_undecodable_message_inside_is_named_and_refused_with_strict(
    recorded: Path, tmp_path: Path, how: str, tick: str, says: str
) -> None:
    damaged = tmp_path / "damaged.mcap"
    bad = spoiled(recorded / "run.mcap", damaged, how)
    out = tmp_path / "out"
    result = toyroom("infer", damaged, "--out", out)
    assert result.returncode == 0, (
        f"expected the damaged file used (exit 0), got {result.returncode}:\n{result.stderr}"
    )
    found = DAMAGE.search(result.stderr)
    assert found is not None and str(damaged) in result.stderr, (
        f"expected a warning naming the dropped state, got:\n{result.stderr}"
    )
    offset, named, reason, first, last, _ = found.groups()
    data = damaged.read_bytes()
    assert data[int(offset)] == 0x05 and bad in data[int(offset) : int(offset) + len(bad) + 64], (
        f"byte {offset} is not where the spoiled message's record starts"
    )
    assert named == tick and says in reason, f"expected tick {tick} and {says!r} named, got {found.group(0)}"
    assert int(first) == 0 and int(last) > DAMAGED_TICK, (
        f"expected the ticks around the damage kept: {first}-{last}"
    )
    report = (out / "report.md").read_text()
    assert "**The recording was damaged**" in report.split("\n## ", 1)[0], (
        f"expected report.md to say first that the recording was damaged, got:\n{report[:800]}"
    )
    mind_ticks = {int(line.split(",", 1)[0]) for line in (out / "mind.csv").read_text().splitlines()[1:]}
    assert DAMAGED_TICK not in mind_ticks and DAMAGED_TICK + 1 in mind_ticks, "the dropped tick was inferred"

    strict = tmp_path / "strict"
    refused = toyroom("infer", damaged, "--out", strict, "--strict")
    assert refused.returncode == 1 and DAMAGE.search(refused.stderr), (
        f"expected --strict to refuse the damaged file (exit 1) with the warning, got {refused.returncode}:\n"
        f"{refused.stderr}"
    )
    assert not strict.exists(), "--strict left outputs behind"
    assert f"refused: {damaged}: damaged: " in refused.stderr, (
        f"expected the refusal to say the file is damaged (not cut off):\n{refused.stderr}"
    )


def write_mcap(path: Path, messages: list[tuple[str, bytes]]) -> None:
    """An MCAP file of ``(topic, JSON payload)``, one channel per topic."""
    with path.open("wb") as handle:
        writer = Writer(handle)
        writer.start(profile="", library="someone else")
        schema = writer.register_schema(name="thing", encoding="jsonschema", data=b"{}")
        channels: dict[str, int] = {}
        for time, (topic, data) in enumerate(messages, start=1):
            if topic not in channels:
                channels[topic] = writer.register_channel(
                    topic=topic, message_encoding="json", schema_id=schema
                )
            writer.add_message(channel_id=channels[topic], log_time=time, data=data, publish_time=time)
        writer.finish()


FOREIGN = [("a//b", b'{"x": 1}'), ("/camera/image", b'{"x": 2}'), ("toyroom/x//b", b'{"x": 3}')]


@pytest.mark.parametrize("command", ["replay", "infer", "fit"])
def test_a_foreign_mcap_is_refused_in_one_line_naming_it(tmp_path: Path, command: str) -> None:
    foreign = tmp_path / "foreign.mcap"
    write_mcap(foreign, FOREIGN)
    out = tmp_path / "out"
    extra = {
        "replay": ["--world", f"w{uuid.uuid4().hex[:8]}", "--speed", "0"],
        "infer": ["--out", out],
        "fit": ["--params", "beta", "--out", out, "--no-progress"],
    }[command]
    result = toyroom(command, foreign, *extra)
    line = f"{foreign}: not a toyroom recording: none of its topics is a toyroom key"
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and line in result.stderr, (
        f"expected exit 2 and one line saying {line!r}, got {result.returncode}:\n"
        f"{result.stdout}\n{result.stderr}"
    )
    assert "'a//b'" in result.stderr and "Traceback" not in result.stderr and not out.exists(), result.stderr


def test_replay_sends_only_toyroom_keys_of_a_mixed_recording(tmp_path: Path) -> None:
    """Foreign topics in a toyroom recording are named in a warning and never reach Zenoh."""
    golden = golden_examples()
    mixed = tmp_path / "mixed.mcap"
    ours = [
        ("toyroom/rec/engine/info", encode(golden["engine_info"])),
        ("toyroom/rec/engine/state", encode(golden["state"])),
    ]
    write_mcap(mixed, [ours[0], *FOREIGN, ours[1]])
    world = f"w{uuid.uuid4().hex[:8]}"
    heard: list[str] = []
    with Bridge(world) as bridge:
        subscriber = bridge.session.declare_subscriber(
            "**", lambda sample: heard.append(str(sample.key_expr))
        )
        result = toyroom("replay", mixed, "--world", world, "--speed", "0", "--wait-subscribers", "30")
        wait_until(lambda: f"toyroom/{world}/engine/state" in heard, 30, "the replayed state")
        subscriber.undeclare()
    assert result.returncode == 0 and "Traceback" not in result.stderr, (
        f"exit {result.returncode}:\n{result.stderr}"
    )
    assert "not replayed" in result.stderr and "'a//b'" in result.stderr, (
        f"expected the foreign topics named:\n{result.stderr}"
    )
    sent = sorted(key for key in heard if not key.startswith(f"toyroom/{world}/@"))
    assert sent == [f"toyroom/{world}/engine/state"], f"expected only the state on the wire, got {sent}"


def test_fit_names_the_users_file_of_an_mcap_without_an_episode(tmp_path: Path) -> None:
    lonely = tmp_path / "lonely.mcap"
    write_mcap(lonely, [("toyroom/rec/engine/state", encode(golden_examples()["state"]))])
    result = toyroom("fit", lonely, "--params", "beta", "--out", tmp_path / "out", "--no-progress")
    assert result.returncode == 2 and f"{lonely}: no engine handshake" in result.stderr, (
        f"expected exit 2 naming {lonely}, got {result.returncode}:\n{result.stderr}"
    )
