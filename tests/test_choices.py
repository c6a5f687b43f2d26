"""Every set of choices is one enum of ``protocol.choices``: each consumer's allowed values
are built from it (the brain's settings, the engine's generator and its command line, the
evaluation's conditions and ``toyroom eval``'s help), so a value added to an enum and
forgotten by one of them fails here."""

from __future__ import annotations

import argparse

import pytest

import protocol
from brain.__main__ import run_parser as brain_parser
from brain.robot.branches import POLICIES as TREE_POLICIES
from brain.robot.branches import build_tree
from brain.robotsettings import ROBOT_POLICIES, RobotSettings
from brain.settings import ALLOWED, ModelSettings
from protocol import (
    MAP_CYCLE,
    OBSERVING,
    EpisodeKind,
    EpisodeMap,
    Minds,
    Perception,
    Policy,
    RobotMode,
    TaskKind,
    task_of,
)
from sim2d.__main__ import build_parser as engine_parser
from sim2d.__main__ import generate_parser
from sim2d.generation import episodes as generator
from sim2d.generation import tasks as generated_tasks
from sim2d.scenario.scenario import load_scenario
from toyroom.bench import memory as memory_bench
from toyroom.cli.cli import build_parser
from toyroom.evaluation import conditions
from toyroom.evaluation import generation as evaluation_generation
from toyroom.evaluation.generation import MAPS


def _option(parser: argparse.ArgumentParser, flag: str, command: str | None = None) -> argparse.Action:
    """The action of ``flag`` (of subcommand ``command``, when given)."""
    if command is not None:
        subparsers = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        parser = subparsers.choices[command]
    return next(a for a in parser._actions if flag in a.option_strings)


def _help_lists(help_text: str, names: tuple[str, ...]) -> list[str]:
    """The names ``help_text`` leaves out."""
    return [name for name in names if name not in help_text]


def test_policies_are_built_from_the_enum() -> None:
    names = Policy.names()
    assert names == ("tom", "benefit", "tidy", "announce", "oracle"), names
    for consumer, values in {
        "brain.robotsettings.ROBOT_POLICIES": ROBOT_POLICIES,
        "brain.robot.branches.POLICIES": TREE_POLICIES,
        "toyroom.evaluation.conditions.POLICIES": conditions.POLICIES,
    }.items():
        assert values == names, f"{consumer} is {values}, expected {names}"
    for name in names:
        assert RobotSettings(policy=name).policy == name
        assert build_tree("robot", name) is not None
    assert OBSERVING not in names, f"{OBSERVING!r}, the observing run, is not a policy: {names}"
    with pytest.raises(ValueError, match="one of tom, benefit, tidy, announce, oracle"):
        RobotSettings(policy=OBSERVING)
    help_text = _option(build_parser(), "--policies", "eval").help or ""
    assert _help_lists(help_text, (*names, OBSERVING)) == [], help_text


def test_perceptions_are_built_from_the_enum() -> None:
    names = Perception.names()
    assert names == ("omniscient", "embodied"), names
    assert conditions.PERCEPTIONS == names, conditions.PERCEPTIONS
    assert ModelSettings().perception == Perception.OMNISCIENT.value
    for name in names:
        assert ModelSettings(perception=name).perception == name
        assert conditions.Condition(perception=name).perception == name
    assert ALLOWED["perception"] == "one of omniscient, embodied", ALLOWED["perception"]
    with pytest.raises(ValueError, match="perception='seeing'.*one of omniscient, embodied"):
        ModelSettings(perception="seeing")
    help_text = _option(build_parser(), "--perception", "eval").help or ""
    assert _help_lists(help_text, names) == [], help_text


@pytest.mark.parametrize(
    ("choices", "in_generator", "in_conditions", "flag"),
    [
        (Minds, generator.MINDS, conditions.MINDS, "--minds"),
        (EpisodeKind, generator.KINDS, conditions.KINDS, "--kind"),
    ],
)
def test_minds_and_episode_kinds_are_built_from_the_enum(
    choices: type[Minds] | type[EpisodeKind],
    in_generator: tuple[str, ...],
    in_conditions: tuple[str, ...],
    flag: str,
) -> None:
    names = choices.names()
    assert in_generator == names, f"sim2d.generation's {flag[2:]}: {in_generator}, expected {names}"
    assert in_conditions == names, f"the conditions' {flag[2:]}: {in_conditions}, expected {names}"
    engine = _option(generate_parser(), flag)
    assert tuple(engine.choices or ()) == names, f"sim2d generate {flag}: {engine.choices}, expected {names}"
    help_text = _option(build_parser(), flag, "eval").help or ""
    assert _help_lists(help_text, names) == [], help_text


def test_task_kinds_are_built_from_the_enum() -> None:
    names = TaskKind.names()
    assert names == ("moved", "hidden", "contested", "seen", "told", "overlooked", "stale"), names
    assert generated_tasks.TASKS == names, generated_tasks.TASKS
    assert conditions.TASK_KINDS == names, conditions.TASK_KINDS
    assert set(generated_tasks.BELIEF_TASKS) <= set(names), generated_tasks.BELIEF_TASKS
    assert generated_tasks.check_kinds(names) == names
    assert conditions.Condition(kind="tasks", tasks=names).tasks == names
    for help_text in (
        _option(generate_parser(), "--tasks").help or "",
        _option(build_parser(), "--tasks", "eval").help or "",
    ):
        assert ", ".join(names) in help_text, help_text


def test_the_generator_and_the_evaluation_draw_the_same_task_kinds() -> None:
    assert len(MAPS) == MAP_CYCLE, f"the evaluation cycles through {MAPS}, task_of through {MAP_CYCLE} maps"
    for kinds in ((), ("told", "overlooked", "stale"), ("moved", "seen")):
        condition = conditions.Condition(kind="tasks", tasks=kinds)
        ours = [condition.task_of(seed) for seed in range(1000, 1060)]
        theirs = [generated_tasks.task_of(seed, kinds or TaskKind.names()) for seed in range(1000, 1060)]
        assert ours == theirs, f"{kinds}: the evaluation reads {ours}, the generator builds {theirs}"
    assert conditions.Condition(kind="everyday").task_of(1000) is None
    drawn = [task_of(seed) for seed in range(6)]
    assert drawn == ["moved", "hidden", "contested", "told", "overlooked", "stale"], drawn


def test_the_robot_mode_is_one_enum_every_command_line_takes() -> None:
    names = RobotMode.names()
    assert names == ("act", "observe"), names
    assert (str(RobotMode.ACT), f"{RobotMode.OBSERVE}") == names, "a mode is written as its word"
    for command, parser, sub in (
        ("python -m sim2d", engine_parser(), None),
        ("python -m brain", brain_parser(), None),
        ("toyroom run", build_parser(), "run"),
    ):
        choices = tuple(_option(parser, "--robot", sub).choices or ())
        assert choices == names, f"{command} --robot takes {choices}, expected {names}"
    assert load_scenario("paper-robot").robot is RobotMode.ACT
    assert load_scenario("paper-1").robot is RobotMode.OBSERVE


def test_the_map_list_has_one_home_in_protocol() -> None:
    assert generator.MAPS is protocol.MAPS, "the generator keeps a map list of its own"
    assert evaluation_generation.MAPS is protocol.MAPS, "the evaluation keeps a map list of its own"
    assert protocol.MAPS == EpisodeMap.names() == ("paper", "house-a", "house-b"), protocol.MAPS
    assert MAP_CYCLE == len(protocol.MAPS)
    assert set(generator.ITEMS) == set(EpisodeMap), f"items per map: {generator.ITEMS}"
    assert set(generator.HOUSES) < set(EpisodeMap), f"generated houses: {generator.HOUSES}"
    assert [evaluation_generation.map_of(i) for i in range(4)] == ["paper", "house-a", "house-b", "paper"]
    assert set(memory_bench.HOUSES) <= set(EpisodeMap) and memory_bench.TASKS == TaskKind.names()
