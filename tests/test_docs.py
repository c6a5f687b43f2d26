"""The README and docs/*.md: every relative link resolves to a file, and every ``toyroom``
command they quote (inline code or a code block) parses with the CLI's parser."""

from __future__ import annotations

import argparse
import re
import shlex
from collections.abc import Iterator
from pathlib import Path

import pytest

from toyroom.cli.cli import NODE_HELP, build_parser, global_parser

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
FENCE = re.compile(r"^```[^\n]*\n(.*?)^```", re.M | re.S)
INLINE = re.compile(r"`([^`]+)`")
PLACEHOLDERS = (
    "FILE DIR2 DIR NAME W S N T K B X R M L SCENE OBSERVER VALUE HOST PORT ROUTER"
    " RECORDINGS LO HI V1 V2 URL RATE"
)
PLACEHOLDER = re.compile(r"\b(?:" + "|".join(PLACEHOLDERS.split()) + r")\b")
"""Upper-case placeholders of the docs, replaced by a dummy value before parsing."""


def _line(text: str, offset: int) -> int:
    return text.count("\n", 0, offset) + 1


def _links(page: Path) -> Iterator[tuple[int, str]]:
    text = page.read_text(encoding="utf-8")
    for match in LINK.finditer(FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)):
        yield _line(text, match.start()), match.group(1)


def _commands(page: Path) -> Iterator[tuple[int, str]]:
    """``(line, command)`` for each ``toyroom ...`` command quoted on ``page``."""
    text = page.read_text(encoding="utf-8")
    for block in FENCE.finditer(text):
        start = _line(text, block.start(1))
        pending: list[str] = []
        first = 0
        for number, raw in enumerate(block.group(1).splitlines(), start):
            line = raw.strip()
            if not pending and not line.startswith("toyroom "):
                continue
            first = first or number
            pending.append(line.removesuffix("\\").strip())
            if not line.endswith("\\"):
                yield first, " ".join(pending)
                pending, first = [], 0
    prose = FENCE.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    for match in INLINE.finditer(prose):
        code = " ".join(match.group(1).split())
        if code.startswith("toyroom "):
            yield _line(text, match.start()), code


def _subcommands() -> dict[str, argparse.ArgumentParser]:
    """The ``toyroom`` subcommands' parsers, by name."""
    for action in build_parser()._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    raise AssertionError("toyroom has no subcommands")


def _problem(command: str) -> str | None:
    """Why ``command`` does not parse, or ``None`` (also for one that is skipped)."""
    if "..." in command or "[" in command or "|" in command or " #" in command:
        return None  # a synopsis or an excerpt, not a command
    if re.match(r"toyroom [\w-]+:", command):
        return None  # a message the command prints (`toyroom eval: stopped by SIGINT: ...`)
    argv = shlex.split(PLACEHOLDER.sub("1", re.sub(r"<[^>]*>", "1", command)))[1:]
    _, rest = global_parser().parse_known_args(argv)
    if not rest or rest[0] == "COMMAND":
        return None
    if rest[0] in NODE_HELP:
        return None  # a node command: its options are the node's own parser's
    if all(token.startswith("-") for token in rest[1:]):
        # a mention (`toyroom infer`, `toyroom run --out`): the command and its options exist
        options = _subcommands()[rest[0]]._option_string_actions
        unknown = [token for token in rest[1:] if token not in options]
        return f"no option {unknown[0]!r}" if unknown else None
    try:
        build_parser().parse_args(argv)
    except SystemExit as exit_:
        return f"argparse exit {exit_.code}"
    return None


def test_every_relative_link_resolves() -> None:
    broken = []
    for page in PAGES:
        for line, target in _links(page):
            if re.match(r"^[a-z]+:", target) or target.startswith("#"):
                continue
            path = target.split("#", 1)[0]
            if not (page.parent / path).exists():
                broken.append(f"{page.relative_to(ROOT)}:{line}: link {target!r} names no file")
    assert not broken, "\n".join(broken)


def test_every_quoted_command_parses(capsys: pytest.CaptureFixture[str]) -> None:
    bad = []
    for page in PAGES:
        for line, command in _commands(page):
            problem = _problem(command)
            if problem is not None:
                error = capsys.readouterr().err.strip().splitlines()
                why = error[-1] if error else problem
                bad.append(f"{page.relative_to(ROOT)}:{line}: {command!r}: {why}")
    assert not bad, "\n".join(bad)


def test_every_quoted_command_exists() -> None:
    """Commands checked by name only (node commands, mentions) must name a real command."""
    known = set(_subcommands())
    unknown = []
    for page in PAGES:
        for line, command in _commands(page):
            _, rest = global_parser().parse_known_args(command.split()[1:])
            if rest and re.fullmatch(r"[a-z][a-z0-9-]*", rest[0]) and rest[0] not in known:
                unknown.append(f"{page.relative_to(ROOT)}:{line}: {command!r}: no command {rest[0]!r}")
    assert not unknown, "\n".join(unknown)


PYTHON = re.compile(r"^```python\n(.*?)^```", re.M | re.S)
EXAMPLES = sorted((ROOT / "examples").glob("*.py"))


def _stripped(text: str) -> list[str]:
    return [line.strip() for line in text.splitlines() if line.strip()]


def test_every_python_block_is_part_of_an_example_the_tests_run() -> None:
    """A ``python`` block of the docs is a run of lines of one of ``examples/*.py`` (indents
    aside), which ``tests/examples`` runs: no snippet the tests never run."""
    examples = {path.name: _stripped(path.read_text(encoding="utf-8")) for path in EXAMPLES}
    unrun = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for block in PYTHON.finditer(text):
            lines = _stripped(block.group(1))
            n = len(lines)
            if not any(
                lines == source[i : i + n] for source in examples.values() for i in range(len(source))
            ):
                unrun.append(f"{page.relative_to(ROOT)}:{_line(text, block.start())}")
    assert unrun == [], f"python blocks that are no part of examples/ ({sorted(examples)}): {unrun}"
