"""The participant's keyboard (pure): which key asks their person to do what.

Arrows step one cell; the digits walk to the places the page numbers (locations, then rooms
without one); ``t`` takes, ``d`` drops, ``p`` plays (or stops), ``y`` and ``n`` answer the
robot, space stops. While the robot asks what the person is looking for, the digits name the
items instead (:func:`digit_keys`; ``n``: nothing). Any other key does nothing (and is not
sent).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from protocol import Direction, PersonAction, PersonCommand

ARROWS = {
    "ArrowUp": Direction.UP,
    "ArrowDown": Direction.DOWN,
    "ArrowLeft": Direction.LEFT,
    "ArrowRight": Direction.RIGHT,
}
LETTERS = {
    "t": PersonAction.TAKE,
    "d": PersonAction.DROP,
    "p": PersonAction.PLAY,
    "y": PersonAction.ACCEPT,
    "n": PersonAction.DECLINE,
    " ": PersonAction.STOP,
}

INSTRUCTIONS = (
    ("arrows", "step one cell"),
    ("1-9", "walk to the numbered place"),
    ("t", "take the item here"),
    ("d", "drop what you hold here"),
    ("p", "play with what you hold (again: stop)"),
    ("y / n", "answer the robot: yes / no"),
    ("1-9, n", "asked what you look for: name the item / nothing"),
    ("space", "stop walking"),
)
"""The keys, as the page lists them."""


def digit_keys(names: Sequence[str]) -> dict[str, str]:
    """The digit key of each of ``names`` (``"1"`` the first, up to ``"9"``): the places the
    page numbers (:func:`~toyroom.play.sight.goto_keys`), and the items named in answer to
    "what are you looking for?"."""
    return {str(n + 1): name for n, name in enumerate(names[:9])}


def command_for(
    key: str,
    person: str,
    seq: int,
    goto: dict[str, str],
    pressed: float = 0.0,
    participant: str = "",
    answers: Mapping[str, str] | None = None,
) -> PersonCommand | None:
    """The command for ``key`` (the browser's ``KeyboardEvent.key``), or ``None`` when the
    key means nothing; ``goto`` maps digit keys to places, and ``answers`` (while the robot
    asks what the person is looking for) digit keys to the items they name; ``pressed`` is
    when (seconds since the page opened)."""
    common = {
        "person": person,
        "seq": seq,
        "key": key,
        "pressed": max(0.0, pressed),
        "participant": participant,
    }
    if key in ARROWS:
        return PersonCommand(action=PersonAction.MOVE, direction=ARROWS[key], **common)  # type: ignore[arg-type]
    if answers and key in answers:
        return PersonCommand(action=PersonAction.ACCEPT, item=answers[key], **common)  # type: ignore[arg-type]
    if key in goto:
        return PersonCommand(action=PersonAction.GOTO, target=goto[key], **common)  # type: ignore[arg-type]
    action = LETTERS.get(key.lower() if len(key) == 1 else key)
    if action is None:
        return None
    return PersonCommand(action=action, **common)  # type: ignore[arg-type]
