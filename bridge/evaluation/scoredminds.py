"""The part of a brain's ``mind`` message that the evaluation scores, read from run logs.

A run log holds every ``mind`` the brain published (:mod:`brain.outputs.runlog`), about
3.4 kB a tick on the houses, most of it what the evaluation never reads (desires, whole
worlds, intentions). Reading only each person's beliefs, preference and flagged false
beliefs is about four times faster than decoding the whole message, and the same numbers:
the decoder skips the other fields. The log is the brain's own output of this very run, so
it is read as is, without the protocol checks a message from the wire gets.
"""

from __future__ import annotations

from pathlib import Path

import msgspec


class Chance(msgspec.Struct, frozen=True):
    """One entry of a distribution: ``p`` of ``id`` (a location, an item, or ``out``)."""

    id: str
    p: float


class ScoredBelief(msgspec.Struct, frozen=True):
    """A person's believed location of ``item``."""

    item: str
    locations: tuple[Chance, ...]


class ScoredAgent(msgspec.Struct, frozen=True):
    """What the evaluation scores of the brain's estimate of one person."""

    agent: str
    beliefs: tuple[ScoredBelief, ...]
    preference: tuple[Chance, ...]
    false_beliefs: tuple[str, ...] = ()


class ScoredMind(msgspec.Struct, frozen=True):
    """What the evaluation scores of one tick's ``mind`` message."""

    tick: int
    agents: tuple[ScoredAgent, ...]


_decoder = msgspec.json.Decoder(ScoredMind)


def read_scored_minds(path: Path) -> dict[int, ScoredMind]:
    """The minds of a run log's ``minds-<observer>.jsonl`` by tick.

    Raises:
        ValueError: a line is not a ``mind`` message (``msgspec.DecodeError`` is one).
    """
    return {m.tick: m for m in map(_decoder.decode, path.read_bytes().splitlines())}
