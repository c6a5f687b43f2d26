"""Zenoh key expressions of a world: everything lives under ``toyroom/<world>/``."""

from __future__ import annotations

import re
from dataclasses import dataclass

from .errors import ProtocolError

ROOT = "toyroom"
_NAME_RE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]{0,63}")


def check_name(name: str, what: str = "world") -> str:
    """Return ``name`` when it is a safe single key chunk, else raise naming what is wrong."""
    if not isinstance(name, str) or not _NAME_RE.fullmatch(name):
        raise ProtocolError(
            f"{what} name must be 1-64 letters, digits, '_' or '-' (starting with a letter or "
            f"digit), got {name!r}"
        )
    return name


@dataclass(frozen=True)
class Keys:
    """The key expressions of one world.

    >>> Keys("demo").state
    'toyroom/demo/engine/state'
    """

    world: str

    def __post_init__(self) -> None:
        check_name(self.world)

    @property
    def prefix(self) -> str:
        """``toyroom/<world>``."""
        return f"{ROOT}/{self.world}"

    @property
    def all(self) -> str:
        """Every message key of the world (not liveliness tokens): ``toyroom/<world>/**``."""
        return f"{self.prefix}/**"

    @property
    def info(self) -> str:
        """Queryable on the engine: the handshake."""
        return f"{self.prefix}/engine/info"

    @property
    def control(self) -> str:
        """Queryable on the engine: reset, step, pause, resume."""
        return f"{self.prefix}/engine/control"

    @property
    def state(self) -> str:
        """Engine -> all: the world state every tick."""
        return f"{self.prefix}/engine/state"

    @property
    def events(self) -> str:
        """Engine -> all: discrete events."""
        return f"{self.prefix}/engine/events"

    @property
    def truth(self) -> str:
        """Engine -> evaluators: simulated people's true minds."""
        return f"{self.prefix}/engine/truth"

    @property
    def mind(self) -> str:
        """Brain -> all: the inferred minds."""
        return f"{self.prefix}/brain/mind"

    def command(self, robot: str = "*") -> str:
        """Brain -> engine: commands for ``robot`` (``*``: any robot)."""
        return f"{self.prefix}/robot/{robot if robot == '*' else check_name(robot, 'robot')}/command"

    def status(self, robot: str = "*") -> str:
        """Engine -> brain: statuses of ``robot``'s commands (``*``: any robot)."""
        return f"{self.prefix}/robot/{robot if robot == '*' else check_name(robot, 'robot')}/status"

    def heartbeat(self, robot: str = "*") -> str:
        """Brain -> engine: the brain still drives ``robot`` (``*``: any robot)."""
        return f"{self.prefix}/robot/{robot if robot == '*' else check_name(robot, 'robot')}/heartbeat"

    def person_command(self, person: str = "*") -> str:
        """A participant's page -> engine: commands for ``person`` (``*``: any person;
        :class:`~protocol.person.PersonCommand`, for engines that offer puppets)."""
        return f"{self.prefix}/person/{person if person == '*' else check_name(person, 'person')}/command"

    def alive(self, role: str = "*", name: str = "*") -> str:
        """A liveliness token key ``toyroom/<world>/@alive/<role>/<name>`` (``*`` to watch)."""
        role = role if role == "*" else check_name(role, "role")
        name = name if name == "*" else check_name(name, "node")
        return f"{self.prefix}/@alive/{role}/{name}"
