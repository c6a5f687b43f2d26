"""The `toyroom` command line."""

from __future__ import annotations

import argparse
import ast
import csv
import os
import subprocess
import sys
from pathlib import Path

import pytest
from support import toyroom_run

from protocol import Mind, decode
from protocol.schema import write_schemas
from toyroom.cli.commands.doctor import run_doctor


def test_doctor_passes_on_this_install(world: str) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "doctor", "--world", world],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, f"doctor failed:\n{result.stdout}\n{result.stderr}"
    assert "all checks passed" in result.stdout
    for tag in ("state", "engine_info", "robot_command", "mind"):
        assert tag in result.stdout


def test_bad_world_name_is_a_clear_error() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "doctor", "--world", "no/slashes"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2 and "world name must be" in result.stderr, result.stderr


def test_doctor_warns_on_stale_schemas_without_failing(world: str, tmp_path: Path, capsys) -> None:
    write_schemas(tmp_path)
    state = tmp_path / "state.json"
    state.write_text(state.read_text().replace('"minimum": 0', '"minimum": 1'))
    code = run_doctor(world, repeats=2, schema_dir=tmp_path)
    printed = capsys.readouterr().out
    assert code == 0, f"doctor failed on stale schemas alone (expected a warning):\n{printed}"
    assert "warning" in printed and "state.json" in printed, printed


def _toyroom(*args: str, timeout: float = 60) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "COLUMNS": "200"}  # help text unwrapped
    return subprocess.run(
        [sys.executable, "-m", "toyroom", *args], capture_output=True, text=True, timeout=timeout, env=env
    )


def _parsers() -> dict[str, argparse.ArgumentParser]:
    """Every parser behind ``toyroom``: its own, each command's, and the nodes' it runs."""
    import brain.__main__
    import sim2d.__main__
    import toyroom.view
    from toyroom.cli.cli import NODES, build_parser

    top = build_parser()
    found = {"toyroom": top}
    for action in top._actions:
        if isinstance(action, argparse._SubParsersAction):
            found |= {f"toyroom {n}": p for n, p in action.choices.items() if n not in NODES}
    found |= {
        "toyroom sim": sim2d.__main__.build_parser(),
        "toyroom generate": sim2d.__main__.generate_parser(),
        "toyroom brain": brain.__main__.run_parser(),
        "toyroom infer (brain)": brain.__main__.infer_parser(),
        "toyroom view": toyroom.view.build_parser(),
    }
    return found


def test_every_option_has_help() -> None:
    missing = [
        f"{name}: {'/'.join(action.option_strings) or action.dest}"
        for name, parser in _parsers().items()
        for action in parser._actions
        if not isinstance(action, argparse._SubParsersAction | argparse._HelpAction)
        and not (action.help or "").strip()
    ]
    assert missing == [], f"options without help text: {missing}"


@pytest.mark.parametrize("command", ["sim", "brain", "view", "generate"])
def test_node_help_names_the_toyroom_command(command: str) -> None:
    result = _toyroom(command, "--help")
    assert result.returncode == 0, result.stderr
    assert result.stdout.startswith(f"usage: toyroom {command} "), result.stdout[:200]
    assert "(default: " in result.stdout, f"toyroom {command} --help shows no defaults:\n{result.stdout}"


def test_help_shows_defaults() -> None:
    result = _toyroom("run", "--help")
    for shown in ("(default: paper-robot)", "(default: btom)", "(default: 10.0)"):
        assert shown in result.stdout, f"`toyroom run --help` lacks {shown}:\n{result.stdout}"


@pytest.mark.parametrize(
    "args",
    [
        ("--log-level", "DEBUG", "sim", "--list"),
        ("sim", "--list", "--log-level", "DEBUG"),
        ("--log-level", "debug", "schema", "--check"),
        ("schema", "--check", "--log-level", "WARNING"),
    ],
    ids=" ".join,
)
def test_global_flags_before_or_after_the_command(args: tuple[str, ...]) -> None:
    result = _toyroom(*args)
    assert result.returncode == 0, f"toyroom {' '.join(args)} exited {result.returncode}: {result.stderr}"
    assert "Traceback" not in result.stderr, result.stderr


def test_a_bad_log_level_is_named() -> None:
    result = _toyroom("--log-level", "LOUD", "schema", "--check")
    assert result.returncode == 2 and "LOUD" in result.stderr, result.stderr


def test_generate_is_a_toyroom_command(tmp_path: Path) -> None:
    result = _toyroom("generate", "--map", "house-a", "--seed", "4", "--out", str(tmp_path))
    assert result.returncode == 0, result.stderr
    assert Path(result.stdout.strip()) == tmp_path / "gen-house-a-s4.toml", result.stdout


def test_observer_names_are_written_once() -> None:
    """Only protocol/mind.py spells out the observer names; everything else asks it."""
    root = Path(__file__).resolve().parents[3]
    names = {"btom", "truebelief", "perceptonly"}
    found = []
    for package in ("protocol", "bridge", "brain", "sim2d"):
        for path in sorted((root / package).rglob("*.py")):
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.Constant) and node.value in names:
                    found.append(f"{path.relative_to(root)}:{node.lineno} {node.value!r}")
    elsewhere = [f for f in found if not f.startswith("protocol/mind.py:")]
    assert elsewhere == [], f"observer names written outside protocol/mind.py: {elsewhere}"


def test_run_writes_the_shadow_observers_minds(tmp_path: Path) -> None:
    out = toyroom_run(tmp_path / "run", "sally-anne", "--no-live", "--shadow", "perceptonly")
    minds = [decode(line, Mind) for line in (out / "minds-perceptonly.jsonl").read_bytes().splitlines()]
    ticks = sorted(int(row["tick"]) for row in csv.DictReader((out / "mind.csv").open(newline="")))
    assert [m.tick for m in minds] == list(range(ticks[0], ticks[-1] + 1)), (
        f"expected one perceptonly mind per tick {ticks[0]}..{ticks[-1]}, got ticks {[m.tick for m in minds]}"
    )


def test_console_script_points_at_the_cli() -> None:
    """``toyroom`` (pyproject's [project.scripts]) names a function that exists."""
    import importlib
    import tomllib

    root = Path(__file__).resolve().parents[3]
    scripts = tomllib.loads((root / "pyproject.toml").read_text())["project"]["scripts"]
    module, _, function = scripts["toyroom"].partition(":")
    assert callable(getattr(importlib.import_module(module), function, None)), (
        f"pyproject's toyroom = {scripts['toyroom']!r} names no function"
    )


def test_a_bad_eval_batch_is_named(tmp_path: Path) -> None:
    result = _toyroom("eval", "--batch", "0", "--episodes", "1", "--out", str(tmp_path))
    assert result.returncode == 2 and "--batch must be at least 1" in result.stderr, result.stderr
    assert not (tmp_path / "metrics.json").exists(), "nothing ran"
