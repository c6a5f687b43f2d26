"""What every simulated person is to the engine and the robot body: scripted
(:mod:`sim2d.people.scripted`), autonomous (:mod:`sim2d.people.autonomous`) or planned
(:mod:`sim2d.people.planned`)."""

from __future__ import annotations

from typing import Protocol

from ..world.world import World


class Person(Protocol):
    """What the engine and the robot body need of a simulated person."""

    id: str

    @property
    def finished(self) -> bool: ...

    def update(self, world: World) -> None: ...

    def on_given(self, world: World) -> None: ...

    def on_informed(self, world: World, item: str, location: str) -> None: ...

    def answer(self, world: World, item: str, offer: str | None = None) -> bool: ...

    def says_wanted(self, world: World, item: str | None) -> tuple[str | None, bool] | None:
        """The answer to a robot's ``ask``: ``(item, wants it)`` (an open question, ``item``
        ``None``: what they want and true, or ``(None, False)``: nothing); ``None``: no answer."""
        ...

    def on_handed_over(self, world: World) -> None: ...
