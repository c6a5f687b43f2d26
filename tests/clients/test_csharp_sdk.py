"""The C# SDK (clients/unity/) compiled with Mono's mcs and run under mono: its generated
message classes against every golden example, and an unknown action kind kept whole. (The
C# engine's conformance, Section V and restarts are in the tests of those.)"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
from support import golden_examples

from protocol import BY_TAG, decode
from protocol.examples import example_paths
from toyroom.gateway import csharp


@pytest.fixture(scope="module")
def built() -> dict[str, Path]:
    return csharp.build()


def test_the_sdk_and_its_sample_compile_without_warnings(built: dict[str, Path]) -> None:
    assert set(built) == {"Toyroom.dll", "GridEngine.exe", "RoundTrip.exe"}
    assert all(path.stat().st_size > 0 for path in built.values())
    assert all("Unity" not in path.parts for path in csharp.sdk_sources()), (
        "the Unity adapter needs UnityEngine"
    )


@pytest.fixture(scope="module")
def round_trip(built: dict[str, Path], tmp_path_factory: pytest.TempPathFactory) -> Path:
    """``RoundTrip.exe`` run once on the golden examples: the folder of what C# wrote back."""
    out = tmp_path_factory.mktemp("round-trip")
    folder = next(iter(example_paths().values())).parent
    command = ["mono", str(built["RoundTrip.exe"]), str(folder), str(out)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, f"RoundTrip.exe failed:\n{result.stdout}{result.stderr}"
    return out


def test_every_golden_example_survives_a_round_trip_through_csharp(round_trip: Path) -> None:
    golden = golden_examples()
    for tag in example_paths():
        written = (round_trip / f"{tag}.json").read_bytes()
        assert decode(written, BY_TAG[tag]) == golden[tag], f"{tag}: C# wrote {written.decode()[:400]}"
        assert b'""' not in written.replace(b'"reason":""', b"").replace(b'"detail":""', b""), (
            f"{tag}: an empty string where the protocol wants null: {written.decode()[:400]}"
        )


def test_an_unknown_action_kind_is_kept_whole(round_trip: Path) -> None:
    command = json.loads((round_trip / "unknown_action.json").read_text())
    assert command["action"] == {"kind": "teleport", "to": "S1"}, command
