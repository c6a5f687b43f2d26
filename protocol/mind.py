"""What the brain infers, published on ``brain/mind`` every brain step.

Probabilities are online estimates (filtered on everything seen so far). Distributions are
lists of ``{id, p}`` pairs (not JSON maps) so that clients without dictionary support,
such as Unity's ``JsonUtility``, can read them.
"""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec

from .message import Id, Message, Probability, Tick

PREFERENCE_THRESHOLD = 0.6
"""The probability of a person's want at which a robot acts on it: the brain's default
``preference_threshold``, and the threshold the evaluation's ``fb_want_confident`` counts at."""


class Observer(enum.Enum):
    """Which model of a person a brain's minds come from (the names every command takes).

    - ``btom``: Bayesian Theory of Mind (beliefs from percepts, preference from actions).
    - ``truebelief``: no theory of mind: people are assumed to know the true world.
    - ``perceptonly``: the belief filter alone, without the action likelihood.
    """

    BTOM = "btom"
    TRUEBELIEF = "truebelief"
    PERCEPTONLY = "perceptonly"

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """Every observer's name, ``btom`` first."""
        return tuple(o.value for o in cls)


class Prob(msgspec.Struct, frozen=True):
    """A probability ``p`` attached to ``id`` (a location, an item, or ``out``): one entry of a
    distribution, or of a per-item probability such as ``AgentMind.false_belief``."""

    id: Id
    p: Probability


class ItemBelief(msgspec.Struct, frozen=True):
    """A person's believed location of ``item``: a distribution over location ids."""

    item: Id
    locations: tuple[Prob, ...]


class Intention(msgspec.Struct, frozen=True):
    """The most probable joint of preference and belief: heading for ``item`` at ``location``.

    ``item`` is ``None`` when the person most likely wants to leave ("out").
    """

    item: Id | None
    location: Id | None
    p: Probability


class GoalUtility(msgspec.Struct, frozen=True):
    """The expected utility of goal ``id`` (an item id, or ``out``)."""

    id: Id
    utility: float


class Preferred(msgspec.Struct, frozen=True):
    """P(goal ``goal`` is worth more to the person than goal ``over``), a tie counting half."""

    goal: Id
    over: Id
    p: Probability


class Desire(msgspec.Struct, frozen=True):
    """What the brain believes a person wants: each goal's expected utility, each pair of
    goals (in ``utility``'s order, ``goal`` before ``over``), and the most probable ranking,
    most wanted first, each entry a group of goals tied at that rank, with probability ``p``."""

    utility: tuple[GoalUtility, ...]
    preferred: tuple[Preferred, ...]
    ranking: tuple[tuple[Id, ...], ...]
    p: Probability


class Placement(msgspec.Struct, frozen=True):
    """Where a world puts ``item``: resting at ``location``, or carried (``held``) by someone
    whose carried item counts as being there."""

    item: Id
    location: Id
    held: bool = False


class WorldBelief(msgspec.Struct, frozen=True):
    """One whole world (every item's place) and the probability the person's belief gives it."""

    items: tuple[Placement, ...]
    p: Probability


class NestedBelief(msgspec.Struct, frozen=True):
    """Where a person believes ``agent`` (another person) believes each item is (protocol 1.3):
    the brain's estimate, one ``ItemBelief`` per item of the scene."""

    agent: Id
    beliefs: tuple[ItemBelief, ...]


class AgentMind(msgspec.Struct, frozen=True):
    """The brain's estimate of one person's mind.

    ``preference`` is a distribution over item ids plus ``out``: P(each goal is the one the
    person wants most). ``desire`` says more (utilities, pairs, ranking). ``worlds`` lists the
    most probable whole worlds of the person's belief (absent when the brain's model does not
    hold the joint), so that "nothing is at that spot" can be read exactly. ``false_belief`` gives, per
    item id, the brain's probability that the person has a false belief about it: that their
    belief gives the item's true location less than the brain's ``false_belief_mass`` (0.1
    by default) times what it gives its likeliest location, which ignorance (a belief spread
    over places that include the true one) is not. ``false_beliefs`` lists the items whose
    false belief is more probable than not.
    """

    agent: Id
    beliefs: tuple[ItemBelief, ...]
    preference: tuple[Prob, ...]
    intention: Intention | None = None
    false_beliefs: tuple[Id, ...] = ()
    false_belief: tuple[Prob, ...] = ()
    desire: Desire | None = None
    worlds: tuple[WorldBelief, ...] = ()
    nested_beliefs: tuple[NestedBelief, ...] = ()
    """Protocol 1.3: per other person B, where this person believes B believes each item is
    (what this person can tell of B's percepts: what B saw while this person saw B)."""
    mode: tuple[Prob, ...] = ()
    """Protocol 1.7: P(each mode) of the person's current mode beside their lasting desire:
    ``pursue`` (acting on it), ``errand`` (out and back: a walk out that is not a want to
    leave) and ``carry`` (putting an item away or carrying it to someone: a carry that is not
    a want for the item); empty when the brain's model has no modes. ``preference`` is then
    the lasting desire's: an errand or a carry does not move it."""
    carry: tuple[Prob, ...] = ()
    """Protocol 1.7: per item id, P(the person is carrying it away): ``carry`` of ``mode``
    item by item."""


class TaskOutcome(enum.Enum):
    """How a robot's task ended."""

    DONE = "done"
    DROPPED = "dropped"


class TaskEnd(msgspec.Struct, frozen=True):
    """A robot task that ended at this tick (protocol 1.3)."""

    task: str
    """The kind of task, as ``RobotActivity.task`` named it while it ran (e.g. ``"put back"``)."""
    detail: str
    """What it was, as ``RobotActivity.detail`` said while it ran."""
    outcome: TaskOutcome
    reason: str = ""
    """Why it was dropped, e.g. ``"no longer needed: A1 took the ball"`` (empty when done)."""


class LikelyDeception(msgspec.Struct, frozen=True):
    """The robot's reading of a move as a likely deception (protocol 1.3): ``mover`` moved
    ``item``, which ``person`` wants, believing ``person`` did not see; ``p`` is P(the mover
    thinks the person still believes it where it was) x P(the person wants it)."""

    mover: Id
    person: Id
    item: Id
    p: Probability


class RobotActivity(msgspec.Struct, frozen=True):
    """What a robot is doing: its current ``task`` and the last thing it said."""

    robot: Id
    task: str
    """e.g. ``"idle"``, ``"inform"``, ``"swap"``, ``"put back"``, ``"go home"``."""
    detail: str = ""
    utterance: str | None = None
    ended: TaskEnd | None = None
    """The task that ended at this tick, if one did (protocol 1.3): a begun task is carried
    through, or dropped with its reason."""
    deceptions: tuple[LikelyDeception, ...] = ()
    """Moves that stand and read as likely deceptions at this tick (protocol 1.3)."""


class Mind(Message, frozen=True, kw_only=True, tag="mind"):
    """The brain's estimates at engine tick ``tick``."""

    episode: Annotated[int, msgspec.Meta(ge=0)]
    tick: Tick
    agents: tuple[AgentMind, ...]
    robots: tuple[RobotActivity, ...] = ()
