"""How a generated episode is drawn is one value (:class:`protocol.EpisodeSpec`) with one
default length (:data:`protocol.MAX_TICKS`), whichever side asks for the episode."""

from __future__ import annotations

import argparse
import tomllib
from pathlib import Path

from protocol import DEFAULT_EPISODE, MAX_TICKS, EpisodeKind, EpisodeSpec, Minds
from sim2d.__main__ import generate_parser
from sim2d.generation.episodes import write_episode, write_house_episode
from toyroom.cli.cli import build_parser
from toyroom.evaluation.conditions import Condition


def _default(parser: argparse.ArgumentParser, flag: str, command: str | None = None) -> object:
    if command is not None:
        subparsers = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parser = subparsers.choices[command]
    return next(a for a in parser._actions if flag in a.option_strings).default


def test_every_side_takes_the_one_default_length() -> None:
    assert DEFAULT_EPISODE == EpisodeSpec() and DEFAULT_EPISODE.max_ticks == MAX_TICKS == 1000
    assert _default(generate_parser(), "--max-ticks") == MAX_TICKS, "python -m sim2d generate"
    assert _default(build_parser(), "--max-ticks", "eval") == MAX_TICKS, "toyroom eval"


def test_an_episode_told_nothing_is_drawn_by_the_default_spec(tmp_path: Path) -> None:
    plain = write_episode(tmp_path / "plain", "paper", 3)
    told = write_episode(tmp_path / "told", "paper", 3, DEFAULT_EPISODE)
    assert plain.read_text() == told.read_text()
    assert tomllib.loads(plain.read_text())["max_ticks"] == MAX_TICKS
    house = write_house_episode(tmp_path / "house", 3, 2, 1, EpisodeSpec(max_ticks=77))
    assert tomllib.loads(house.read_text())["max_ticks"] == 77


def test_a_condition_asks_for_its_episodes_with_a_spec() -> None:
    condition = Condition(minds=Minds.RICH, kind=EpisodeKind.TASKS, tasks=("moved",), autonomy=("miss=0.1",))
    assert condition.spec(600) == EpisodeSpec(Minds.RICH, EpisodeKind.TASKS, 600, ("moved",), ("miss=0.1",))
    assert Condition().spec() == DEFAULT_EPISODE
