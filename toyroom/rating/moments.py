"""Moments of a run named by what happens (pure): ``"A1 leaves Storage 1"`` is the tick of
A1's first ``leave`` event from that room in a recording, so that a rating question asks
about the same moment of every participant's run, whatever its tick (``at`` in a questions
file, :mod:`toyroom.rating.questions`).

A moment is ``PERSON VERB THING``:

- ``enters ROOM`` / ``leaves ROOM``: a region, by id or name (``S1``, ``Storage 1``);
- ``takes ITEM`` / ``drops ITEM`` / ``plays with ITEM`` / ``gets ITEM``: an item by id or name
  (``gets``: someone, the robot or a person, gives it to them);
- ``completes STEP``: the step of their script labelled ``STEP``.

A person is named by id or name (``Agent 1``); names are matched without regard to case.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from bridge.recording import Trace
from protocol import Event, EventKind

VERBS = ("enters", "leaves", "takes", "drops", "plays with", "gets", "completes")


class MomentError(ValueError):
    """A moment that cannot be read, or does not happen in a recording; says why."""


class MomentMissing(MomentError):
    """A moment that can be read but does not happen (often enough) in this recording."""


@dataclass(frozen=True)
class Moment:
    """A moment, read: who does what to what."""

    person: str
    verb: str
    thing: str
    """The region, item or step label, as the recording names it (its id, or the label)."""


def read_moment(phrase: str, trace: Trace) -> Moment:
    """``phrase`` read against ``trace``'s scene (people, regions and items by id or name).

    Raises:
        MomentError: not ``PERSON VERB THING``, or naming what the scene does not have.
    """
    words = phrase.split()
    people = {a.id.lower(): a.id for a in trace.info.scene.agents} | {
        a.name.lower(): a.id for a in trace.info.scene.agents if a.name
    }
    found = [
        (start, verb)
        for start in range(1, len(words))
        for verb in VERBS
        if " ".join(words[start : start + len(verb.split())]).lower() == verb
    ]
    if not found or found[0][0] + len(found[0][1].split()) >= len(words):
        raise MomentError(f"{phrase!r} is not 'PERSON VERB THING' (verbs: {', '.join(VERBS)})")
    start, verb = found[0]
    who = " ".join(words[:start])
    person = people.get(who.lower())
    if person is None:
        raise MomentError(f"{phrase!r}: no person {who!r} in the recording")
    thing = " ".join(words[start + len(verb.split()) :])
    return Moment(person, verb, _thing(phrase, verb, thing, trace))


def _thing(phrase: str, verb: str, thing: str, trace: Trace) -> str:
    """The region or item id ``thing`` names (a step label as it is)."""
    if verb == "completes":
        return thing
    scene = trace.info.scene
    rooms = verb in ("enters", "leaves")
    pairs = [(r.id, r.name) for r in scene.regions] if rooms else [(i.id, i.name) for i in scene.items]
    known = {ident.lower(): ident for ident, _ in pairs}
    known |= {name.lower(): ident for ident, name in pairs if name}
    found = known.get(thing.lower())
    if found is None:
        kind = "room" if rooms else "item"
        names = ", ".join(sorted({ident for ident, _ in pairs}))
        raise MomentError(f"{phrase!r}: no {kind} {thing!r} in the recording ({kind}s: {names})")
    return found


def _matches(moment: Moment) -> Callable[[Event], bool]:
    """Whether an event is ``moment``."""
    kinds = {
        "enters": EventKind.ENTER,
        "leaves": EventKind.LEAVE,
        "takes": EventKind.TAKE,
        "drops": EventKind.DROP,
        "plays with": EventKind.PLAY,
    }
    if moment.verb == "completes":
        return lambda e: e.actor == moment.person and e.label == moment.thing
    if moment.verb == "gets":
        return lambda e: e.kind == EventKind.GIVE and e.target == moment.person and e.item == moment.thing
    kind = kinds[moment.verb]
    if moment.verb in ("enters", "leaves"):
        return lambda e: e.kind == kind and e.actor == moment.person and e.location == moment.thing
    return lambda e: e.kind == kind and e.actor == moment.person and e.item == moment.thing


def moment_tick(phrase: str, trace: Trace, nth: int = 1) -> int:
    """The tick of the ``nth`` time ``phrase`` happens in ``trace``.

    Raises:
        MomentError: the phrase cannot be read.
        MomentMissing: it happens fewer than ``nth`` times (saying how many).
    """
    matches = _matches(read_moment(phrase, trace))
    ticks = [state.tick for state, events in trace.ticks for e in events if matches(e)]
    if len(ticks) < nth:
        times = "never" if not ticks else f"only {len(ticks)} time{'s' if len(ticks) > 1 else ''}"
        raise MomentMissing(f"{phrase!r} happens {times} in this recording (wanted time {nth})")
    return ticks[nth - 1]
