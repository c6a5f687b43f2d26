"""MCAP recordings cut short, and one that mixes two worlds, read by ``toyroom infer``,
``toyroom replay --strict`` and ``toyroom fit`` (issue 64, items 12 and 13).

A file that starts with the MCAP magic but ends early is named as cut off, never as a
traceback nor as "not an MCAP recording": cut before its first whole message, it is one line
(exit 2); cut later (inside the footer, inside the closing magic), every whole message is
used with a warning saying the file was cut off and how many messages were kept, and
``--strict`` refuses it in one line (exit 1). A recording that holds the keys of two worlds
is refused in one line naming them (exit 2), with nothing written or published.
"""

from __future__ import annotations

import subprocess
import sys
import uuid
from pathlib import Path

import pytest
from mcap.reader import make_reader
from mcap.writer import Writer
from support import toyroom_run

pytestmark = pytest.mark.process


def toyroom(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "toyroom", *map(str, args)], capture_output=True, text=True, timeout=240
    )


def interleave(first: Path, second: Path, target: Path) -> None:
    """Write the messages of two MCAP files into ``target``, interleaved by the time since
    each file's first message (one channel per topic, as the recorder writes them)."""
    timed = []
    for source in (first, second):
        with source.open("rb") as handle:
            found = list(make_reader(handle).iter_messages(log_time_order=False))
        start = found[0][2].log_time
        timed += [(message.log_time - start, schema, channel, message) for schema, channel, message in found]
    with target.open("wb") as handle:
        writer = Writer(handle, use_chunking=False)
        writer.start(profile="", library="test")
        schemas: dict[tuple[str, bytes], int] = {}
        channels: dict[str, int] = {}
        for time, schema, channel, message in sorted(timed, key=lambda t: t[0]):
            assert schema is not None, f"a message on {channel.topic} without a schema"
            if (schema.name, schema.data) not in schemas:
                schemas[(schema.name, schema.data)] = writer.register_schema(
                    schema.name, schema.encoding, schema.data
                )
            if channel.topic not in channels:
                channels[channel.topic] = writer.register_channel(
                    channel.topic, channel.message_encoding, schemas[(schema.name, schema.data)]
                )
            writer.add_message(channels[channel.topic], time + 1, message.data, time + 1)
        writer.finish()


@pytest.fixture(scope="module")
def recorded(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Real runs of sally-anne and paper-1, each on its own world, recorded as sally-anne.mcap
    and paper-1.mcap, and mixed.mcap: the two interleaved."""
    root = tmp_path_factory.mktemp("cut")
    for scenario in ("sally-anne", "paper-1"):
        world = f"{scenario}-{uuid.uuid4().hex[:8]}"
        record = ["--no-live", "--world", world, "--record", str(root / f"{scenario}.mcap")]
        toyroom_run(root / scenario, scenario, *record)
    interleave(root / "sally-anne.mcap", root / "paper-1.mcap", root / "mixed.mcap")
    return root


def worlds_of(path: Path) -> list[str]:
    """The worlds (``toyroom/<world>/...``) of an MCAP file's channels."""
    with path.open("rb") as handle:
        summary = make_reader(handle).get_summary()
    assert summary is not None, f"{path} has no summary"
    return sorted({channel.topic.split("/")[1] for channel in summary.channels.values()})


def args_of(command: str, path: Path, out: Path, whole: Path) -> list[str | Path]:
    """The command line of ``command`` on ``path`` (``fit`` with ``whole`` as its second
    recording: a fit needs two)."""
    if command == "infer":
        return ["infer", path, "--out", out]
    if command.startswith("replay"):
        return ["replay", path, "--world", f"w{uuid.uuid4().hex[:8]}", "--speed", "0", *command.split()[1:]]
    fit = ["--params", "beta", "--grid", "beta=2", "--models", "graded", "--folds", "2", "--no-progress"]
    return ["fit", path, whole, *fit, "--out", out]


@pytest.mark.parametrize("command", ["infer", "replay", "replay --strict", "fit"])
def test_a_recording_of_two_worlds_is_refused_naming_them(
    recorded: Path, tmp_path: Path, command: str
) -> None:
    mixed = recorded / "mixed.mcap"
    worlds = worlds_of(mixed)
    assert len(worlds) == 2, f"expected the mixed file to hold two worlds, got {worlds}"
    out = tmp_path / "out"
    result = toyroom(*args_of(command, mixed, out, recorded / "sally-anne.mcap"))
    name = command.split()[0]
    line = f"toyroom {name}: {mixed}: mixes the messages of 2 worlds ("
    assert result.returncode == 2 and result.stderr.count("\n") == 1 and result.stderr.startswith(line), (
        f"expected exit 2 and one line starting {line!r}, got exit {result.returncode}:\n"
        f"{result.stdout[-1500:]}\n{result.stderr[-3000:]}"
    )
    assert all(repr(world) in result.stderr for world in worlds), (
        f"expected both worlds {worlds} named, got {result.stderr}"
    )
    assert result.stdout == "" and not out.exists(), (
        f"expected nothing written or replayed, got stdout {result.stdout[-500:]!r}, "
        f"out {sorted(p.name for p in out.iterdir()) if out.exists() else None}"
    )


CUTS = [1, 2, 7, 100, -1, -2, -3, -4, -5, -6, -7, -8, -9, -30]
"""How each copy is cut: n > 0, its first n bytes (inside the opening magic, or inside its
first records, before any message); n < 0, all but its last -n bytes (inside the closing
magic, inside the footer)."""


def cut_copy(source: Path, target: Path, cut: int) -> Path:
    data = source.read_bytes()
    target.write_bytes(data[:cut])
    return target


def whole_messages(path: Path) -> int:
    """How many messages the (whole) MCAP file holds, counted by the mcap library."""
    with path.open("rb") as handle:
        return sum(1 for _ in make_reader(handle).iter_messages(log_time_order=False))


CASES = [
    *(("infer", cut) for cut in CUTS),
    *(("replay --strict", cut) for cut in (1, 100, -1, -8, -9, -30)),
    *(("fit", cut) for cut in (2, 7, 100, -9, -30)),
]
"""Every cut for ``infer``; for ``replay --strict`` and ``fit`` (the same reader, tested at
every byte in ``tests/bridge/recording/test_cut_mcap.py``), a cut of each kind the issue named:
a run of process starts each, so the fast tier carries the rest."""


@pytest.mark.parametrize(
    ("command", "cut"), CASES, ids=[f"{c}-first-{n}" if n > 0 else f"{c}-less-last-{-n}" for c, n in CASES]
)
def test_a_cut_recording_is_named_as_cut_off(recorded: Path, tmp_path: Path, command: str, cut: int) -> None:
    whole = recorded / "sally-anne.mcap"
    path = cut_copy(whole, tmp_path / "cut.mcap", cut)
    out = tmp_path / "out"
    result = toyroom(*args_of(command, path, out, whole))
    said = f"exit {result.returncode}:\n{result.stdout[-1500:]}\n{result.stderr[-3000:]}"
    name = command.split()[0]
    assert "Traceback" not in result.stderr, f"expected no traceback, got {said}"
    if cut > 0:  # no whole message: one line, nothing written
        line = (
            f"toyroom {name}: {path}: an MCAP recording cut off at byte {cut}, before its first whole message"
        )
        assert result.returncode == 2 and result.stderr.count("\n") == 1 and result.stderr.startswith(line), (
            f"expected exit 2 and one line starting {line!r}, got {said}"
        )
        assert not out.exists(), f"expected nothing written, got {sorted(p.name for p in out.iterdir())}"
        return
    kept = f"({whole_messages(whole)} messages before it)"
    if command == "replay --strict":
        line = f"toyroom replay: refused: {path}: cut off: "
        assert result.returncode == 1 and result.stderr.count("\n") == 1 and result.stderr.startswith(line), (
            f"expected --strict to refuse the cut file (exit 1) in one line starting {line!r}, got {said}"
        )
        assert kept in result.stderr and "messages from" not in result.stdout, (
            f"expected every message counted as kept {kept!r} and none replayed, got {said}"
        )
        return
    warned = [line for line in result.stderr.splitlines() if f"{path}: cut off: " in line]
    assert result.returncode == 0 and len(warned) == 1 and kept in warned[0], (
        f"expected the cut file used (exit 0) with one warning that it is cut off and {kept!r}, got {said}"
    )
    report = (out / "report.md").read_text()
    assert "**The recording was cut off**" in report, (
        f"expected report.md to say the recording was cut off, got:\n{report[:800]}"
    )
