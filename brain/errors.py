"""Errors raised by the brain: one root and specific subclasses."""

from __future__ import annotations


class BrainError(Exception):
    """Root of every error raised by ``brain``."""


class SettingsError(BrainError, ValueError):
    """A settings file or override that names an unknown setting or a bad value."""


class StateError(BrainError, ValueError):
    """A ``state`` the brain cannot follow: an item of the scene missing from it, neither
    resting nor held, held by an agent it does not list, or resting at an unknown place."""


class NonFiniteError(BrainError, ArithmeticError):
    """A number of the model's output (a probability, a utility) is NaN or infinite: the
    brain fails rather than publish or write it (:mod:`brain.outputs.finite`).

    Attributes:
        person: whose estimate. tick: the engine tick. field: which quantity.
    """

    def __init__(self, person: str, tick: int, field: str, detail: str) -> None:
        self.person, self.tick, self.field = person, tick, field
        super().__init__(
            f"'{person}' at tick {tick}: the model's {field} not finite ({detail}): its numbers "
            "overflowed; nothing more is published (check the settings: python -m brain check-settings)"
        )


class ModelTooLarge(BrainError, MemoryError):
    """A scene whose model arrays would take more memory than the brain allows
    (:data:`brain.model.size.MAX_MODEL_BYTES`), refused before any is allocated."""


class MemoryFileError(BrainError, OSError):
    """A memory file (:mod:`brain.memory`) the brain cannot use: not a toyroom memory (another
    file, or damaged), written by a newer toyroom, or in use by another process. Raised at
    start, never read as an empty memory."""


class MemoryRequestError(BrainError, ValueError):
    """A request to a memory file (``toyroom memory forget``) that names what the file does not
    hold: a person or household it has no rows of, or a person in more than one household
    with none named."""


class MemoryInUseError(MemoryFileError):
    """A memory file another process holds (a running brain holds its file for as long as it
    runs): ``toyroom memory forget`` then asks that brain to forget (:mod:`brain.memory.requests`)."""


class EngineLost(BrainError):
    """The engine went away and did not come back within the brain's ``--lost-timeout``."""
