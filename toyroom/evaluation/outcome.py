"""Whether each simulated person ended a run with what they wanted (playing with their
preferred item, or outside when they want to leave), and when they first had it, from the
events of the run and the people's last true minds."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from protocol import RegionKind, Scene, Truth

from .metrics import EpisodeOutcome


def judge(
    scene: Scene,
    truth: Truth,
    playing: Mapping[str, str | None],
    regions: Mapping[str, str],
    reached: Sequence[tuple[int, str, str]],
) -> EpisodeOutcome:
    """The outcome of a run whose last truth is ``truth``.

    Args:
        scene: the run's scene (regions, the agents' homes).
        truth: the people's true minds at the run's last tick.
        playing: what each person plays with at the end (``None``: nothing).
        regions: the region each person last entered (absent: still in their home's).
        reached: ``(tick, person, item played with or region entered)`` in order of ticks.
    """
    outside = {r.id for r in scene.regions if r.kind is RegionKind.OUTSIDE}
    homes = {a.id: (a.home.col, a.home.row) for a in scene.agents}
    home_region = {(c.col, c.row): r.id for r in scene.regions for c in r.cells}
    outcome = EpisodeOutcome(ticks=truth.tick)
    for person in truth.agents:
        region = regions.get(person.agent, home_region.get(homes.get(person.agent, (-1, -1)), ""))
        wants_out = person.preference == "out"
        ok = region in outside if wants_out else playing.get(person.agent) == person.preference
        outcome.per_person[person.agent] = ok
        outcome.people += 1
        outcome.successes += ok
        goal = outside if wants_out else {person.preference}
        outcome.ticks_to_goal[person.agent] = next(
            (t for t, who, what in sorted(reached) if who == person.agent and what in goal), None
        )
    return outcome
