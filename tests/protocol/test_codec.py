"""The codec: golden examples round-trip, and every failure is a ProtocolError that names
the message type and the offending field."""

from __future__ import annotations

import json

import msgspec
import pytest

from protocol import (
    BY_TAG,
    MESSAGE_TYPES,
    PROTOCOL_VERSION,
    Encoding,
    ProtocolError,
    RobotCommand,
    State,
    VersionMismatch,
    decode,
    encode,
    tag_of,
)
from protocol.examples import example_paths


def _example_doc(tag: str) -> dict:
    return json.loads(example_paths()[tag].read_text())


def test_there_is_one_golden_example_per_message_type() -> None:
    have = set(example_paths())
    want = {tag_of(cls) for cls in MESSAGE_TYPES}
    assert have == want, f"examples missing: {want - have}, examples of no message: {have - want}"


@pytest.mark.parametrize("tag", sorted(BY_TAG))
@pytest.mark.parametrize("encoding", list(Encoding))
def test_golden_example_round_trips(tag: str, encoding: Encoding) -> None:
    message = decode(example_paths()[tag].read_bytes(), BY_TAG[tag])
    again = decode(encode(message, encoding), BY_TAG[tag], encoding)
    assert again == message, f"{tag} changed in a {encoding.name} round trip: {message} -> {again}"


def test_json_starts_with_the_envelope() -> None:
    doc = encode(decode(example_paths()["step"].read_bytes()))
    assert doc.startswith(b'{"type":"step","protocol":"' + PROTOCOL_VERSION.encode()), doc


def test_bad_field_names_type_and_path() -> None:
    doc = _example_doc("state")
    doc["agents"][1]["cell"]["col"] = "three"
    with pytest.raises(ProtocolError) as caught:
        decode(json.dumps(doc).encode(), State)
    err = caught.value
    assert (err.message_type, err.field) == ("state", "$.agents[1].cell.col"), str(err)
    assert "Expected `int`, got `str`" in err.reason


def test_out_of_range_value_is_refused() -> None:
    doc = _example_doc("state")
    doc["tick"] = -1
    with pytest.raises(ProtocolError) as caught:
        decode(json.dumps(doc).encode())
    assert caught.value.field == "$.tick", str(caught.value)


def test_a_constraint_error_says_what_came() -> None:
    doc = _example_doc("state")
    doc["tick"] = -1
    with pytest.raises(ProtocolError) as caught:
        decode(json.dumps(doc).encode())
    assert caught.value.reason.endswith(", got -1"), caught.value.reason


@pytest.mark.parametrize("encoding", list(Encoding))
def test_an_empty_string_for_null_says_send_null(encoding: Encoding) -> None:
    """What Unity's JsonUtility writes for a null string."""
    doc = _example_doc("state")
    doc["agents"][0]["holding"] = ""
    payload = encode(decode(json.dumps(_example_doc("state")).encode()), encoding)
    raw = json.dumps(doc).encode() if encoding is Encoding.JSON else msgspec.msgpack.encode(doc)
    assert decode(payload, State, encoding)  # the same message with null decodes
    with pytest.raises(ProtocolError) as caught:
        decode(raw, State, encoding)
    err = caught.value
    assert err.field == "$.agents[0].holding" and 'send null, not ""' in err.reason, str(err)


def test_missing_envelope_fields_are_named() -> None:
    for missing in ("type", "protocol"):
        doc = _example_doc("step")
        del doc[missing]
        with pytest.raises(ProtocolError) as caught:
            decode(json.dumps(doc).encode())
        assert caught.value.field == f"$.{missing}", f"dropping {missing}: {caught.value}"


def test_unknown_message_type_is_named() -> None:
    doc = _example_doc("step")
    doc["type"] = "teleport"
    with pytest.raises(ProtocolError) as caught:
        decode(json.dumps(doc).encode())
    assert caught.value.message_type == "teleport" and caught.value.field == "$.type"
    assert "unknown message type 'teleport'" in str(caught.value)


def test_a_command_of_unknown_kind_with_a_field_name_no_struct_can_hold_is_refused() -> None:
    """Found by fuzzing: a field name that is not an identifier used to raise a TypeError."""
    doc = _example_doc("robot_command")
    doc["action"] = {"kind": "wave", "hand side": "left"}
    with pytest.raises(
        ProtocolError, match="expected field names that are identifiers, got 'hand side'"
    ) as caught:
        decode(json.dumps(doc).encode())
    assert caught.value.field == "$.action"


def test_unexpected_message_type_is_refused() -> None:
    with pytest.raises(ProtocolError, match="expected a 'state' message, got a 'step' message"):
        decode(example_paths()["step"].read_bytes(), State)


def test_major_version_mismatch_names_both_versions() -> None:
    doc = _example_doc("state")
    doc["protocol"] = "2.0"
    with pytest.raises(VersionMismatch) as caught:
        decode(json.dumps(doc).encode())
    assert caught.value.ours == PROTOCOL_VERSION and caught.value.theirs == "2.0"
    assert PROTOCOL_VERSION in str(caught.value) and "2.0" in str(caught.value)


def test_newer_minor_version_with_unknown_fields_decodes() -> None:
    doc = _example_doc("state")
    doc["protocol"] = "1.7"
    doc["weather"] = "sunny"
    message = decode(json.dumps(doc).encode(), State)
    assert message.protocol == "1.7" and message.tick == doc["tick"]


def test_malformed_version_is_named() -> None:
    doc = _example_doc("step")
    doc["protocol"] = "one"
    with pytest.raises(ProtocolError) as caught:
        decode(json.dumps(doc).encode())
    assert caught.value.field == "$.protocol"


def test_inconsistent_say_is_refused() -> None:
    doc = _example_doc("robot_command")
    doc["action"]["location"] = None
    with pytest.raises(ProtocolError, match="needs field 'location'") as caught:
        decode(json.dumps(doc).encode(), RobotCommand)
    assert caught.value.message_type == "robot_command"


def test_non_json_and_non_object_payloads() -> None:
    for payload in (b"", b"not json", b"[1, 2]", b"\xff\xfe", b'"text"'):
        with pytest.raises(ProtocolError):
            decode(payload)
    with pytest.raises(ProtocolError):
        decode(b"\x93\x01\x02\x03", encoding=Encoding.MSGPACK)


def test_msgpack_mime_is_recognised() -> None:
    assert Encoding.from_mime("application/msgpack") is Encoding.MSGPACK
    assert Encoding.from_mime("application/json") is Encoding.JSON
    assert Encoding.from_mime("zenoh/bytes") is Encoding.JSON
    assert Encoding.from_mime(None) is Encoding.JSON


def test_every_decoder_is_built_at_import() -> None:
    """No thread ever builds a decoder: two threads building their first msgspec decoders
    at once (Zenoh's subscriber thread and a node's main thread) crashed a brain process."""
    from protocol import Encoding
    from protocol.codec import _DECODERS
    from protocol.registry import MESSAGE_TYPES

    missing = [(cls.__name__, e.name) for cls in MESSAGE_TYPES for e in Encoding if (cls, e) not in _DECODERS]
    assert not missing, f"decoders built lazily (from any thread): {missing}"
