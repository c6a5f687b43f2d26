"""Every top-level message type, by its ``type`` tag."""

from __future__ import annotations

import msgspec

from .control import Pause, Reset, Resume, Step
from .events import Event
from .handshake import EngineInfo, Hello
from .message import Message
from .mind import Mind
from .person import PersonCommand
from .replies import ControlReply, ErrorReply
from .robot import CommandStatus, Heartbeat, RobotCommand
from .state import State
from .truth import Truth

MESSAGE_TYPES: tuple[type[Message], ...] = (
    Hello,
    EngineInfo,
    Reset,
    Step,
    Pause,
    Resume,
    ControlReply,
    ErrorReply,
    State,
    Event,
    Truth,
    RobotCommand,
    CommandStatus,
    Heartbeat,
    Mind,
    PersonCommand,
)
"""All message types, in the order the documentation lists them."""


def tag_of(cls: type[msgspec.Struct]) -> str:
    """The tag of a message class (its ``type``: ``State`` -> ``"state"``) or of a gateway
    frame class (its ``op``: ``Put`` -> ``"put"``)."""
    tag = cls.__struct_config__.tag
    assert isinstance(tag, str)  # every registered class sets a string tag
    return tag


BY_TAG: dict[str, type[Message]] = {tag_of(cls): cls for cls in MESSAGE_TYPES}
"""Message classes keyed by their ``type`` tag."""
