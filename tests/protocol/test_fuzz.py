"""Property-based: random bytes and mutated golden examples never make the decoder raise
anything but ProtocolError."""

from __future__ import annotations

import json
from typing import Any

import msgspec
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from protocol import BY_TAG, Encoding, Message, ProtocolError, decode, encode
from protocol.examples import example_paths

EXAMPLES = {tag: path.read_bytes() for tag, path in example_paths().items()}
TAGS = sorted(EXAMPLES)


def _decode_or_protocol_error(data: bytes, encoding: Encoding, expected: type[Message] | None) -> None:
    try:
        decode(data, expected, encoding)
    except ProtocolError:
        pass  # the one allowed failure; anything else propagates and fails the test


@settings(max_examples=400, deadline=None)
@given(data=st.binary(max_size=512), encoding=st.sampled_from(list(Encoding)), typed=st.booleans())
def test_random_bytes(data: bytes, encoding: Encoding, typed: bool) -> None:
    _decode_or_protocol_error(data, encoding, BY_TAG["state"] if typed else None)


@settings(max_examples=300, deadline=None)
@given(
    tag=st.sampled_from(TAGS),
    encoding=st.sampled_from(list(Encoding)),
    edits=st.lists(
        st.tuples(st.sampled_from(["flip", "delete", "insert"]), st.integers(0, 10**6), st.integers(0, 255)),
        min_size=1,
        max_size=8,
    ),
)
def test_byte_mutations_of_golden_examples(tag: str, encoding: Encoding, edits: list) -> None:
    data = bytearray(encode(decode(EXAMPLES[tag]), encoding))
    for op, pos, value in edits:
        pos %= max(len(data), 1)
        if op == "flip" and data:
            data[pos] ^= value or 1
        elif op == "delete" and data:
            del data[pos]
        else:
            data.insert(pos, value)
    _decode_or_protocol_error(bytes(data), encoding, None)


json_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers(-(2**70), 2**70)
    | st.floats(allow_nan=True)
    | st.text(max_size=12),
    lambda children: (
        st.lists(children, max_size=4) | st.dictionaries(st.text(max_size=8), children, max_size=4)
    ),
    max_leaves=12,
)


def _paths(node: Any, prefix: tuple = ()) -> list[tuple]:
    out = [prefix]
    if isinstance(node, dict):
        for key, child in node.items():
            out += _paths(child, prefix + (key,))
    elif isinstance(node, list):
        for i, child in enumerate(node):
            out += _paths(child, prefix + (i,))
    return out


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    tag=st.sampled_from(TAGS),
    choice=st.integers(0, 10**6),
    value=json_values,
    drop=st.booleans(),
    encoding=st.sampled_from(list(Encoding)),
)
def test_structural_mutations_of_golden_examples(
    tag: str, choice: int, value: Any, drop: bool, encoding: Encoding
) -> None:
    doc = json.loads(EXAMPLES[tag])
    paths = _paths(doc)[1:]
    path = paths[choice % len(paths)]
    parent = doc
    for step in path[:-1]:
        parent = parent[step]
    if drop and isinstance(parent, dict):
        del parent[path[-1]]
    else:
        parent[path[-1]] = value
    if encoding is Encoding.JSON:
        data = json.dumps(doc).encode()
    else:
        try:
            data = msgspec.msgpack.encode(doc)
        except OverflowError:  # integers beyond 64 bits have no MessagePack form
            assume(False)
    _decode_or_protocol_error(data, encoding, None)
    _decode_or_protocol_error(data, encoding, BY_TAG[tag])
