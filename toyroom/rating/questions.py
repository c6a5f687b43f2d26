"""A rating study's questions file (``toyroom rate --questions FILE.toml``), read and checked
against the recordings it is about.

The file holds the study's texts and its questions::

    title = "What do they think?"
    instructions = "Watch each clip, then move the sliders."
    consent = "By taking part you agree that ..."
    shuffle = false          # true: each participant gets the questions in an order of their own
    replay_rate = 2          # replays run at this many times real time (default 2)

    [[questions]]
    id = "skate-before"      # optional: q1, q2... by position
    recording = "paper-robot" # a recording given on the command line, by file name without
                              # extension or by scenario name (optional with one recording:
                              # then its file name)
    tick = 120               # the engine tick asked about, or instead:
    at = "A1 leaves S1"      # a moment of the run (:mod:`toyroom.rating.moments`): the same
                             # moment of every participant's run, whatever its tick
    nth = 1                  # with ``at``: its first time (default), second...
    offset = 0               # with ``at``: ticks after it (negative: before)
    person = "A1"
    ask = "belief"           # belief: where the person thinks ``item`` is (a slider per location);
                             # desire: how much they want each item (a slider per goal)
    item = "skate"           # belief only
    locations = ["S1", "P2"] # belief only, optional: the sliders' locations (default: all)
    goals = ["skate", "ball", "out"]  # desire only, optional (default: every item)
    retrospective = false    # true: the rater first watches up to ``show_until`` (default:
                             # the recording's end), then says what the person thought at ``tick``
    text = "..."             # optional: the question's wording (default: made from the above)

Every table is strict: an unknown key is an error naming it, the closest known key, the
question and the line of its ``[[questions]]`` header.
"""

from __future__ import annotations

import difflib
import fnmatch
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bridge.errors import BridgeError
from bridge.recording import Trace
from protocol import AgentKind

from .moments import MomentError, MomentMissing, moment_tick

ASKS = ("belief", "desire")
"""What a question asks for: ``belief`` (over locations, for an item) or ``desire`` (over goals)."""
OUT = "out"
"""The goal of leaving (the planner's ``out``), as ``toyroom fit --judgments`` names it."""
STUDY_KEYS = ("title", "instructions", "consent", "shuffle", "replay_rate", "questions")
REPLAY_RATE = 2.0
"""Replays run at twice real time unless the file says ``replay_rate``."""
QUESTION_KEYS = (
    "id", "recording", "tick", "at", "nth", "offset", "person", "ask", "item", "locations",
    "goals", "retrospective", "show_until", "text",
)  # fmt: skip


class QuestionsError(BridgeError):
    """A questions file that cannot be read or names what the recordings do not have; says
    the file, the line or key, and what is wrong."""


class _Absent(QuestionsError):
    """A question's moment does not happen in one recording: a question shared by several
    recordings is not asked of that one (a question of one recording is refused)."""


@dataclass(frozen=True)
class Question:
    """One question, resolved against its recording.

    Attributes:
        id: the question's name (the ``question`` column of the answers).
        episode: the recording's name as the file gave it (the ``episode`` column).
        recording: the index of the recording among those given.
        tick: the engine tick asked about.
        person: the person asked about.
        ask: ``belief`` or ``desire``.
        targets: the sliders' ``target`` column values: ``ITEM@LOCATION`` for a belief, a
            goal (an item or ``out``) for a desire.
        labels: each slider's label, in the order of ``targets``.
        retrospective: whether the rater first sees the episode past ``tick`` (``smoothed``).
        show_until: the last tick the rater watches.
        text: the question as the page asks it.
    """

    id: str
    episode: str
    recording: int
    tick: int
    person: str
    ask: str
    targets: tuple[str, ...]
    labels: tuple[str, ...]
    retrospective: bool
    show_until: int
    text: str

    @property
    def quantity(self) -> str:
        """The answers' ``quantity`` column, as ``toyroom fit --judgments`` reads it: ``belief``,
        or ``utility`` for a desire question (its sliders ask how much the person wants each
        goal, which the fit reads as the posterior expected utility, not P(most wanted))."""
        return "utility" if self.ask == "desire" else self.ask

    @property
    def estimate(self) -> str:
        """``smoothed`` for a retrospective question, else ``online``."""
        return "smoothed" if self.retrospective else "online"


@dataclass(frozen=True)
class RatingStudy:
    """A questions file: the texts the page shows and the questions, in the file's order."""

    path: Path
    title: str
    instructions: str
    consent: str
    shuffle: bool
    questions: tuple[Question, ...]
    replay_rate: float = REPLAY_RATE
    skipped: tuple[str, ...] = ()
    """A note per recording a question shared by several was not asked of: its moment (``at``)
    does not happen in that run (a participant who never left the room)."""
    """Replays run at this many times real time (the page says so)."""


def episode_names(traces: Sequence[Trace], names: Sequence[str]) -> dict[str, int]:
    """Each recording by file name (without extension) and by scenario name, where the name
    is one recording's only (as ``toyroom fit --judgments`` resolves the ``episode`` column)."""
    found: dict[str, set[int]] = {}
    for e, (trace, name) in enumerate(zip(traces, names, strict=True)):
        found.setdefault(trace.info.scenario, set()).add(e)
        found.setdefault(name, set()).add(e)
    return {name: next(iter(e)) for name, e in found.items() if len(e) == 1}


def _header_lines(text: str) -> list[int]:
    """The line number of each ``[[questions]]`` header, in order."""
    lines = text.splitlines()
    return [n for n, line in enumerate(lines, start=1) if line.strip().startswith("[[questions]]")]


def _unknown(keys: Sequence[str], known: Sequence[str]) -> str | None:
    """The first key not in ``known``, said with the closest known one, or ``None``."""
    for key in keys:
        if key not in known:
            close = difflib.get_close_matches(key, known, n=1)
            hint = f" (did you mean {close[0]!r}?)" if close else ""
            return f"unknown key {key!r}{hint}; known keys: {', '.join(known)}"
    return None


def _text(table: dict[str, Any], key: str, where: str, default: str = "") -> str:
    value = table.get(key, default)
    if not isinstance(value, str):
        raise QuestionsError(f"{where}: {key} must be a string, got {value!r}")
    return value.strip()


def load_study(path: Path, traces: Sequence[Trace], names: Sequence[str]) -> RatingStudy:
    """Read and check ``path`` against the recordings (``names``: each one's file name
    without extension).

    Raises:
        QuestionsError: naming the file, the line and key, and what is wrong.
    """
    try:
        text = path.read_text(encoding="utf-8")
        data = tomllib.loads(text)
    except OSError as err:
        raise QuestionsError(f"{path}: cannot read the questions ({err.strerror or err})") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise QuestionsError(f"{path}: not TOML: {err}") from None
    if (problem := _unknown(list(data), STUDY_KEYS)) is not None:
        raise QuestionsError(f"{path}: {problem}")
    tables = data.get("questions")
    if not isinstance(tables, list) or not tables or not all(isinstance(t, dict) for t in tables):
        raise QuestionsError(f"{path}: expected one or more [[questions]] tables")
    shuffle = data.get("shuffle", False)
    if not isinstance(shuffle, bool):
        raise QuestionsError(f"{path}: shuffle must be true or false, got {shuffle!r}")
    rate = data.get("replay_rate", REPLAY_RATE)
    if not isinstance(rate, int | float) or isinstance(rate, bool) or not 0.1 <= rate <= 100:
        raise QuestionsError(f"{path}: replay_rate must be from 0.1 to 100 (times real time), got {rate!r}")
    lines = _header_lines(text)
    questions, skipped = [], []
    for n, table in enumerate(tables):
        line = f" line {lines[n]}" if n < len(lines) else ""
        where = f"{path}{line}"
        targets = _recordings(table, n, where, traces, names)
        asked = []
        for name, e in targets:
            suffix = f"-{name}" if len(targets) > 1 else ""
            try:
                asked.append(_question(table, n, where, traces, (name, e), suffix))
            except _Absent as absent:
                skipped.append(f"not asked of {name}: {absent}")
        if not asked:
            raise QuestionsError(f"{where}: its moment happens in none of its recordings: {skipped[-1]}")
        questions += asked
    ids = [q.id for q in questions]
    if dupes := sorted({i for i in ids if ids.count(i) > 1}):
        raise QuestionsError(f"{path}: question ids must differ; repeated: {', '.join(dupes)}")
    return RatingStudy(
        path,
        _text(data, "title", str(path), "Rating study"),
        _text(data, "instructions", str(path)),
        _text(data, "consent", str(path)),
        shuffle,
        tuple(questions),
        float(rate),
        tuple(skipped),
    )


def _integer(table: dict[str, Any], key: str, where: str, low: int, high: int) -> int:
    value = table.get(key)
    if not isinstance(value, int) or isinstance(value, bool):
        raise QuestionsError(f"{where}: {key} must be an integer tick, got {value!r}")
    if not low <= value <= high:
        raise QuestionsError(f"{where}: {key} = {value} is outside the recording (ticks {low} to {high})")
    return value


def _tick(table: dict[str, Any], where: str, trace: Trace) -> int:
    """The question's tick: ``tick``, or the moment ``at`` (its ``nth`` time, ``offset`` ticks
    after it) in this recording."""
    first, last = trace.ticks[0][0].tick, trace.ticks[-1][0].tick
    if ("tick" in table) == ("at" in table):
        raise QuestionsError(f"{where}: give tick or at (a moment such as 'A1 leaves S1'), one of them")
    if "tick" in table:
        if "nth" in table or "offset" in table:
            raise QuestionsError(f"{where}: nth and offset go with at, not tick")
        return _integer(table, "tick", where, first, last)
    nth, offset = table.get("nth", 1), table.get("offset", 0)
    if not isinstance(nth, int) or isinstance(nth, bool) or nth < 1:
        raise QuestionsError(f"{where}: nth must be an integer from 1, got {nth!r}")
    if not isinstance(offset, int) or isinstance(offset, bool):
        raise QuestionsError(f"{where}: offset must be an integer number of ticks, got {offset!r}")
    try:
        moment = moment_tick(_text(table, "at", where), trace, nth)
    except MomentError as err:
        raise (_Absent if isinstance(err, MomentMissing) else QuestionsError)(f"{where}: at: {err}") from None
    tick = moment + offset
    if not first <= tick <= last:  # the run ended too soon (or began too late) for this moment
        raise _Absent(
            f"{where}: at {table['at']!r} (tick {moment}) + offset {offset} = {tick} is outside the "
            f"recording (ticks {first} to {last})"
        )
    return tick


def _names(table: dict[str, Any], key: str, where: str, known: Sequence[str]) -> tuple[str, ...]:
    value = table.get(key, list(known))
    if not isinstance(value, list) or not value or not all(isinstance(v, str) for v in value):
        raise QuestionsError(f"{where}: {key} must be a non-empty list of names, got {value!r}")
    if bad := [v for v in value if v not in known]:
        raise QuestionsError(f"{where}: {key}: {bad[0]!r} is unknown (known: {', '.join(known)})")
    if len(set(value)) != len(value):
        raise QuestionsError(f"{where}: {key} names one twice: {value!r}")
    return tuple(value)


def _recordings(
    table: dict[str, Any], n: int, where: str, traces: Sequence[Trace], names: Sequence[str]
) -> list[tuple[str, int]]:
    """The recordings the ``n``-th question is asked of, as ``(name, index)``: the one its
    ``recording`` names (by file name or scenario; the only one when it names none), or every
    recording of a scenario several share, or whose file name matches a glob (``p*``): one
    question each, named by file name (issue 55: two participants of one scenario)."""
    episodes = episode_names(traces, names)
    default = names[0] if len(traces) == 1 else ""
    wanted = _text(table, "recording", f"{where} (questions[{n}])", default)
    if wanted in episodes:
        return [(wanted, episodes[wanted])]
    shared = [
        (name, e)
        for e, (trace, name) in enumerate(zip(traces, names, strict=True))
        if trace.info.scenario == wanted or fnmatch.fnmatchcase(name, wanted)
    ]
    if not shared:
        known = ", ".join(sorted({*names, *(t.info.scenario for t in traces)})) or "none"
        raise QuestionsError(
            f"{where} (questions[{n}]): recording {wanted!r} is no recording given (known: {known})"
        )
    return shared


def _question(
    table: dict[str, Any],
    n: int,
    where: str,
    traces: Sequence[Trace],
    target: tuple[str, int],
    suffix: str = "",
) -> Question:
    """The ``n``-th ``[[questions]]`` table asked of recording ``target`` (its name and index),
    checked (``where``: the file and the table's line, for errors; ``suffix``: added to the
    question's id when it is asked of several recordings)."""
    qid = _text(table, "id", f"{where} (questions[{n}])", f"q{n + 1}") + suffix
    where = f"{where} (questions[{n}] '{qid}')"
    if (problem := _unknown(list(table), QUESTION_KEYS)) is not None:
        raise QuestionsError(f"{where}: {problem}")
    episode, e = target
    scene, last = traces[e].info.scene, traces[e].ticks[-1][0].tick
    tick = _tick(table, where, traces[e])
    people = [a.id for a in scene.agents if a.kind is AgentKind.PERSON]
    person = _text(table, "person", where)
    if person not in people:
        raise QuestionsError(f"{where}: person {person!r} is not in {episode} (people: {', '.join(people)})")
    ask = _text(table, "ask", where)
    if ask not in ASKS:
        raise QuestionsError(f"{where}: ask must be one of {', '.join(ASKS)}, got {ask!r}")
    items = [i.id for i in scene.items]
    names = {i.id: i.name or i.id for i in scene.items}
    if ask == "belief":
        if "goals" in table:
            raise QuestionsError(f"{where}: goals is for ask = 'desire'; a belief question takes locations")
        item = _text(table, "item", where)
        if item not in items:
            raise QuestionsError(f"{where}: item {item!r} is unknown (items: {', '.join(items)})")
        places = _names(table, "locations", where, [loc.id for loc in scene.locations])
        rooms = {r.id: r.name or r.id for r in scene.regions}
        region = {loc.id: rooms.get(loc.region, loc.region) for loc in scene.locations}
        targets = tuple(f"{item}@{p}" for p in places)
        labels = tuple(f"{p} ({region[p]})" for p in places)
        prompt = f"Where does {person} think the {names[item]} is?"
    else:
        if "item" in table or "locations" in table:
            raise QuestionsError(f"{where}: item and locations are for ask = 'belief'; a desire takes goals")
        targets = _names(table, "goals", where, [*items, OUT]) if "goals" in table else tuple(items)
        labels = tuple("leave" if g == OUT else names[g] for g in targets)
        prompt = f"How much does {person} want each of these?"
    retrospective = table.get("retrospective", False)
    if not isinstance(retrospective, bool):
        raise QuestionsError(f"{where}: retrospective must be true or false, got {retrospective!r}")
    if "show_until" in table:
        show = _integer(table, "show_until", where, tick, last)
    else:
        show = last if retrospective else tick
    if show != tick and not retrospective:
        raise QuestionsError(f"{where}: show_until is for retrospective questions (retrospective = true)")
    if retrospective:
        prompt = prompt.replace("does", "did").replace("is?", "was?") + f" (at tick {tick})"
    text = _text(table, "text", where, prompt)
    return Question(qid, episode, e, tick, person, ask, targets, labels, retrospective, show, text)
