"""JSON Schemas of the messages, generated from the Structs and checked in.

``protocol/schema/<type>.json`` holds the schema of each message (draft 2020-12), so a
client in another language can validate or generate code without reading Python;
``protocol/schema/gateway/<op>.json`` the schema of each gateway frame (:mod:`protocol.frames`).
"""

from __future__ import annotations

import inspect
import json
from pathlib import Path
from typing import Any

import msgspec

from .bundled import bundled_dir
from .frames import FRAME_TYPES, FRAMES_VERSION, Frame
from .registry import MESSAGE_TYPES, tag_of
from .version import PROTOCOL_VERSION

SCHEMA_DIR = bundled_dir("protocol", "schema")
"""Where the checked-in schemas live."""


NULL = {"type": "null"}


def normalised(node: Any) -> Any:
    """``node`` with what msgspec releases write differently made one way, recursively.

    - every ``description`` cleaned by :func:`inspect.cleandoc` (msgspec copies docstrings
      raw up to 0.22, cleaned from 0.23 on; cleaning is idempotent);
    - in an ``anyOf``, ``{"type": "null"}`` last (0.18 lists it first, 0.23 last).
    """
    if isinstance(node, dict):
        return {key: _clean(key, value) for key, value in node.items()}
    if isinstance(node, list):
        return [normalised(value) for value in node]
    return node


def _clean(key: str, value: Any) -> Any:
    if key == "description" and isinstance(value, str):
        return inspect.cleandoc(value)
    if key == "anyOf" and isinstance(value, list):
        value = [v for v in value if v != NULL] + [v for v in value if v == NULL]
    return normalised(value)


def message_schema(cls: type[msgspec.Struct]) -> dict[str, Any]:
    """The JSON Schema of one message class, self-contained (its ``$defs`` included), with
    what a msgspec release may format differently normalised (:func:`normalised`)."""
    tag = tag_of(cls)
    body = normalised(msgspec.json.schema(cls))
    # The envelope's ``protocol`` has a default for senders, but decoders require it.
    definition = body["$defs"][cls.__name__]
    definition["required"] = ["type", "protocol"] + [
        name for name in definition.get("required", []) if name not in ("type", "protocol")
    ]
    definition["properties"]["protocol"] = {
        "type": "string",
        "pattern": r"^(0|[1-9][0-9]{0,5})\.(0|[1-9][0-9]{0,5})$",
        "description": f"Protocol version of the sender, major.minor (this schema: {PROTOCOL_VERSION}).",
    }
    schema: dict[str, Any] = {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": f"toyroom/protocol/{PROTOCOL_VERSION}/{tag}.json",
        "title": f"toyroom '{tag}' message, protocol {PROTOCOL_VERSION}",
    }
    schema.update(body)
    return schema


def frame_schema(cls: type[Frame]) -> dict[str, Any]:
    """The JSON Schema of one gateway frame class, self-contained."""
    op = tag_of(cls)
    schema: dict[str, Any] = {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": f"toyroom/gateway/{FRAMES_VERSION}/{op}.json",
        "title": f"toyroom gateway '{op}' frame, frames {FRAMES_VERSION}",
    }
    schema.update(normalised(msgspec.json.schema(cls)))
    return schema


def _text(schema: dict[str, Any]) -> str:
    return json.dumps(schema, indent=2, sort_keys=True) + "\n"


def render_all() -> dict[str, str]:
    """Every schema file's path (relative to the schema directory) and exact text (sorted
    keys, 2-space indent, final newline): the messages, then ``gateway/`` the frames."""
    files = {f"{tag_of(cls)}.json": _text(message_schema(cls)) for cls in MESSAGE_TYPES}
    files.update({f"gateway/{tag_of(cls)}.json": _text(frame_schema(cls)) for cls in FRAME_TYPES})
    return files


def _existing(directory: Path) -> list[str]:
    return sorted(p.relative_to(directory).as_posix() for p in directory.glob("**/*.json"))


def write_schemas(directory: Path = SCHEMA_DIR) -> list[Path]:
    """Write every schema into ``directory`` (removing stale ``*.json`` there); return the paths."""
    directory.mkdir(parents=True, exist_ok=True)
    wanted = render_all()
    for old in _existing(directory):
        if old not in wanted:
            (directory / old).unlink()
    paths = []
    for name, text in wanted.items():
        path = directory / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
        paths.append(path)
    return paths


def stale_schemas(directory: Path = SCHEMA_DIR) -> list[str]:
    """What differs between ``directory`` and freshly generated schemas, one line per file."""
    wanted = render_all()
    problems = []
    for name, text in wanted.items():
        path = directory / name
        if not path.exists():
            problems.append(f"{name}: missing")
        elif path.read_text(encoding="utf-8") != text:
            problems.append(f"{name}: out of date")
    for old in _existing(directory) if directory.exists() else []:
        if old not in wanted:
            problems.append(f"{old}: no such message or frame any more")
    return problems
