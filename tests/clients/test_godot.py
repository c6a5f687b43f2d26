"""The Godot add-on (``clients/godot/``) run headless under Debian's ``godot3-server``
(Godot 3.2, installed by ``make test``), through a real ``toyroom gateway`` and loopback Zenoh:
its TileMap scene export gives every bundled map back; its sample passes ``toyroom conform
--strict`` in lock-step and in real time; the brain, unchanged, reproduces the paper's
Section V on it (the same assertions as ``tests/brain/test_section_v.py``) and completes
``paper-robot`` with the robot's give succeeding; killed and restarted under a running
brain, it is handled as the other engines are (``tests/faults/test_engine_killed.py``, with
the grid and C# engines)."""

from __future__ import annotations

import importlib.util
import subprocess
import sys
import uuid
from collections.abc import Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from types import ModuleType

import pytest
from support import EventsCsv, GatewayProcess, GodotEngineProcess, MindCsv, toyroom_run

from toyroom.gateway import godot

TESTS = Path(__file__).resolve().parents[1]
SCENARIOS = TESTS.parent / "sim2d" / "scenarios"
SECTION_V = ("paper-1", "paper-2", "paper-3", "sally-anne")
RUNS = (*SECTION_V, "paper-robot")
REALTIME = ("--realtime", "7")
"""The real-time sample's clock: a tick of 0.7 s every 0.1 s of wall time. The people's scripts
are then over (they stand still) by the time the kit's say and ask checks walk the robot to
A1; with 0.1 s ticks (`--tick-seconds 0.1`) A1 may still be walking then, and those checks
skip ("out of earshot")."""


def _section_v() -> ModuleType:
    """``tests/brain/test_section_v.py``, for its assertions (under a name of its own, so that
    nothing of it is collected twice)."""
    spec = importlib.util.spec_from_file_location("godot_section_v", TESTS / "brain" / "test_section_v.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """``toyroom run --engine godot`` on Section V's scenarios (the robot observing) and on
    ``paper-robot`` (the robot acting), three at a time (on two cores, more is slower); each
    run's folder."""

    def one(scenario: str) -> Path:
        observe = ("--robot", "observe") if scenario in SECTION_V else ()
        out = tmp_path_factory.mktemp(f"godot-{scenario}")
        return toyroom_run(out, scenario, "--engine", "godot", "--no-live", *observe)

    with ThreadPoolExecutor(3) as pool:
        return dict(zip(RUNS, pool.map(one, RUNS), strict=True))


def test_the_tilemap_export_gives_every_map_back(runs: dict[str, Path], tmp_path: Path) -> None:
    """Each run's exported scene built into a TileMap and described from its tiles again."""
    for scenario, out in runs.items():
        (tmp_path / f"{scenario}.json").write_bytes((out / "scenarios" / f"{scenario}.json").read_bytes())
    command = [godot.godot(), "--path", str(godot.PROJECT), "--", "--check-tilemap", str(tmp_path)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=60)
    got = result.stdout + result.stderr
    assert result.returncode == 0, f"expected every map back from its TileMap, got:\n{got}"
    assert f"{len(RUNS)} of {len(RUNS)} scenes the same" in result.stdout, result.stdout


def test_section_v_holds_on_the_godot_engine(runs: dict[str, Path]) -> None:
    section_v = _section_v()
    minds = {scenario: MindCsv(runs[scenario] / "mind.csv") for scenario in SECTION_V}
    for scenario in ("paper-1", "paper-2", "paper-3"):
        for step in ("2", "3", "4", "5"):
            section_v.test_before_the_swap_the_skate_is_in_s1_and_the_ball_unknown(minds, scenario, step)
    for scenario in ("paper-1", "paper-2"):
        section_v.test_scenarios_1_and_2_find_the_ball_then_the_skate(minds, scenario)
    section_v.test_scenario_1_step_8_is_unchanged_and_still_prefers_the_skate(minds)
    section_v.test_scenario_2_changes_its_mind_to_the_ball(minds)
    section_v.test_scenario_3_looks_for_the_ball_in_s2_then_s1(minds)
    assert section_v.sally_checks(minds["sally-anne"], runs["sally-anne"] / "trace.jsonl") == []
    section_v.test_sallys_false_belief_has_a_probability(minds)
    mind = minds["paper-1"]
    early = [mind.false_belief("A1", mind.tick("A1", step), "ball") for step in ("0", "1", "2")]
    late = mind.false_belief("A1", mind.tick("A1", "5"), "ball")
    assert max(early) < 0.2 and late > 0.8, (
        f"paper-1: P(false belief about the ball) at steps 0-2 {early} (expected < 0.2: ignorance) "
        f"and at step 5 {late:.3f} (expected > 0.8)"
    )


def test_paper_robot_completes_with_the_swap_and_the_give(runs: dict[str, Path]) -> None:
    events = EventsCsv(runs["paper-robot"] / "events.csv")
    swap = events.find(actor="A2", kind="give", item="skate", target="robot")
    assert swap, "expected A2 to hand the skate to the robot (the swap), found no such give"
    gave = events.find(actor="robot", kind="give", item="skate", target="A1")
    assert gave, "expected the robot to give the skate to A1, found no such give event"
    done = events.find(actor="robot", kind="command", detail__contains="give succeeded")
    assert done, "expected a robot give command to succeed in events.csv, found none"
    failed = events.find(actor="robot", kind="command", detail__contains="failed")
    assert not failed, f"expected no robot command to fail, got {failed}"


def conform(world: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "toyroom", "conform", "--world", world, "--strict", "--timeout", "5"],
        capture_output=True,
        text=True,
        timeout=240,
    )


@pytest.fixture(params=["lockstep", "realtime"])
def sample(request: pytest.FixtureRequest, tmp_path: Path) -> Iterator[tuple[str, str]]:
    """The sample on ``paper-robot`` through a gateway, in either clock: (world, clock)."""
    clock = request.param
    world = f"godot-{clock}-{uuid.uuid4().hex[:6]}"
    args = REALTIME if clock == "realtime" else ()
    with GatewayProcess(world) as gateway, GodotEngineProcess(gateway.url, tmp_path, "paper-robot", *args):
        yield world, clock


def test_the_sample_passes_conform_strict(sample: tuple[str, str]) -> None:
    world, clock = sample
    result = conform(world)
    summary = result.stdout.strip().splitlines()[-1] if result.stdout.strip() else "(nothing)"
    got = result.stdout + result.stderr
    assert result.returncode == 0, f"{clock}: expected conform --strict to pass, got:\n{got}"
    assert " 0 skipped, 0 failed" in summary, f"{clock}: expected no skip and no failure, got {summary}"
    other = "lock-step" if clock == "realtime" else "real time"
    assert f"the clock runs in {other}" not in result.stdout, f"{clock}: conform saw the other clock:\n{got}"
