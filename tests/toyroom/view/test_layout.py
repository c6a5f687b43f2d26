"""The view's layout and panel text, without a browser: the paper map fills most of the
reference frame beside the panel column, and the minds panel names each person's beliefs
and desire, false beliefs in red with where the item really is."""

from __future__ import annotations

import pytest

from protocol import AgentMind, ItemBelief, Mind, Prob, Scene
from sim2d.engine import Engine
from toyroom.view import PANEL_FRACTION, WINDOW, frame
from toyroom.view.colours import FALSE_TEXT
from toyroom.view.panel import legend_lines, likeliest, mind_lines
from toyroom.view.text import Span, fit_font


@pytest.fixture(scope="module")
def paper() -> tuple[Scene, Engine]:
    engine = Engine("paper-robot")
    return engine.scene(), engine


@pytest.mark.parametrize("scenario", ["paper-robot", "sally-anne", "food-trucks"])
def test_the_map_fills_its_part_of_the_frame(scenario: str) -> None:
    scene = Engine(scenario).scene()
    layout = frame(scene)
    width, height = WINDOW
    assert layout.map.width / width >= 0.7 or layout.map.height / height >= 0.7, layout.map
    assert layout.map.left + layout.map.width <= layout.panel.left, "the map runs under the panels"
    assert layout.panel.left >= width * (1 - PANEL_FRACTION) - 1e-9
    # the map's corners land on the grid's corners
    assert layout.point(layout.map.left, layout.map.top + layout.map.height) == pytest.approx(
        (scene.origin.x, scene.origin.y)
    )


def text_of(line: tuple[object, ...]) -> str:
    return "".join(part.text for part in line if isinstance(part, Span))


def test_the_minds_panel_names_beliefs_desires_and_false_beliefs(paper: tuple[Scene, Engine]) -> None:
    scene, engine = paper
    state = engine.state()  # the skate is with A1, the ball with A2
    a1 = AgentMind(
        agent="A1",
        beliefs=(
            ItemBelief("skate", (Prob("S1", 0.9), Prob("P2", 0.08), Prob("P1", 0.02))),
            ItemBelief("ball", (Prob("S2", 0.62), Prob("P2", 0.30), Prob("S1", 0.08))),
        ),
        preference=(Prob("skate", 0.95), Prob("ball", 0.03), Prob("out", 0.02)),
        false_beliefs=("skate",),
    )
    mind = Mind(episode=0, tick=42, agents=(a1,))
    lines = mind_lines(scene, state, mind)
    texts = [text_of(line) for line in lines]
    assert any("tick 42" in text for text in texts), texts
    assert "A1 · Agent 1" in texts, texts
    assert "  wants: skate 0.95" in texts, texts  # under LEAST_SHOWN: left out
    skate = next(line for line in lines if text_of(line).startswith("  skate:"))
    assert text_of(skate) == "  skate: S1 0.90, P2 0.08  ✗ with A1", text_of(skate)
    assert all(part.colour == FALSE_TEXT for part in skate if isinstance(part, Span)), "not in red"
    ball = next(line for line in lines if text_of(line).startswith("  ball:"))
    assert text_of(ball) == "  ball: S2 0.62, P2 0.30, S1 0.08", text_of(ball)
    assert all(part.colour != FALSE_TEXT for part in ball if isinstance(part, Span))
    assert "A2 · Agent 2" not in texts, "A2 is in no mind here, so not in the panel"


def test_the_legend_says_who_is_who(paper: tuple[Scene, Engine]) -> None:
    scene, _ = paper
    texts = " ".join(text_of(line) for line in legend_lines(scene))
    for words in ("A1 · Agent 1", "A2 · Agent 2", "robot", "skate (board)", "ball (ball)", "false belief"):
        assert words in texts, f"{words!r} not in the legend: {texts}"
    assert fit_font(legend_lines(scene), 250, 400, 14) >= 12, "the legend would be written too small"


def test_likeliest_keeps_the_first_and_the_likely() -> None:
    assert likeliest((Prob("a", 0.01), Prob("b", 0.02))) == "b 0.02"
    assert likeliest(()) == "-"
