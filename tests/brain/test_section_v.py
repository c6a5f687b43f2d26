"""The paper's Section V, asserted from ``mind.csv`` of real runs: the engine and the brain
as separate processes over loopback Zenoh, in lock-step (p_smoothed unless said)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from support import MindCsv, toyroom_run

PAPER = ("paper-1", "paper-2", "paper-3")


@pytest.fixture(
    scope="module",
    params=[
        ("sim2d", "graded"),
        ("grid", "graded"),
        ("grid+gateway", "graded"),
        ("csharp", "graded"),
        ("sim2d", "point"),
    ],
    ids="-".join,
)
def runs(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory) -> dict[str, MindCsv]:
    """Runs on every engine (the brain, unchanged, must reproduce Section V on each): sim2d, the
    grid engine over Zenoh and through ``toyroom gateway`` (a WebSocket), and the C# SDK's
    engine under Mono (always through the gateway), with the default graded beliefs, and with
    the paper's point beliefs (``--set belief_model=point``)."""
    engine, belief_model = request.param
    engine_args = ("--engine", "grid", "--gateway") if engine == "grid+gateway" else ("--engine", engine)
    out = {}
    for scenario in (*PAPER, "sally-anne"):
        # the robot only watches: the statements are about what an observer infers
        directory = toyroom_run(
            tmp_path_factory.mktemp(f"{engine}-{belief_model}-{scenario}"),
            scenario,
            *("--robot", "observe", *engine_args, "--set", f"belief_model={belief_model}"),
        )
        for name in ("mind.csv", "beliefs.png", "preferences.png", "report.md", "trace.jsonl"):
            assert (directory / name).stat().st_size > 0, f"{scenario}: {name} is missing or empty"
        used = (directory / "settings.toml").read_text()
        assert f'belief_model = "{belief_model}"' in used, f"{scenario}: settings.toml says\n{used}"
        out[scenario] = MindCsv(directory / "mind.csv")
    return out


@pytest.mark.parametrize("scenario", PAPER)
@pytest.mark.parametrize("step", ["2", "3", "4", "5"])
def test_before_the_swap_the_skate_is_in_s1_and_the_ball_unknown(
    runs: dict[str, MindCsv], scenario: str, step: str
) -> None:
    mind = runs[scenario]
    t = mind.tick("A1", step)
    skate = mind.belief("A1", t, "skate", "S1")
    assert skate >= 0.8, f"{scenario} step {step}: P(skate in S1) = {skate:.3f}, expected >= 0.8"
    s2, p2 = mind.belief("A1", t, "ball", "S2"), mind.belief("A1", t, "ball", "P2")
    assert s2 + p2 >= 0.8, f"{scenario} step {step}: ball mass on S2+P2 = {s2 + p2:.3f}, expected >= 0.8"
    assert max(s2, p2) <= 0.9, (
        f"{scenario} step {step}: ball S2 {s2:.3f}, P2 {p2:.3f}: neither should pass 0.9"
    )


@pytest.mark.parametrize("scenario", ["paper-1", "paper-2"])
def test_scenarios_1_and_2_find_the_ball_then_the_skate(runs: dict[str, MindCsv], scenario: str) -> None:
    mind = runs[scenario]
    t6, t7 = mind.tick("A1", "6"), mind.tick("A1", "7")
    assert mind.belief("A1", t6, "ball", "S1") >= 0.8
    assert mind.belief("A1", t6, "skate", "S1") <= 0.2
    assert mind.belief("A1", t7, "skate", "P2") >= 0.8
    assert mind.belief("A1", t7, "ball", "S1") >= 0.8
    skate, ball = mind.preference("A1", t6, "skate"), mind.preference("A1", t6, "ball")
    assert skate > ball, f"{scenario} step 6: preference skate {skate:.3f} should be above ball {ball:.3f}"


def test_scenario_1_step_8_is_unchanged_and_still_prefers_the_skate(runs: dict[str, MindCsv]) -> None:
    mind = runs["paper-1"]
    t7, t8 = mind.tick("A1", "7"), mind.tick("A1", "8")
    for item in ("skate", "ball"):
        for location in ("P1", "S1", "S2", "P2"):
            before, after = mind.belief("A1", t7, item, location), mind.belief("A1", t8, item, location)
            assert abs(before - after) < 0.05, (
                f"P({item} in {location}) moved from {before:.3f} to {after:.3f}"
            )
    assert mind.preference("A1", t8, "skate") > mind.preference("A1", t8, "ball")


def test_scenario_2_changes_its_mind_to_the_ball(runs: dict[str, MindCsv]) -> None:
    mind = runs["paper-2"]
    t9 = mind.tick("A1", "9")
    assert mind.belief("A1", t9, "ball", "P1") >= 0.8
    ball, skate = mind.preference("A1", t9, "ball"), mind.preference("A1", t9, "skate")
    assert ball > skate, f"step 9: preference ball {ball:.3f} should be above skate {skate:.3f}"


def test_scenario_3_looks_for_the_ball_in_s2_then_s1(runs: dict[str, MindCsv]) -> None:
    mind = runs["paper-3"]
    t6, t7 = mind.tick("A1", "6"), mind.tick("A1", "7")
    assert mind.belief("A1", t6, "ball", "S2") <= 0.2
    assert mind.belief("A1", t6, "skate", "P2") >= 0.8
    assert mind.belief("A1", t7, "ball", "S1") >= 0.8
    assert mind.preference("A1", t6, "ball") > mind.preference("A1", t6, "skate")


def _false_beliefs(trace: Path, agent: str) -> dict[int, tuple[str, ...]]:
    flags = {}
    for line in trace.read_text().splitlines():
        record = json.loads(line)
        if record["key"].endswith("/brain/mind"):
            for mind in record["payload"]["agents"]:
                if mind["agent"] == agent:
                    flags[record["payload"]["tick"]] = tuple(mind["false_beliefs"])
    return flags


def sally_checks(mind: MindCsv, trace: Path) -> list[str]:
    """What fails of the Sally-Anne test (an empty list: passed)."""
    problems = []
    moved, back = mind.tick("anne", "moved"), mind.tick("sally", "back")
    basket = mind.belief("sally", moved, "marble", "basket", "p_online")
    if basket < 0.8:
        problems.append(f"after Anne's move, P(marble in basket) online = {basket:.3f} < 0.8")
    flags = _false_beliefs(trace, "sally")
    if "marble" not in flags.get(moved, ()):
        problems.append(f"no false-belief flag on the marble after Anne's move (flags: {flags.get(moved)})")
    box = mind.belief("sally", back, "marble", "box", "p_online")
    if box < 0.8 or "marble" in flags.get(back, ()):
        problems.append(f"after Sally sees the box, P(box) = {box:.3f}, flags {flags.get(back)}")
    return problems


def test_sally_anne(runs: dict[str, MindCsv]) -> None:
    assert sally_checks(runs["sally-anne"], runs["sally-anne"].path.parent / "trace.jsonl") == []


def test_sallys_false_belief_has_a_probability(runs: dict[str, MindCsv]) -> None:
    """``false_belief`` rows: near 0 while Sally sees the marble in the basket, near 1 once Anne
    has moved it unseen, near 0 again once Sally sees it in the box."""
    mind = runs["sally-anne"]
    dropped, moved, back = (
        mind.tick("sally", "basket"),
        mind.tick("anne", "moved"),
        mind.tick("sally", "back"),
    )
    for tick, low, what in (
        (dropped, True, "put in the basket"),
        (moved, False, "moved"),
        (back, True, "seen"),
    ):
        p = mind.false_belief("sally", tick, "marble")
        assert (p < 0.1) if low else (p > 0.9), f"marble {what} (tick {tick}): P(false belief) = {p:.3f}"


def test_ignorance_is_not_a_false_belief(runs: dict[str, MindCsv], request: pytest.FixtureRequest) -> None:
    """Scenario 1: at steps 0-2 A1 does not know whether the ball is in S2 or P2 (it is in one
    of them): ignorance, not a false belief (P < 0.2). By step 5 the ball has been taken to S1
    while she was out: a false belief (P > 0.8). The point model, where each person is certain
    of one world, cannot tell the two apart (0.5-0.8 at steps 0-2)."""
    _, belief_model = request.node.callspec.params["runs"]
    mind = runs["paper-1"]
    early = [mind.false_belief("A1", mind.tick("A1", step), "ball") for step in ("0", "1", "2")]
    late = mind.false_belief("A1", mind.tick("A1", "5"), "ball")
    assert late > 0.8, f"step 5: P(false belief about the ball) = {late:.3f}, expected > 0.8"
    if belief_model == "graded":
        assert max(early) < 0.2, f"steps 0-2: P(false belief) = {early}, expected < 0.2 (ignorance)"
    else:
        assert min(early) >= 0.4, f"steps 0-2 on the point model: {early} (expected it to confuse the two)"


def test_true_belief_baseline_fails_sally_anne(tmp_path: Path) -> None:
    out = toyroom_run(tmp_path, "sally-anne", "--observer", "truebelief", "--robot", "observe")
    problems = sally_checks(MindCsv(out / "mind.csv"), out / "trace.jsonl")
    assert problems, "an observer that assumes people know the true world should fail the Sally-Anne test"
    assert any("P(marble in basket)" in p for p in problems)


def test_recorded_run_infers_the_same_mind(tmp_path: Path) -> None:
    import subprocess
    import sys

    live = toyroom_run(tmp_path / "live", "paper-2")
    again = tmp_path / "again"
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "infer", str(live / "trace.jsonl"), "--out", str(again)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert (again / "mind.csv").read_text() == (live / "mind.csv").read_text()
    assert (again / "report.md").read_text() == (live / "report.md").read_text()
