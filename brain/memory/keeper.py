"""The node's side of the memory: which snapshot a day starts from, and when to save one.

A scene that names its household (``Scene.household``, protocol 1.5) is a day of it: the
brain starts from the end of the day before (a day's first tick), or from the day's last
checkpoint (a brain that joins the day later: restarted after a crash). A day before whose
brain stopped before its end (killed, or stopped by SIGTERM) is not skipped: the next day
starts from its last checkpoint, with a warning naming it (and one naming any days between
that no brain with this file lived). It saves a checkpoint
every ``checkpoint_ticks`` engine ticks and the day's end when the episode ends, each in one
transaction (:class:`~brain.memory.store.MemoryStore`). A scene without a household uses no
memory.

At every tick it carries out the requests to forget someone that ``toyroom memory forget``
left for it (:mod:`.requests`): the person's rows and bytes go from the file, and no later save
of this brain holds them (a person of the scene it follows, not saved yet, too).
"""

from __future__ import annotations

import logging

import msgspec

from protocol import AgentKind, Mind, Scene

from ..errors import MemoryRequestError
from .requests import ForgetAnswer, ForgetRequest, pending, serve
from .snapshot import Distribution, Snapshot, snapshot_of
from .store import MemoryStore

log = logging.getLogger("toyroom.brain")

CHECKPOINT_TICKS = 100
"""Engine ticks between two checkpoints within a day (the default)."""


class MemoryKeeper:
    """Reads and saves one brain's memory (``store``, held open for the brain's life)."""

    def __init__(self, store: MemoryStore, checkpoint_ticks: int = CHECKPOINT_TICKS) -> None:
        if checkpoint_ticks < 1:
            raise ValueError(f"checkpoint_ticks is a number of ticks >= 1, not {checkpoint_ticks}")
        self.store = store
        self.checkpoint_ticks = checkpoint_ticks
        self.household: tuple[str, int] | None = None
        """The (household, day) being followed (``None``: the scene names none)."""
        self.forgotten: set[tuple[str, str]] = set()
        """(household, person) forgotten on request: never saved again by this keeper."""
        self._saved_at: int | None = None
        self._people: frozenset[str] = frozenset()
        self._tick: int | None = None
        self.forget_requested()

    def start(self, scene: Scene, tick: int | None) -> Snapshot | None:
        """What the day of ``scene`` starts from, joined at engine tick ``tick`` (``None``:
        not known yet: the day's checkpoint if any)."""
        if scene.household is None:
            self.household = None
            log.warning(
                "scene '%s' names no household: the memory %s is neither read nor written (a scenario "
                "names its household with [household] id and day)",
                scene.name,
                self.store.path,
            )
            return None
        key = self.household = (scene.household.id, scene.household.day)
        self._people = frozenset(a.id for a in scene.agents if a.kind is AgentKind.PERSON)
        self._saved_at = tick
        self.store.name(key[0], names_of(scene))
        self.forget_requested()
        memory = self.store.morning(*key) if tick == 0 else self.store.resume(*key)
        if memory is None:
            log.info("household '%s' day %d: nothing remembered before it", *key)
            return None
        kind = "end" if memory.final else f"checkpoint at tick {memory.tick}"
        if memory.day < key[1] and not memory.final:  # a day cut short: said, not skipped
            log.warning(
                "household '%s' day %d: day %d has no end (its brain stopped at or after tick %d, "
                "before the day ended): starting from day %d's %s; what was learned after it is lost",
                *key,
                memory.day,
                memory.tick,
                memory.day,
                kind,
            )
        else:
            log.info("household '%s' day %d: starting from day %d's %s", *key, memory.day, kind)
        if memory.day < key[1] - 1:
            log.warning(
                "household '%s' day %d: %s not remembered (no brain with this memory file lived %s): "
                "starting from day %d's %s",
                *key,
                _days(memory.day + 1, key[1] - 1),
                "it" if memory.day + 2 == key[1] else "them",
                memory.day,
                kind,
            )
        return memory

    def after_tick(self, mind: Mind, items: dict[str, Distribution], over: bool) -> None:
        """Carry out any request to forget; save the day's end when ``over``, else a
        checkpoint when one is due (without anyone forgotten)."""
        self._tick = mind.tick
        self.forget_requested()
        if self.household is None:
            return
        due = self._saved_at is None or mind.tick - self._saved_at >= self.checkpoint_ticks
        if over or due:
            snapshot = snapshot_of(*self.household, mind, items, final=over)
            kept = tuple(p for p in snapshot.people if (snapshot.household, p.person) not in self.forgotten)
            self.store.save(msgspec.structs.replace(snapshot, people=kept))
            self._saved_at = mind.tick

    def forget_requested(self) -> list[ForgetAnswer]:
        """Carry out the requests to forget waiting beside the file (:mod:`.requests`)."""
        if not pending(self.store.path):
            return []
        return serve(self.store.path, self._forget)

    def _forget(self, request: ForgetRequest) -> ForgetAnswer:
        """Forget ``request.person`` in the file and in every later save: in the household
        named, or else the one household that holds them, counting the one followed when
        they are a person of its scene (not saved yet, perhaps)."""
        person = request.person
        held = self.store.people_by_household()
        homes = {h for h, people in held.items() if person in people}
        if self.household is not None and person in self._people:
            homes.add(self.household[0])
        if request.household is not None:
            homes &= {request.household}
        if len(homes) != 1:  # none, or several: the store's own one-line answer
            try:
                self.store.household_of(person, request.household)
            except MemoryRequestError as err:
                return ForgetAnswer(request.household, error=str(err), tick=self._tick)
        if len(homes) != 1:
            error = (
                f"person {person!r} is in {len(homes)} households of memory file {self.store.path} "
                f"({', '.join(sorted(homes))}, the one a running brain follows): name one with --household"
            )
            return ForgetAnswer(request.household, error=error, tick=self._tick)
        home = homes.pop()
        removed = self.store.forget(person, home) if person in held.get(home, ()) else 0
        self.forgotten.add((home, person))
        # the log does not repeat the name: it would be one more copy of it
        log.warning("forgot a person in household '%s' on request: %d rows removed", home, removed)
        return ForgetAnswer(home, removed, tick=self._tick)


def names_of(scene: Scene) -> dict[str, str]:
    """The places (a location and its room: ``S1 in Storage 1``) and items (``red ball (ball)``)
    as the scene names them, by id."""
    rooms = {r.id: r.name or r.id for r in scene.regions}
    places = {loc.id: f"{loc.id} in {rooms.get(loc.region, loc.region)}" for loc in scene.locations}
    items = {i.id: f"{i.name} ({i.id})" for i in scene.items if i.name and i.name != i.id}
    return {**places, **items}


def _days(first: int, last: int) -> str:
    """``day 2`` or ``days 2 to 4``."""
    if first == last:
        return f"day {first} is"
    return f"days {first} {'and' if last == first + 1 else 'to'} {last} are"
