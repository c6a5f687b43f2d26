"""Task episodes (``python -m sim2d generate --kind tasks``): built so that the robot has a job."""

from __future__ import annotations

from pathlib import Path

import pytest

from protocol import EpisodeKind, EpisodeSpec, Minds
from sim2d.engine import Engine
from sim2d.generation.episodes import write_episode
from sim2d.generation.tasks import seed_of, task_of
from sim2d.people.autonomous import AutonomousPerson
from sim2d.scenario.scenario import load_scenario

RICH_TASKS = EpisodeSpec(Minds.RICH, EpisodeKind.TASKS)
"""Rich minds, a task episode."""

TASK_EPISODE = EpisodeSpec(kind=EpisodeKind.TASKS)
"""A task episode."""


def run(path: Path, ticks: int = 700) -> tuple[list[tuple[int, str, str, str | None, str | None]], int]:
    """The people's takes and drops, and how many ticks A1 held a false belief about what they want."""
    engine = Engine(load_scenario(str(path)), seed=1)
    acts, false = [], 0
    while not engine.done and engine.world.tick < ticks:
        result = engine.step()
        acts += [
            (e.tick, e.actor, e.kind.value, e.item, e.location)
            for e in result.events
            if e.kind.value in ("take", "drop")
        ]
        assert result.truth is not None
        mind = next(m for m in result.truth.agents if m.agent == "A1")
        where = {p.item: p.location for p in result.truth.items}
        belief = next(b for b in mind.beliefs if b.item == mind.preference)
        false += {p.id: p.p for p in belief.locations}.get(where[mind.preference], 0.0) < 0.1
    return acts, false


@pytest.mark.parametrize("seed", [0, 1])
def test_an_item_moved_while_its_owner_is_away_gives_them_a_false_belief(tmp_path: Path, seed: int) -> None:
    assert task_of(seed) in ("moved", "hidden")
    path = write_episode(tmp_path, "paper", seed, TASK_EPISODE)
    scenario = load_scenario(str(path))
    owner, mover = scenario.people
    assert owner.jobs.errand > 0 and mover.jobs.moves is not None and owner.prefers == mover.jobs.moves[0]
    acts, false = run(path)
    item, target = mover.jobs.moves
    assert (mover.id, "drop", item, target) in [a[1:] for a in acts], (
        f"the mover puts the {item} at {target}: {acts}"
    )
    assert false > 20, f"the owner comes back believing the {item} where it was (false belief ticks: {false})"


def test_a_contested_item_is_wanted_by_both(tmp_path: Path) -> None:
    seed = seed_of("contested")
    scenario = load_scenario(str(write_episode(tmp_path, "house-a", seed, TASK_EPISODE)))
    assert {p.prefers for p in scenario.people} == {scenario.items[0].id}
    assert all(p.jobs.errand == 0 and p.jobs.moves is None for p in scenario.people)


def test_everyday_episodes_are_unchanged_by_the_kind_option(tmp_path: Path) -> None:
    everyday = write_episode(tmp_path / "a", "paper", 4).read_text()
    again = write_episode(tmp_path / "b", "paper", 4, EpisodeSpec(kind=EpisodeKind.EVERYDAY)).read_text()
    assert everyday == again and "errand" not in everyday


def test_a_move_the_owner_watched_leaves_no_false_belief(tmp_path: Path) -> None:
    """Sally-Anne's true-belief control: the owner sees the item moved before the errand."""
    seed = seed_of("seen")
    path = write_episode(tmp_path, "paper", seed, TASK_EPISODE)
    scenario = load_scenario(str(path))
    owner, mover = scenario.people
    assert owner.jobs.errand_after > 0 and mover.jobs.moves is not None
    acts, false = run(path, ticks=400)
    item, target = mover.jobs.moves
    assert (mover.id, "drop", item, target) in [a[1:] for a in acts], acts
    assert false == 0, f"the owner watched the move: expected no false belief, got {false} ticks"


def test_an_errand_is_carried_through_when_told(tmp_path: Path) -> None:
    """Told where the item they want is while on an errand, the owner finishes the errand."""
    path = write_episode(tmp_path, "paper", 0, TASK_EPISODE)
    engine = Engine(load_scenario(str(path)), seed=1)
    owner = engine.people["A1"]
    for _ in range(5):
        engine.step()
    assert isinstance(owner, AutonomousPerson) and owner.current is not None and owner.current.errand
    owner.on_informed(engine.world, owner.preference, engine.world.map.locations[0].id)
    assert owner.current is not None and owner.current.errand, "still on the errand"
    assert owner.belief.most_likely(owner.preference) == engine.world.map.locations[0].id, (
        "but it was taken in"
    )


def owner_timeline(path: Path) -> tuple[int | None, int | None, int | None, int]:
    """When the owner (A1) went outside and came back in, when the mover dropped the item,
    and how many ticks the owner held a false belief before they were back."""
    engine = Engine(load_scenario(str(path)), seed=1)
    out = back = dropped = None
    false = 0
    while not engine.done and engine.world.tick < 800 and back is None:
        result = engine.step()
        for e in result.events:
            if e.actor == "A1" and e.kind.value == "enter":
                out = e.tick if e.location == "O" and out is None else out
                back = e.tick if out is not None and e.location != "O" else back
            if e.actor == "A2" and e.kind.value == "drop" and dropped is None:
                dropped = e.tick
        assert result.truth is not None
        mind = next(m for m in result.truth.agents if m.agent == "A1")
        where = {p.item: p.location for p in result.truth.items}
        belief = next(b for b in mind.beliefs if b.item == mind.preference)
        false += {p.id: p.p for p in belief.locations}.get(where[mind.preference], 0.0) < 0.1
    return out, back, dropped, false


@pytest.mark.parametrize(
    ("map_name", "seed"),
    [("paper", 0), ("house-a", seed_of("moved", 2)), ("house-b", 1), ("house-b", seed_of("hidden", 2))],
)
def test_the_move_lands_while_the_owner_is_out_shortly_before_they_are_back(
    tmp_path: Path, map_name: str, seed: int
) -> None:
    """``move_after`` times the move from walking distances: taken after the owner is outside,
    dropped before they come back in, and not long before."""
    path = write_episode(tmp_path, map_name, seed, TASK_EPISODE)
    out, back, dropped, false = owner_timeline(path)
    assert out is not None and back is not None and dropped is not None, (out, back, dropped)
    assert out < dropped < back, f"expected the drop while the owner is out ({out}..{back}), got {dropped}"
    assert back - dropped < 200, f"the drop came {back - dropped} ticks before the owner was back"
    assert false > 0, "the owner comes back with a false belief"


def test_the_owner_knows_where_their_item_is_whatever_the_minds(tmp_path: Path) -> None:
    """Rich minds start not knowing most things; a task's owner knows where they left theirs."""
    seed = seed_of("moved")
    scenario = load_scenario(str(write_episode(tmp_path, "paper", seed, RICH_TASKS)))
    owner = scenario.people[0]
    assert owner.jobs.knows == (owner.prefers,)
    engine = Engine(scenario, seed=1)
    person = engine.people[owner.id]
    assert isinstance(person, AutonomousPerson)
    where = scenario.items[0].at
    assert person.belief.most_likely(owner.prefers) == where
    assert person.belief.sureness(owner.prefers) > 0.99


@pytest.mark.parametrize("search", ["likely", "nearest"])
def test_a_hidden_item_is_where_the_owner_looks_last(tmp_path: Path, search: str) -> None:
    from sim2d.generation.tasks import search_order

    seed = seed_of("hidden")
    scenario = load_scenario(str(write_episode(tmp_path, "house-b", seed, TASK_EPISODE)))
    game_map = scenario.map
    start = game_map.locations[0]
    order = search_order(game_map, start, search)
    visible = set(game_map.sees[(start.cell.col, start.cell.row)])
    assert {loc.id for loc in order} == {loc.id for loc in game_map.locations} - visible - {start.id}
    if search == "nearest":
        from protocol.carry import walking_distances

        here = start
        for loc in order:  # each next spot is the nearest of those left
            far = walking_distances(game_map.walkable, [(here.cell.col, here.cell.row)])
            left = order[order.index(loc) :]
            assert far[(loc.cell.col, loc.cell.row)] == min(far[(o.cell.col, o.cell.row)] for o in left)
            here = loc
    owner, mover = scenario.people  # the generated episode hides it last in the owner's order
    assert mover.jobs.moves is not None
    spot = next(loc for loc in game_map.locations if loc.id == scenario.items[0].at)
    seen = set(game_map.sees.get(owner.home, ())) | {spot.id}
    unseen_order = [loc.id for loc in search_order(game_map, spot, "likely") if loc.id not in seen]
    assert unseen_order and mover.jobs.moves[1] == unseen_order[-1], (mover.jobs.moves, unseen_order)
