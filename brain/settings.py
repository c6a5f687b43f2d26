"""The model's and the robot's parameters, with the defaults of ``docs/model.md``, and
settings files (``--settings FILE.toml``, ``--set NAME=VALUE``)."""

from __future__ import annotations

import dataclasses
import enum
import json
import logging
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from protocol import FALSE_BELIEF_MASS, Perception

from .errors import SettingsError
from .robotsettings import (
    MIN_DECISION_SECONDS,
    ROBOT_ALLOWED,
    RobotSettings,
    check_values,
)


class UnseenWorld(enum.StrEnum):
    """How an embodied robot keeps the world it cannot see (``ModelSettings.unseen_world``):
    ``joint``, every combination of the unseen items' places (:mod:`brain.tracking.jointworld`);
    ``factored``, one belief per item (:mod:`brain.tracking.itemworld`); ``auto``, joint where
    it fits (:mod:`brain.tracking.unseen`)."""

    AUTO = "auto"
    JOINT = "joint"
    FACTORED = "factored"


@dataclass(frozen=True)
class ModelSettings:
    """Every parameter of the Theory-of-Mind model. Every float is finite and at most
    :data:`~brain.robotsettings.MAGNITUDE` (1e6) in size, so the model's numbers stay finite.

    Attributes:
        r: the paper's factor ``f``: a change of believed world weighs ``r`` times a stay
            (only matters with ``delta > 0``).
        delta: perceptual noise per item: the probability of a percept that the believed
            world would not produce.
        beta: Boltzmann rationality of the action likelihood ``P(a) ∝ exp(beta * Q)``.
        epsilon: floor mixed into every action likelihood (an impossible action never
            zeroes the forward pass).
        hazard: probability that the preference is redrawn from the prior (uniform over the
            goals, or remembered desires) at a decision; a redraw may keep it, so a change to
            another goal has ``hazard * (D - 1) / D``. It compounds exactly over a longer gap
            (``1 - (1 - hazard)^n`` over ``n`` decision times), toward the prior.
        decision_seconds: the typical time of one decision (a move to the next cell): a
            longer gap between two decisions (a wait) compounds the hazard over it. At least
            :data:`~brain.robotsettings.MIN_DECISION_SECONDS` (0.05 s).
        wait_decisions: a person who stands on their cell this many ``decision_seconds``
            since their last decision, while a decision is due (not after playing, not
            outside), has decided to wait: one Stay, with its likelihood, and one more for
            each further decision time (waiting is evidence in proportion to its length;
            ``brain/tracking/waits.py``). More than 1, since a move itself takes one decision
            time (1.5 tolerates a continuous engine's jitter); 0 ignores waits.
        discount: the planner's discount per action.
        preferred_utility: reward of playing with the preferred item.
        other_utility: reward of playing with any other item.
        leave_utility_item: reward of reaching the outside for a person who wants an item.
        leave_utility_out: reward of reaching the outside for a person who wants to leave.
        step_cost: cost of every non-terminal action.
        vi_tolerance: value iteration stops when no value moves more than this (not the exact closed form).
        exact_max_worlds: the largest number of worlds ``W = (2 L)**K`` for which the exact
            joint model is used; above it, the factored model (``brain/model/factored.py``).
        top_worlds: how many of the most probable whole worlds of each person's belief the
            outputs give (``world`` rows of ``mind.csv``, ``worlds`` in the ``mind`` message).
        belief_model: ``graded`` (the default): each person holds a belief of their own and
            plans on it by QMDP (``brain/model/graded.py``; exact model only: above
            ``exact_max_worlds`` the factored model's point beliefs are used); ``point``: each
            person is certain of one world, the robot unsure which (the paper's reading).
        prior_resolution: graded model: the grid over each item's initial belief has the
            probabilities ``c / prior_resolution`` (1: the person is sure of some location).
        ignorance: graded model: the prior probability, per item, that a person starts not
            knowing where it is (their initial belief uniform over its resting locations);
            the grid's points share the rest. 0: the grid alone.
        stale_share: graded model: the largest share of the grid's part of the prior
            (``1 - ignorance``) that goes to initial beliefs giving an item's true place (when
            the person is first seen) nothing: beliefs from before the episode that have gone
            out of date. The grid's points share it evenly, but those points are most of the
            grid on many locations; above this share they get this share. 0.6 is the grid's
            own share on 4 locations at ``prior_resolution = 2`` (scenes of up to 4 locations
            keep the grid's prior); the prior probability of a false belief is at most
            ``(1 - ignorance) stale_share`` however many locations the scene has.
        belief_update: graded model: ``predict`` (a change of world is predicted with weight
            ``r``, then the percept corrects it) or ``paper`` (the paper's single normalisation
            after summing over the previous worlds).
        false_belief_mass: a person has a false belief about an item when their belief gives
            its true location less than this times what it gives its likeliest location
            (``false_belief`` rows of ``mind.csv``): a belief spread evenly over places that
            include the true one, however many, is ignorance, not a false belief.
        desire_model: ``favourite`` (one favourite goal: an item, or ``out``; the paper's) or
            ``graded`` (a utility per goal on a grid: ``brain/model/desires.py``).
        person_planner: graded beliefs: how a person plans with their belief: ``qmdp`` (the
            expected value under it, as if it resolved after one step) or ``belief`` (value
            iteration over their discretised belief, so going to look has value;
            ``brain/model/lookahead.py``).
        perception: what the robot sees: ``omniscient`` (every item wherever it is, the
            paper's setting) or ``embodied`` (the item spots its own cell sees; every person is
            tracked; the rest is inferred jointly with the people's minds,
            :mod:`brain.tracking.worldview`).
        unseen_world: embodied: how the unseen world is kept (:class:`UnseenWorld`; ``auto``:
            the joint branches where they fit, :mod:`brain.tracking.unseen`).
        miss: the chance that a person overlooks an item coming into view (kept while it stays
            there): each person's filter keeps rows of who overlooked what, weighed by their
            decisions (:mod:`brain.model.person.lapses`); 0 (the default) turns lapses off.
        hearsay_per_s: the rate (per second) at which someone in a person's region tells them where
            they believe an item is, unheard by the robot (rows of who was told what, like
            ``miss``); 0 (the default) turns it off.
        answer_reliability: the probability that a person's answer to the robot's question
            (protocol 1.6's ``ask``) is true to what they want (:mod:`brain.model.answers`):
            evidence, not an overwrite; in (0.5, 1].
        forget_per_s: the rate (per second) at which a person's belief about each item
            drifts toward uniform over the locations (graded beliefs in the exact model; what
            is in view is put right by the next percept); 0 (the default): people never
            forget. Formerly ``forget`` (:data:`RENAMED`).
        nested_peek_per_s: the rate (per second) at which a person thinks another, out of their
            sight, may have come back and looked unseen (nested beliefs,
            :mod:`brain.model.nested`: their model of the other drifts toward their own
            belief); 0: what they last saw the other see is all they credit.
        errand_per_s: the rate (per second) at which a person pursuing their lasting desire
            starts an errand, out and back (:mod:`brain.model.modes`; graded beliefs in the
            exact model); 0 (the default, why in ``docs/model.md``): no errands, a walk out
            reads as wanting to leave.
        carry_per_s: the rate (per second) at which a person pursuing their lasting desire
            starts carrying an item away (putting it away, or to someone: the Drop ends it),
            over all items; 0 (the default): none, a carry reads as wanting the item carried.
        resume_per_s: the rate (per second) at which an errand or a carry ends on its own and
            the person resumes their desire: ``1 / resume_per_s`` is its mean length (s).
        desire_levels: graded desires: how many utilities each goal may take, evenly spaced
            from its low to its high value (``desire_levels**(K + 1) - 1``; ``**K - 1`` with no outside).
        memory_drift: households (:mod:`brain.memory`): the chance per day the model assumes
            that a person's favourites are redrawn: that much of a remembered desire is
            spread evenly over the candidates at the next day's start.
        memory_strength: households: how many looks' worth a remembered belief about an item
            counts for in the next morning's prior (:mod:`brain.model.person.remembered`).
        memory_forget: households: the share of the morning's prior, per item, that goes back
            to the grid's own weights (a night may blur what a person believed; the robot's
            own memory of where items rest is blurred alike: something may move overnight).
    """

    r: float = 8.0
    delta: float = 1e-4
    beta: float = 2.0
    epsilon: float = 1e-3
    hazard: float = 0.05
    decision_seconds: float = 0.7
    wait_decisions: float = 1.5
    discount: float = 0.95
    preferred_utility: float = 30.0
    other_utility: float = 1.0
    leave_utility_item: float = 2.0
    leave_utility_out: float = 30.0
    step_cost: float = 1.0
    vi_tolerance: float = 1e-9
    exact_max_worlds: int = 512
    top_worlds: int = 3
    belief_model: str = "graded"
    prior_resolution: int = 2
    ignorance: float = 0.5
    stale_share: float = 0.6
    belief_update: str = "predict"
    false_belief_mass: float = FALSE_BELIEF_MASS
    desire_model: str = "favourite"
    person_planner: str = "qmdp"
    desire_levels: int = 3
    perception: Perception = Perception.OMNISCIENT
    unseen_world: UnseenWorld = UnseenWorld.AUTO
    miss: float = 0.0
    hearsay_per_s: float = 0.0
    answer_reliability: float = 0.9
    forget_per_s: float = 0.0
    nested_peek_per_s: float = 0.002
    errand_per_s: float = 0.0
    carry_per_s: float = 0.0
    resume_per_s: float = 0.05
    memory_drift: float = 0.1
    memory_strength: float = 3.0
    memory_forget: float = 0.1

    def __post_init__(self) -> None:
        checks = {
            "r": self.r > 0,
            "delta": 0.0 <= self.delta < 0.5,
            "beta": self.beta >= 0,
            "epsilon": 0.0 <= self.epsilon < 1.0,
            "hazard": 0.0 <= self.hazard < 1.0,
            "decision_seconds": self.decision_seconds >= MIN_DECISION_SECONDS,
            "wait_decisions": self.wait_decisions == 0 or self.wait_decisions > 1,
            "discount": 0.0 < self.discount < 1.0,
            "belief_model": self.belief_model in ("point", "graded"),
            "prior_resolution": 1 <= self.prior_resolution <= 100,
            "ignorance": 0.0 <= self.ignorance <= 1.0,
            "stale_share": 0.0 <= self.stale_share <= 1.0,
            "belief_update": self.belief_update in ("predict", "paper"),
            "false_belief_mass": 0.0 < self.false_belief_mass <= 1.0,
            "desire_model": self.desire_model in ("favourite", "graded"),
            "desire_levels": self.desire_levels >= 2,
            "person_planner": self.person_planner in ("qmdp", "belief"),
            "top_worlds": self.top_worlds >= 0,
            "perception": self.perception in Perception.names(),
            "unseen_world": isinstance(self.unseen_world, UnseenWorld),
            "miss": 0.0 <= self.miss < 1.0,
            "hearsay_per_s": self.hearsay_per_s >= 0.0,
            "answer_reliability": 0.5 < self.answer_reliability <= 1.0,
            "forget_per_s": self.forget_per_s >= 0.0,
            "nested_peek_per_s": self.nested_peek_per_s >= 0.0,
            "vi_tolerance": self.vi_tolerance >= 0.0,
            "errand_per_s": self.errand_per_s >= 0.0,
            "carry_per_s": self.carry_per_s >= 0.0,
            "resume_per_s": self.resume_per_s > 0.0,
            "memory_drift": 0.0 <= self.memory_drift <= 1.0,
            "memory_strength": self.memory_strength >= 0.0,
            "memory_forget": 0.0 <= self.memory_forget <= 1.0,
        }
        check_values("model", self, checks, ALLOWED)
        object.__setattr__(self, "perception", Perception(self.perception))  # a name given as text


ALLOWED = {
    **ROBOT_ALLOWED,
    "r": "r > 0",
    "delta": "0 <= delta < 0.5",
    "beta": "beta >= 0",
    "epsilon": "0 <= epsilon < 1",
    "hazard": "0 <= hazard < 1",
    "decision_seconds": f"decision_seconds >= {MIN_DECISION_SECONDS:g} s: each decision time a person stands "
    "is one step of their filter, so the brain's work per engine second grows as 1 / decision_seconds",
    "wait_decisions": "0, or wait_decisions > 1",
    "discount": "0 < discount < 1",
    "belief_model": "one of point, graded",
    "prior_resolution": "an int from 1 to 100 (the grid's points grow as its power of the spots)",
    "ignorance": "0 <= ignorance <= 1",
    "stale_share": "0 <= stale_share <= 1",
    "belief_update": "one of predict, paper",
    "false_belief_mass": "0 < false_belief_mass <= 1",
    "desire_model": "one of favourite, graded",
    "desire_levels": "an int >= 2",
    "person_planner": "one of qmdp, belief",
    "top_worlds": "an int >= 0",
    "perception": f"one of {', '.join(Perception.names())}",
    "unseen_world": f"one of {', '.join(w.value for w in UnseenWorld)}",
    "miss": "0 <= miss < 1",
    "hearsay_per_s": "hearsay_per_s >= 0",
    "answer_reliability": "0.5 < answer_reliability <= 1",
    "forget_per_s": "forget_per_s >= 0",
    "nested_peek_per_s": "nested_peek_per_s >= 0",
    "vi_tolerance": "vi_tolerance >= 0",
    "errand_per_s": "errand_per_s >= 0",
    "carry_per_s": "carry_per_s >= 0",
    "resume_per_s": "resume_per_s > 0",
    "memory_drift": "0 <= memory_drift <= 1",
    "memory_strength": "memory_strength >= 0",
    "memory_forget": "0 <= memory_forget <= 1",
}
"""What the settings allow of each value they check, as their errors say it (``toyroom run``
checks them with ``python -m brain check-settings`` before any process starts)."""


@dataclass(frozen=True)
class Settings:
    """The model's and the robot's settings together, as a run uses them."""

    model: ModelSettings = ModelSettings()
    robot: RobotSettings = RobotSettings()


SECTIONS = {"model": ModelSettings, "robot": RobotSettings}
"""The tables of a settings file and the settings each holds (field names are unique across
them, so ``--set beta=3`` needs no table name; ``--set model.beta=3`` works too)."""


RENAMED = {"forget": "forget_per_s", "hearsay": "hearsay_per_s", "nested_peek": "nested_peek_per_s"}
"""Former names of settings, each read as its new name with a warning, so settings files
and ``--set`` lines written before a rename keep working."""

log = logging.getLogger(__name__)


def current_name(name: str) -> str:
    """``name``, or the new name of a setting :data:`RENAMED` (with a one-line warning)."""
    new = RENAMED.get(name)
    if new is None:
        return name
    log.warning("setting %r is now called %r: please use the new name", name, new)
    return new


def _field_types(cls: type) -> dict[str, type]:
    return {f.name: type(f.default) for f in dataclasses.fields(cls)}


def _value(section: str, name: str, value: object) -> object:
    """``value`` checked against the type of ``section.name`` (an int is a fine float)."""
    expected = _field_types(SECTIONS[section])[name]
    if issubclass(expected, enum.Enum):  # a choice: read from its value (ALLOWED names them)
        if value not in {v.value for v in expected}:
            raise SettingsError(f"{section}.{name}: {ALLOWED[name]}, got {value!r}")
        return expected(value)
    if expected is float and isinstance(value, int) and not isinstance(value, bool):
        return float(value)
    if not isinstance(value, expected) or (expected is not bool and isinstance(value, bool)):
        raise SettingsError(f"{section}.{name}: expected {expected.__name__}, got {value!r}")
    return value


def _section_of(name: str) -> tuple[str, str]:
    """``(table, field)`` for ``name`` or ``table.name`` (a former name read as the new one)."""
    if "." in name:
        section, _, field = name.partition(".")
        field = current_name(field) if section in SECTIONS else field
        if section in SECTIONS and field in _field_types(SECTIONS[section]):
            return section, field
    else:
        name = current_name(name)
        for section, cls in SECTIONS.items():
            if name in _field_types(cls):
                return section, name
    known = ", ".join(f"{s}.{n}" for s, cls in SECTIONS.items() for n in _field_types(cls))
    raise SettingsError(f"unknown setting {name!r}; known: {known}")


def parse_override(text: str) -> tuple[str, str, object]:
    """``NAME=VALUE`` (VALUE in TOML syntax, or a bare word for a string) as
    ``(table, field, value)``."""
    name, sep, raw = text.partition("=")
    if not sep or not name.strip():
        raise SettingsError(f"expected NAME=VALUE, got {text!r}")
    section, field = _section_of(name.strip())
    try:
        value: object = tomllib.loads(f"v = {raw.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        value = raw.strip()
    return section, field, _value(section, field, value)


def _read_toml(path: Path) -> dict[str, object]:
    """A settings file's tables.

    Raises:
        SettingsError: one line naming the file: missing, not UTF-8, not TOML, or nested
            deeper than ``tomllib`` can read (its recursion limit).
    """
    try:
        return tomllib.loads(path.read_text(encoding="utf-8"))
    except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise SettingsError(f"{path}: {err}") from None
    except RecursionError:
        raise SettingsError(f"{path}: not valid TOML: nested too deep to read") from None


def load_settings(path: Path | None = None, overrides: Sequence[str] = ()) -> Settings:
    """The defaults, then a settings file's ``[model]`` and ``[robot]`` tables, then each
    ``NAME=VALUE`` override.

    Raises:
        SettingsError: naming the file, the setting and what is wrong.
    """
    values: dict[str, dict[str, object]] = {section: {} for section in SECTIONS}
    if path is not None:
        data = _read_toml(path)
        for section, table in data.items():
            if section not in SECTIONS or not isinstance(table, dict):
                raise SettingsError(f"{path}: unknown table [{section}]; known: {', '.join(SECTIONS)}")
            for name, value in table.items():
                try:
                    section_, field = _section_of(f"{section}.{name}")
                    if field in values[section_]:  # TOML refuses a key twice: a former name
                        raise SettingsError(f"{section_}.{field} is set twice (once by a former name)")
                    values[section_][field] = _value(section_, field, value)
                except SettingsError as err:
                    raise SettingsError(f"{path}: {err}") from None
    for text in overrides:
        section, field, value = parse_override(text)
        values[section][field] = value
    try:
        return Settings(
            model=ModelSettings(**values["model"]),  # type: ignore[arg-type]
            robot=RobotSettings(**values["robot"]),  # type: ignore[arg-type]
        )
    except ValueError as err:
        raise SettingsError(str(err)) from None


def settings_toml(settings: Settings) -> str:
    """The settings as a TOML file that :func:`load_settings` reads back to the same."""
    lines = ["# The settings of this run (toyroom --settings reads it back)."]
    for section, values in (("model", settings.model), ("robot", settings.robot)):
        lines.append(f"\n[{section}]")
        for f in dataclasses.fields(values):
            value = getattr(values, f.name)
            text = ("true" if value else "false") if isinstance(value, bool) else repr(value)
            lines.append(f"{f.name} = {json.dumps(value) if isinstance(value, str) else text}")
    return "\n".join(lines) + "\n"
