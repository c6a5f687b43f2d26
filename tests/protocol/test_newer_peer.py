"""Open vocabularies against a real peer of a newer minor version: the grid engine with
``--newer`` speaks protocol 1.99 and sends a capability, an item shape, a region kind, an
event kind and a state field that 1.1 does not know. The brain, unchanged, infers exactly
what it infers from the 1.1 engine, keeps the unknown event in its recording, and warns
once per unknown value; the conformance kit passes it; and sim2d, sent a command of a kind
it does not know, fails that command with a reason instead of dropping it."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import uuid
from pathlib import Path

import pytest
from support import EngineProcess, GridEngineProcess, run_brain

from bridge import Bridge
from bridge.handshake import handshake
from bridge.recording.mcap import read_mcap
from protocol import (
    CommandState,
    CommandStatus,
    EngineInfo,
    ItemShape,
    RegionKind,
    UnknownAction,
    decode,
    encode,
    unknown_action,
)
from protocol.robot import RobotCommand

SCENARIO = "paper-2"


def brain_on_grid(tmp_path: Path, *flags: str) -> tuple[Path, str]:
    """The brain's outputs and log of ``paper-2`` on the grid engine with ``flags``."""
    world = f"newer-{uuid.uuid4().hex[:8]}"
    out = tmp_path / ("newer" if flags else "current")
    with GridEngineProcess(world, "--scenario", SCENARIO, "--robot", "observe", *flags):
        brain = run_brain(
            world,
            "--scenario",
            SCENARIO,
            "--robot",
            "observe",
            "--out",
            str(out),
            "--record",
            str(out / "run.mcap"),
        )
    assert brain.returncode == 0, f"the brain failed on the grid engine {flags}:\n{brain.stderr[-3000:]}"
    return out, brain.stderr


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, tuple[Path, str]]:
    root = tmp_path_factory.mktemp("newer-peer")
    return {"current": brain_on_grid(root), "newer": brain_on_grid(root, "--newer")}


def test_the_brain_infers_the_same_from_a_newer_peer(runs: dict[str, tuple[Path, str]]) -> None:
    current, newer = (runs[k][0] / "mind.csv" for k in ("current", "newer"))
    a, b = current.read_text().splitlines(), newer.read_text().splitlines()
    assert len(a) > 100 and a == b, (
        f"mind.csv differs: {len(a)} rows from the 1.1 engine, {len(b)} from the 1.99 one; first "
        f"difference: {next(((x, y) for x, y in zip(a, b, strict=False) if x != y), None)}"
    )


def test_unknown_values_are_warned_about_once_each(runs: dict[str, tuple[Path, str]]) -> None:
    log = runs["newer"][1]
    for vocabulary, value in [
        ("Capability", "teleport"),
        ("ItemShape", "cup"),
        ("RegionKind", "closet"),
        ("EventKind", "sneeze"),
    ]:
        said = log.count(f"a peer sent {vocabulary} '{value}'")
        assert said == 1, f"expected one warning about {vocabulary} {value!r}, got {said}:\n{log[-2000:]}"
    assert "minor versions differ" in log, log[-2000:]
    assert "invalid" not in log.lower(), f"a message from the newer peer was refused:\n{log[-2000:]}"


def test_the_recording_keeps_the_unknown_event(runs: dict[str, tuple[Path, str]]) -> None:
    kinds = [
        json.loads(r.data).get("kind")
        for r in read_mcap(runs["newer"][0] / "run.mcap")
        if r.key.endswith("engine/events")
    ]
    assert "sneeze" in kinds, f"the recording's event kinds: {sorted(set(map(str, kinds)))}"


def test_conform_passes_a_newer_peer() -> None:
    world = f"newer-conform-{uuid.uuid4().hex[:6]}"
    with GridEngineProcess(world, "--scenario", "paper-robot", "--newer"):
        result = subprocess.run(
            [sys.executable, "-m", "toyroom", "conform", "--world", world, "--timeout", "10"],
            capture_output=True,
            text=True,
            timeout=300,
        )
    assert result.returncode == 0, result.stdout + result.stderr


def test_known_values_decode_to_members_and_unknown_ones_stay_strings() -> None:
    info = decode(encode(decode((Path("protocol/examples/engine_info.json")).read_bytes(), EngineInfo)))
    assert all(isinstance(r.kind, RegionKind) for r in info.scene.regions)
    raw = json.loads(Path("protocol/examples/engine_info.json").read_text())
    raw["protocol"] = "1.99"
    raw["scene"]["items"][0]["shape"] = "cup"
    raw["capabilities"].append("teleport")
    newer = decode(json.dumps(raw).encode(), EngineInfo)
    assert newer.scene.items[0].shape == "cup" and not isinstance(newer.scene.items[0].shape, ItemShape)
    assert "teleport" in newer.capabilities
    again = json.loads(encode(newer))
    assert again["scene"]["items"][0]["shape"] == "cup" and "teleport" in again["capabilities"]


def test_sim2d_fails_a_command_of_an_unknown_kind(world: str) -> None:
    wave = unknown_action("wave", {"arm": "left"})
    command = RobotCommand(id="w1", robot="robot", action=wave)  # type: ignore[arg-type]
    assert isinstance(decode(encode(command)), RobotCommand)
    assert isinstance(decode(encode(command)).action, UnknownAction)
    got: list[CommandStatus] = []
    arrived = threading.Event()

    def on_status(status: CommandStatus, _: object) -> None:
        got.append(status)
        arrived.set()

    with EngineProcess(world, "--scenario", "paper-robot"), Bridge(world) as client:
        handshake(client, client="test", timeout=30.0)
        client.subscribe(client.keys.status("robot"), on_status, expected=CommandStatus)
        publisher = client.publisher(client.keys.command("robot"))
        assert publisher.wait_matched(10.0), "sim2d never subscribed to robot commands"
        publisher.put(command)
        assert arrived.wait(10.0), "sim2d never answered a command of an unknown kind"
    status = got[0]
    assert status.state is CommandState.FAILED and "unknown command kind 'wave'" in status.reason, status


def test_the_viewer_draws_an_unknown_shape_as_a_block(
    runs: dict[str, tuple[Path, str]], tmp_path: Path
) -> None:
    """The newer run's recording (its scene's items all of shape ``cup``) replayed into the
    viewer: the cups are drawn in the block's colour."""
    from tests.toyroom.view.test_view import pixels_of, shot_at
    from toyroom.view import ITEM_COLOURS

    image = shot_at(runs["newer"][0] / "run.mcap", 30, tmp_path / "view.png")
    block = ITEM_COLOURS[ItemShape.BLOCK]
    assert pixels_of(image, block) > 20, f"the cups were not drawn as blocks (no pixels of #{block:06x})"
