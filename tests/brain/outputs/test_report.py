"""The figures and ``report.md`` say only what is there: ground truth where the scenario has
some (and at the steps it covers), legend entries for what is drawn, a caption on what the
steps are, and why a step's smoothed preference can contradict what the person does there."""

from __future__ import annotations

from pathlib import Path

import pytest

from brain.outputs.groundtruth import GroundTruth, TruthStep, load_ground_truth
from brain.outputs.mindtable import MindRow
from brain.outputs.report import draw_beliefs, draw_preferences, pyplot, report_markdown, write_report

LOCATIONS = ("P1", "S1", "S2")


def _rows(
    steps: list[tuple[int, str, dict[str, float], tuple[float, float], tuple[float, float], float]],
) -> list[MindRow]:
    """``mind.csv`` rows of one person A1 and one item, the skate: per step its tick, label,
    belief over LOCATIONS (online = smoothed), P(skate) and P(out) online and smoothed, and
    the log-evidence so far."""
    rows = []
    for tick, label, belief, online, smoothed, evidence in steps:
        for location in LOCATIONS:
            p = belief.get(location, 0.0)
            rows.append(MindRow(tick, label, "A1", "belief", "skate", location, p, p))
        rows.append(MindRow(tick, label, "A1", "preference", "skate", "", online[0], smoothed[0]))
        rows.append(MindRow(tick, label, "A1", "preference", "out", "", online[1], smoothed[1]))
        rows.append(MindRow(tick, label, "A1", "log_evidence", "", "", evidence, -9.0))
    return rows


# A1 plays with the skate in P1 at step 0 and then puts it away in S1 and leaves: online she
# wants the skate at step 0 (0.9), smoothed she does not (0.0).
PLAY_THEN_LEAVE = _rows(
    [
        (0, "", {"P1": 1.0}, (0.5, 0.5), (0.7, 0.3), 0.0),
        (1, "0", {"P1": 1.0}, (0.9, 0.1), (0.0, 1.0), -1.2),
        (40, "1", {"S1": 1.0}, (0.1, 0.9), (0.0, 1.0), -4.0),
    ]
)
# the first labelled step before any decision (log-evidence still 0)
FIRST_SIGHT = _rows(
    [
        (0, "start", {"P1": 0.5, "S1": 0.5}, (0.5, 0.5), (0.5, 0.5), 0.0),
        (9, "end", {"S1": 1.0}, (0.8, 0.2), (0.8, 0.2), -2.0),
    ]
)
BELIEFS_ONLY = GroundTruth(
    scenario="made-up",
    agent="A1",
    steps=(TruthStep("0", {"skate": {"P1": 1.0}}, {}),),
)


def _legend(ax: object) -> list[str]:
    return [text.get_text() for text in ax.get_legend().get_texts()]  # type: ignore[attr-defined]


def _caption(fig: object) -> str:
    return "\n".join(text.get_text() for text in fig.texts)  # type: ignore[attr-defined]


def test_without_ground_truth_the_figures_never_mention_it() -> None:
    beliefs = draw_beliefs(PLAY_THEN_LEAVE, "A1", None)
    preferences = draw_preferences(PLAY_THEN_LEAVE, "A1", None)
    try:
        for fig in (beliefs, preferences):
            words = " ".join([ax.get_title() for ax in fig.axes] + [_caption(fig)] + _legend(fig.axes[0]))
            assert "ground truth" not in words and "hatched" not in words, words
        assert _legend(beliefs.axes[0]) == ["P1", "S1"], "S2 has no bar: no legend entry"
    finally:
        pyplot().close("all")


def test_ground_truth_is_named_only_where_it_is_drawn() -> None:
    beliefs = draw_beliefs(PLAY_THEN_LEAVE, "A1", BELIEFS_ONLY)
    preferences = draw_preferences(PLAY_THEN_LEAVE, "A1", BELIEFS_ONLY)
    try:
        assert _legend(beliefs.axes[0]) == ["P1", "S1", "ground truth"]
        assert "hatched: ground truth" in beliefs.axes[0].get_title()
        assert "at steps 0." in _caption(beliefs), _caption(beliefs)
        # the truth gives no preference: no hatched bars, no legend entries, no word of it
        assert _legend(preferences.axes[0]) == ["out"], "skate's smoothed bars are all 0: not listed"
        assert "ground truth" not in preferences.axes[0].get_title() + _caption(preferences)
    finally:
        pyplot().close("all")


def test_sally_anne_preferences_list_no_ground_truth() -> None:
    """Sally-Anne's ground truth has beliefs only: its preference legend once listed
    'marble (ground truth)' and 'out (ground truth)' with no bars."""
    truth = load_ground_truth("sally-anne")
    assert truth is not None
    rows = [
        MindRow(tick, label, "sally", quantity, item, value, p, p)
        for tick, label in ((15, "play"), (49, "basket"))
        for quantity, item, value, p in (
            ("belief", "marble", "rug", 1.0),
            ("preference", "marble", "", 0.8),
            ("preference", "out", "", 0.2),
            ("log_evidence", "", "", -1.0),
        )
    ]
    fig = draw_preferences(rows, "sally", truth)
    try:
        assert _legend(fig.axes[0]) == ["marble", "out"]
    finally:
        pyplot().close("all")


def test_the_caption_says_what_the_steps_are() -> None:
    fig = draw_beliefs(PLAY_THEN_LEAVE, "A1", None)
    try:
        caption = _caption(fig).replace("\n", " ")
        assert "labelled waypoints A1 completed" in caption, caption
        assert "0 (tick 1), 1 (tick 40)" in caption, caption
        assert "step 0 already includes A1's first decision" in caption, caption
    finally:
        pyplot().close("all")
    fig = draw_beliefs(FIRST_SIGHT, "A1", None)
    try:
        assert "step start comes before any decision" in _caption(fig).replace("\n", " ")
    finally:
        pyplot().close("all")


def _flat(text: str) -> str:
    return " ".join(text.split())


def test_the_report_explains_a_smoothed_preference_that_contradicts_the_step() -> None:
    text = _flat(report_markdown(PLAY_THEN_LEAVE, "made-up", "A1", "btom"))
    assert "| step | tick |" in text and "| 0 | 1 |" in text, text
    assert "## Reading the steps" in text
    assert "step 0 at tick 1, step 1 at tick 40" in text, text
    assert "The estimates at step 0, the first, already weigh A1's first decision" in text, text
    assert "the one A1 acts on next" in text, text
    assert "at step 0, P(skate) is 0.90 online but 0.00 smoothed, which favours out (1.00)" in text, text


def test_the_report_says_when_the_first_step_comes_before_any_evidence() -> None:
    text = _flat(report_markdown(FIRST_SIGHT, "made-up", "A1", "btom"))
    assert (
        "The estimates at step start, the first, come before any decision of A1's: they are the prior" in text
    )
    assert "change of mind" not in text, "online and smoothed agree here: nothing to explain"


@pytest.mark.parametrize(
    ("truth", "says"),
    [
        (None, "No ground truth for this scenario: the figures show the model alone."),
        (BELIEFS_ONLY, "hatched beside the model in the figures: beliefs at steps 0."),
    ],
)
def test_the_report_says_what_the_ground_truth_covers(
    truth: GroundTruth | None, says: str, tmp_path: Path
) -> None:
    write_report(PLAY_THEN_LEAVE, "made-up", "btom", truth, tmp_path)
    text = (tmp_path / "report.md").read_text()
    assert says in text, text
    assert (tmp_path / "beliefs.png").stat().st_size > 0 and (tmp_path / "preferences.png").stat().st_size > 0
