"""What the gateway checks of a client's frame and of a payload it carries, either way.

A frame that is refused becomes a :class:`Refusal`, which the link answers with an ``error``
frame naming what is wrong (the link stays open); a Zenoh payload handed to a client must
be one JSON value in UTF-8 (MessagePack is transcoded), or it would break the text frame.
"""

from __future__ import annotations

import msgspec

from protocol import Encoding, ProtocolError, decode
from protocol.frames import ClientFrame

_frames = msgspec.json.Decoder(ClientFrame)
_encoder = msgspec.json.Encoder()


class Refusal(Exception):
    """A frame is refused: becomes a :class:`FrameError` to the client."""

    def __init__(self, code: str, message: str, ref: int | None = None) -> None:
        super().__init__(message)
        self.code, self.message, self.ref = code, message, ref


def to_json(payload: bytes, mime: str | None) -> bytes:
    """A Zenoh payload as JSON bytes fit to embed in a frame (MessagePack is transcoded).

    Raises:
        ValueError: the payload is neither valid JSON nor valid MessagePack.
    """
    if Encoding.from_mime(mime) is Encoding.MSGPACK:
        return _encoder.encode(msgspec.msgpack.decode(payload))
    # one JSON value in UTF-8, or the text frame would break: checked, not decoded (a fifth
    # of the time, for every subscriber of every state)
    msgspec.json.decode(payload, type=msgspec.Raw)
    payload.decode("utf-8")
    return payload


TOO_DEEP = "nested too deeply to decode"
"""What a frame or payload nested too deeply to decode is told (msgspec's depth limit)."""


def checked_payload(raw: msgspec.Raw, where: str, ref: int | None) -> bytes:
    """A frame's payload after checking that it is a protocol message (any minor version)."""
    data = bytes(raw)
    try:
        decode(data, None, Encoding.JSON)
    except ProtocolError as err:
        raise Refusal("bad_payload", f"{where}: {err}", ref) from None
    except RecursionError:  # nested deeper than the decoder goes: not a message
        raise Refusal("bad_payload", f"{where}: {TOO_DEEP}", ref) from None
    return data


def read_frame(data: bytes) -> ClientFrame:
    """One client frame, decoded.

    Raises:
        Refusal: ``bad_frame`` naming what is wrong: not JSON, not a frame, a field of the
            wrong type, or nested too deeply to decode (which raises ``RecursionError`` in the
            decoder; caught here so that such a frame is refused like any other).
    """
    try:
        return _frames.decode(data)
    except msgspec.DecodeError as err:
        raise Refusal("bad_frame", f"not a gateway frame ({err}): {data[:120]!r}") from None
    except RecursionError:
        raise Refusal("bad_frame", f"not a gateway frame ({TOO_DEEP}): {data[:40]!r}...") from None
