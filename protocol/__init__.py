"""toyroom's wire protocol: typed, versioned messages, their codec, keys and schemas.

Everything an engine (sim2d, or a Unity client) and a brain say to each other is a message
defined here. See ``protocol/README.md`` for the wire-level description.
"""

from .codec import Encoding, decode, encode, read_header, to_builtins
from .control import Pause, Reset, Resume, Step
from .errors import Error, ProtocolError, VersionMismatch
from .events import Event, EventKind
from .geometry import NEIGHBOURS, Cell, GridCell, Pose, Vec2
from .handshake import Capability, ClockMode, EngineInfo, Hello
from .keys import Keys, check_name
from .message import Header, Message
from .mind import (
    AgentMind,
    Desire,
    GoalUtility,
    Intention,
    ItemBelief,
    Mind,
    Observer,
    Placement,
    Preferred,
    Prob,
    RobotActivity,
    WorldBelief,
)
from .registry import BY_TAG, MESSAGE_TYPES, tag_of
from .replies import ControlReply, ErrorCode, ErrorReply
from .robot import (
    Action,
    Cancel,
    CommandState,
    CommandStatus,
    Give,
    Heartbeat,
    Navigate,
    Pick,
    Place,
    Request,
    RobotCommand,
    Say,
    SayTopic,
)
from .scene import (
    AgentKind,
    AgentSpec,
    Door,
    ItemShape,
    ItemSpec,
    Location,
    Region,
    RegionKind,
    Scene,
    Visibility,
)
from .scene_check import InvalidScene, scene_problems, validate_scene
from .state import Activity, AgentState, ItemState, State
from .truth import ItemPlace, TrueMind, Truth
from .version import PROTOCOL_VERSION, Version, check_version

__all__ = [
    "NEIGHBOURS",
    "GridCell",
    "PROTOCOL_VERSION",
    "Action",
    "Activity",
    "AgentKind",
    "AgentMind",
    "Desire",
    "GoalUtility",
    "Placement",
    "Preferred",
    "AgentSpec",
    "AgentState",
    "BY_TAG",
    "Cancel",
    "Capability",
    "Cell",
    "ClockMode",
    "CommandState",
    "CommandStatus",
    "ControlReply",
    "Door",
    "Encoding",
    "EngineInfo",
    "Error",
    "ErrorCode",
    "ErrorReply",
    "Event",
    "EventKind",
    "Give",
    "Header",
    "Heartbeat",
    "Hello",
    "Intention",
    "InvalidScene",
    "ItemBelief",
    "ItemPlace",
    "ItemShape",
    "ItemSpec",
    "ItemState",
    "Keys",
    "Location",
    "MESSAGE_TYPES",
    "Message",
    "Observer",
    "Mind",
    "Navigate",
    "Pause",
    "Pick",
    "Place",
    "Pose",
    "Prob",
    "ProtocolError",
    "Region",
    "RegionKind",
    "Request",
    "Reset",
    "Resume",
    "RobotActivity",
    "WorldBelief",
    "RobotCommand",
    "Say",
    "SayTopic",
    "Scene",
    "State",
    "Step",
    "TrueMind",
    "Truth",
    "Vec2",
    "Version",
    "VersionMismatch",
    "Visibility",
    "check_name",
    "check_version",
    "decode",
    "encode",
    "read_header",
    "scene_problems",
    "tag_of",
    "to_builtins",
    "validate_scene",
]
