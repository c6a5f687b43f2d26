"""Encoding and decoding messages: JSON (canonical) and MessagePack (fast).

JSON (UTF-8) is the canonical encoding, readable by any client with no code generation.
MessagePack carries exactly the same structure, smaller and faster to parse. On Zenoh the
encoding is signalled by the sample's encoding field: ``application/json`` or
``application/msgpack``; a sample with any other encoding is read as JSON.

Decoding never raises anything but :class:`~protocol.errors.ProtocolError`.
"""

from __future__ import annotations

import enum
import re
from typing import Any, TypeVar, overload

import msgspec

from .errors import ProtocolError
from .message import Header, Id, Message
from .registry import BY_TAG, MESSAGE_TYPES
from .robot import RobotCommand, unknown_action
from .version import check_version
from .vocabulary import note_unknown

M = TypeVar("M", bound=Message)


class Encoding(enum.Enum):
    """Wire encodings, valued by their MIME type (the Zenoh encoding string)."""

    JSON = "application/json"
    MSGPACK = "application/msgpack"

    @classmethod
    def from_mime(cls, mime: str | None) -> Encoding:
        """The encoding for a Zenoh encoding string; anything but MessagePack reads as JSON."""
        if mime and mime.split(";", 1)[0].strip() == cls.MSGPACK.value:
            return cls.MSGPACK
        return cls.JSON


_json_encoder = msgspec.json.Encoder()
_msgpack_encoder = msgspec.msgpack.Encoder()
_header_decoders: dict[Encoding, msgspec.json.Decoder[Header] | msgspec.msgpack.Decoder[Header]] = {
    Encoding.JSON: msgspec.json.Decoder(Header),
    Encoding.MSGPACK: msgspec.msgpack.Decoder(Header),
}
_PATH_RE = re.compile(r"^(?P<reason>.*?)(?: - at `(?P<path>\$[^`]*)`)?$", re.DOTALL)


def _build_decoder(cls: type[Message], encoding: Encoding) -> Any:
    if encoding is Encoding.JSON:
        return msgspec.json.Decoder(cls)
    return msgspec.msgpack.Decoder(cls)


_DECODERS: dict[tuple[type[Message], Encoding], Any] = {
    (cls, encoding): _build_decoder(cls, encoding) for cls in MESSAGE_TYPES for encoding in Encoding
}
"""Every message type's decoders, built once at import. msgspec resolves a Struct's type
annotations when its first decoder is built, and two threads doing that at once can crash
the interpreter (a segfault seen in 1 of about 200 brain processes: Zenoh's subscriber
thread and the main thread each decoding a first message); at import only one thread runs."""


def encode(message: Message, encoding: Encoding = Encoding.JSON) -> bytes:
    """Encode a message; JSON output is compact UTF-8."""
    if encoding is Encoding.JSON:
        return _json_encoder.encode(message)
    return _msgpack_encoder.encode(message)


def _split(error: Exception) -> tuple[str, str | None]:
    """msgspec's ``"Expected `int`, got `str` - at `$.tick`"`` -> (reason, ``$.tick``)."""
    match = _PATH_RE.match(str(error))
    if match is None:  # pragma: no cover - the pattern matches any string
        return str(error), None
    return match.group("reason"), match.group("path")


def read_header(data: bytes, encoding: Encoding = Encoding.JSON) -> Header:
    """Read only the envelope (``type`` and ``protocol``) of a payload."""
    try:
        return _header_decoders[encoding].decode(data)
    except msgspec.ValidationError as err:
        reason, path = _split(err)
        if "missing required field" in reason:
            name = reason.rsplit("`", 2)[-2] if reason.count("`") >= 2 else None
            path = f"$.{name}" if name else path
        return _raise(f"bad envelope: {reason}", None, path)
    except Exception as err:  # msgspec.DecodeError, RecursionError, anything else
        return _raise(f"not a {encoding.name} message ({_split(err)[0]})", None, None)


def _raise(reason: str, message_type: str | None, field: str | None) -> Any:
    raise ProtocolError(reason, message_type=message_type, field=field)


@overload
def decode(data: bytes, expected: type[M], encoding: Encoding = ...) -> M: ...


@overload
def decode(data: bytes, expected: None = ..., encoding: Encoding = ...) -> Message: ...


def decode(data: bytes, expected: type[M] | None = None, encoding: Encoding = Encoding.JSON) -> Message:
    """Decode a payload into a message.

    Args:
        data: the payload bytes.
        expected: the message class the caller wants (``None``: any known message).
        encoding: how the payload is encoded.

    Raises:
        ProtocolError: the payload is not a message, is of an unknown or unexpected type,
            has a malformed field (named as a JSON path), or is of another major version
            (:class:`~protocol.errors.VersionMismatch`). Nothing else is ever raised.
    """
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise ProtocolError(f"expected bytes, got {type(data).__name__}")
    header = read_header(data, encoding)
    cls = BY_TAG.get(header.type)
    if cls is None:
        known = ", ".join(sorted(BY_TAG))
        raise ProtocolError(
            f"unknown message type {header.type!r}; known types: {known}",
            message_type=header.type,
            field="$.type",
        )
    if expected is not None and cls is not expected:
        want = expected.__struct_config__.tag
        raise ProtocolError(
            f"expected a '{want}' message, got a '{header.type}' message",
            message_type=header.type,
            field="$.type",
        )
    check_version(header.protocol, message_type=header.type)
    try:
        return _DECODERS[(cls, encoding)].decode(data)
    except msgspec.ValidationError as err:
        reason, path = _split(err)
        if cls is RobotCommand and path == "$.action.kind" and reason.startswith("Invalid value"):
            return _unknown_command(data, encoding)
        reason = _with_value(reason, _value_at(data, encoding, path))
        raise ProtocolError(reason, message_type=header.type, field=path) from None
    except Exception as err:
        raise ProtocolError(
            f"not a valid {encoding.name} document ({_split(err)[0]})", message_type=header.type
        ) from None


_MISSING = object()
_STEP_RE = re.compile(r"\.([A-Za-z_][A-Za-z0-9_]*)|\[(\d+)\]")
EMPTY_FOR_NULL = (
    'got "" (an empty string): where a value is absent, send null, not "" '
    '(Unity\'s JsonUtility writes "" for a null string: protocol/README.md, "JSON from C#")'
)


def _value_at(data: bytes, encoding: Encoding, path: str | None) -> Any:
    """The raw value at JSON path ``path`` (``$.agents[1].cell``) of a payload, or a marker
    when it cannot be found."""
    if not path or not path.startswith("$"):
        return _MISSING
    try:
        value: Any = msgspec.json.decode(data) if encoding is Encoding.JSON else msgspec.msgpack.decode(data)
    except Exception:
        return _MISSING
    for name, index in _STEP_RE.findall(path[1:]):
        try:
            value = value[int(index)] if index else value[name]
        except (KeyError, IndexError, TypeError):
            return _MISSING
    return value


def _with_value(reason: str, value: Any) -> str:
    """``reason`` saying what came, when msgspec did not (its constraint errors do not)."""
    if value == "":
        return f"{reason}, {EMPTY_FOR_NULL}"
    if value is _MISSING or ", got " in reason:
        return reason
    shown = repr(value)
    return f"{reason}, got {shown if len(shown) <= 80 else shown[:77] + '...'}"


class _LooseCommand(msgspec.Struct, frozen=True):
    """A ``robot_command`` whose action is read as a plain object."""

    protocol: str
    id: Id
    robot: Id
    action: dict[str, Any]


_LOOSE: dict[Encoding, Any] = {
    Encoding.JSON: msgspec.json.Decoder(_LooseCommand),
    Encoding.MSGPACK: msgspec.msgpack.Decoder(_LooseCommand),
}


def _unknown_command(data: bytes, encoding: Encoding) -> RobotCommand:
    """A command of a kind this side does not know, kept as an :class:`UnknownAction`."""
    try:
        loose = _LOOSE[encoding].decode(data)
    except msgspec.DecodeError as err:  # ValidationError included
        reason, path = _split(err)
        raise ProtocolError(reason, message_type="robot_command", field=path) from None
    kind = loose.action.get("kind")
    if not isinstance(kind, str) or not kind:
        raise ProtocolError(
            "expected a command kind (a string)", message_type="robot_command", field="$.action.kind"
        )
    bad = [name for name in loose.action if not (isinstance(name, str) and name.isidentifier())]
    if bad:
        raise ProtocolError(
            f"expected field names that are identifiers, got {bad[0]!r}",
            message_type="robot_command",
            field="$.action",
        )
    note_unknown("command kind", kind)
    action = unknown_action(kind, loose.action)
    return RobotCommand(protocol=loose.protocol, id=loose.id, robot=loose.robot, action=action)  # type: ignore[arg-type]


def to_builtins(message: Message) -> dict[str, Any]:
    """The message as plain JSON-compatible Python values (dicts, lists, str, numbers)."""
    result = msgspec.to_builtins(message)
    assert isinstance(result, dict)  # a Struct always converts to a dict
    return result
