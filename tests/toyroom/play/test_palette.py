"""One colour per person across the study's pages (issue 55: A1 was orange on the play page
and blue on the rating page): the play page's layout colours are the rating page's."""

from __future__ import annotations

import subprocess
import sys

import msgspec

from protocol import AgentKind, Scene
from toyroom.play.palette import person_colours
from toyroom.rating.drawing import plan


def test_the_play_and_rating_pages_colour_each_person_alike() -> None:
    printed = subprocess.run(
        [sys.executable, "-m", "sim2d", "scene", "--scenario", "paper-robot"],
        capture_output=True, text=True, timeout=120, check=True,
    ).stdout  # fmt: skip
    scene = msgspec.json.decode(printed, type=Scene)
    people = [a.id for a in scene.agents if a.kind is AgentKind.PERSON]
    play = person_colours(people)
    rate = {a["id"]: a["colour"] for a in plan(scene)["agents"] if a["person"]}
    assert play == rate, f"play page {play}, rating page {rate}"
    assert len(set(play.values())) == len(people), f"two people share a colour: {play}"
