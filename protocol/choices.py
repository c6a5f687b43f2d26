"""The sets of choices the commands and settings take, one enum each, defined once here.

Every list of allowed values is built from these: the brain's settings
(``RobotSettings.policy``, ``ModelSettings.perception``), the engine's episode generator
(``python -m sim2d generate --minds/--kind/--tasks``) and the evaluation's conditions
(``toyroom eval --perception/--minds/--kind/--tasks/--policies``). ``protocol`` is the one
package all of them may import. :class:`~protocol.mind.Observer` is another such set.
"""

from __future__ import annotations

import enum
from collections.abc import Sequence


class Choice(enum.StrEnum):
    """A set of named choices (the values are the names every command line takes).

    A choice is its name as text (``str(Policy.TOM) == "tom"``, and it compares equal to
    it), so a TOML file, a ``--set`` option and the wire carry the same words as before.
    """

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """Every value's name, in the order declared."""
        return tuple(str(choice.value) for choice in cls)


class Policy(Choice):
    """How the acting robot chooses what to do (the brain's ``RobotSettings.policy``).

    - ``tom``: the paper's tree, acting on the people's inferred minds;
    - ``benefit``: the same minds, each task chosen by its expected benefit against its costs;
    - ``tidy``: no theory of mind: put every moved item back where it was;
    - ``announce``: no theory of mind: tell everyone about every move;
    - ``oracle``: reads the simulated people's true minds (an upper bound, not a robot one
      could build): ``tom``'s tree on the engine's truth (``engine/truth``, sim2d only)
      instead of the inferred minds. Beside ``tom`` and ``none`` it splits help into reading
      (``tom`` against ``oracle``) and acting (``oracle`` against ``none``).

    The robot that only observes has no policy (nothing to choose): an evaluation runs it
    beside every policy, always, under the name :data:`OBSERVING`.
    """

    TOM = "tom"
    BENEFIT = "benefit"
    TIDY = "tidy"
    ANNOUNCE = "announce"
    ORACLE = "oracle"


class RobotMode(Choice):
    """Whether the scene's robot acts (a scenario's ``robot``, every ``--robot`` option).

    - ``act``: the brain sends it commands;
    - ``observe``: it only watches (the brain's inference runs, nothing is sent).
    """

    ACT = "act"
    OBSERVE = "observe"


OBSERVING = "none"
"""What an evaluation calls its observing run (``toyroom eval --policies none``), run beside
every :class:`Policy`: the robot acts not at all. Not a policy: ``RobotSettings`` takes none."""


class Perception(Choice):
    """What the robot sees (the brain's ``perception`` setting).

    - ``omniscient``: every item wherever it is (the paper's setting);
    - ``embodied``: the item spots the visibility table lists from its own cell; it infers
      the rest.
    """

    OMNISCIENT = "omniscient"
    EMBODIED = "embodied"


class Minds(Choice):
    """What kind of minds the simulated people of a generated episode have.

    - ``simple``: they perceive exactly, remember, keep to themselves and go where they
      believe their item most likely is (what the brain's percept filter assumes);
    - ``rich``: they forget, overlook, gossip and wander (knobs drawn from the seed);
    - ``model``: they perceive as simple ones do and act by the brain's planner.
    """

    SIMPLE = "simple"
    RICH = "rich"
    MODEL = "model"


class EpisodeKind(Choice):
    """What a generated episode is about.

    - ``everyday``: people with random habits;
    - ``tasks``: built around one of the robot's jobs (:class:`TaskKind`).
    """

    EVERYDAY = "everyday"
    TASKS = "tasks"


class TaskKind(Choice):
    """The job a ``tasks`` episode is built around, in the generator's order (:func:`task_of`).

    - ``moved``: shortly before its owner comes back from an errand, someone moves the item
      they will come back for to a spot out of their view;
    - ``hidden``: the same, to the spot the owner's search reaches last;
    - ``contested``: both people want the same item;
    - ``seen``: the owner watches the item being moved to a spot in view (a true belief:
      putting it back would mislead them);
    - ``told``: the other person tells the owner a wrong place out of the robot's hearing;
    - ``overlooked``: the owner stands in view of the item without noticing it, then goes to
      a wrong place;
    - ``stale``: the owner is sure of a wrong place from before the episode.
    """

    MOVED = "moved"
    HIDDEN = "hidden"
    CONTESTED = "contested"
    SEEN = "seen"
    TOLD = "told"
    OVERLOOKED = "overlooked"
    STALE = "stale"


class EpisodeMap(Choice):
    """The maps generated episodes are drawn on (``python -m sim2d generate --map``), in the
    order an evaluation's episodes cycle through them, one per episode index.

    - ``paper``: the paper's bundled map;
    - ``house-a``, ``house-b``: two houses the generator builds (its rooms, spots and seed:
      ``sim2d.generation.episodes.HOUSES``).
    """

    PAPER = "paper"
    HOUSE_A = "house-a"
    HOUSE_B = "house-b"


MAPS: tuple[str, ...] = EpisodeMap.names()
"""The names of :class:`EpisodeMap`, in its order: the one list of maps the generator
(``sim2d.generation.episodes``) and the evaluation (``toyroom.evaluation.generation``) use."""

MAP_CYCLE = len(MAPS)
"""How many maps an evaluation's episodes cycle through, in turn by seed (:data:`MAPS`);
:func:`task_of` steps past that cycle."""


def task_of(seed: int, kinds: Sequence[str] = TaskKind.names()) -> str:
    """The job a task episode of ``seed`` is built around: in turn among ``kinds`` (names of
    :class:`TaskKind`), one step further every :data:`MAP_CYCLE` seeds, so that every map of
    an evaluation gets every kind (plain turns alias them: with three kinds, each map would
    get only one)."""
    return kinds[(seed + seed // MAP_CYCLE) % len(kinds)]
