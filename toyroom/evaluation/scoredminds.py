"""The part of a brain's ``mind`` message that the evaluation scores, read from run logs.

A run log holds every ``mind`` the brain published (:mod:`brain.outputs.runlog`), about
3.4 kB a tick on the houses, most of it what the evaluation never reads (desires, whole
worlds, intentions). Reading only each person's beliefs, preference and flagged false
beliefs is about four times faster than decoding the whole message, and the same numbers:
the decoder skips the other fields. The log is the brain's own output of this very run, so
it is read as is, without the protocol checks a message from the wire gets. Its structs
hold no cycles, so the garbage collector does not track them (``gc=False``): an evaluation
keeps many thousands of them, and the collector's passes over them cost more than reading
them did.
"""

from __future__ import annotations

from pathlib import Path

import msgspec


class Chance(msgspec.Struct, frozen=True, gc=False):
    """One entry of a distribution: ``p`` of ``id`` (a location, an item, or ``out``)."""

    id: str
    p: float


class ScoredBelief(msgspec.Struct, frozen=True, gc=False):
    """A person's believed location of ``item``."""

    item: str
    locations: tuple[Chance, ...]


class ScoredNested(msgspec.Struct, frozen=True, gc=False):
    """Where the person believes ``agent`` believes each item is."""

    agent: str
    beliefs: tuple[ScoredBelief, ...]


class ScoredAgent(msgspec.Struct, frozen=True, gc=False):
    """What the evaluation scores of the brain's estimate of one person."""

    agent: str
    beliefs: tuple[ScoredBelief, ...]
    preference: tuple[Chance, ...]
    false_beliefs: tuple[str, ...] = ()
    false_belief: tuple[Chance, ...] = ()
    """P(false belief) per item."""
    nested_beliefs: tuple[ScoredNested, ...] = ()


class ScoredEnd(msgspec.Struct, frozen=True, gc=False):
    """A robot task that ended at this tick (``TaskEnd``): ``outcome`` ``done`` or ``dropped``."""

    task: str
    detail: str
    outcome: str


class ScoredRobot(msgspec.Struct, frozen=True, gc=False):
    """What the evaluation counts of a robot's activity (:mod:`.robottasks`)."""

    robot: str
    task: str
    ended: ScoredEnd | None = None


class ScoredMind(msgspec.Struct, frozen=True, gc=False):
    """What the evaluation scores of one tick's ``mind`` message."""

    tick: int
    agents: tuple[ScoredAgent, ...]
    robots: tuple[ScoredRobot, ...] = ()


class _Head(msgspec.Struct):
    """What comes before a line's ``agents``: only its tick is read."""

    tick: int


_decoder = msgspec.json.Decoder(ScoredMind)
_head_decoder = msgspec.json.Decoder(_Head)
_AGENTS = b'"agents":'


def read_scored_minds(path: Path) -> dict[int, ScoredMind]:
    """The minds of a run log's ``minds-<observer>.jsonl`` by tick.

    Most ticks nobody's estimate changes, so a line usually ends exactly as the one before it
    from its ``"agents":`` on (about 94% of the lines of an evaluation's run): such a line's
    agents are the previous line's, and only the part before them is decoded, for the tick.

    Raises:
        ValueError: a line is not a ``mind`` message (``msgspec.DecodeError`` is one).
    """
    minds: dict[int, ScoredMind] = {}
    previous: tuple[bytes, ScoredMind] | None = None
    for line in path.read_bytes().splitlines():
        at = line.find(_AGENTS)
        head, agents = line[:at], line[at:]
        if previous is not None and at > 0 and head.endswith(b",") and agents == previous[0]:
            tick = _head_decoder.decode(head[:-1] + b"}").tick
            mind = ScoredMind(tick=tick, agents=previous[1].agents, robots=previous[1].robots)
        else:
            mind = _decoder.decode(line)
        minds[mind.tick] = mind
        previous = (agents, mind)
    return minds
