"""JSON Schemas: generated, checked in, current, and every golden example validates."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

import jsonschema
import msgspec
import pytest

from protocol import BY_TAG
from protocol.examples import example_paths
from protocol.registry import MESSAGE_TYPES, tag_of
from protocol.schema import NULL, SCHEMA_DIR, message_schema, normalised, stale_schemas


def _validator(tag: str) -> jsonschema.Draft202012Validator:
    schema = json.loads((SCHEMA_DIR / f"{tag}.json").read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


@pytest.mark.parametrize("tag", sorted(BY_TAG))
def test_golden_example_validates_against_its_schema(tag: str) -> None:
    doc = json.loads(example_paths()[tag].read_text())
    errors = [f"{e.json_path}: {e.message}" for e in _validator(tag).iter_errors(doc)]
    assert errors == [], f"example {tag}.json does not match schema {tag}.json: {errors}"


def test_schema_rejects_what_the_decoder_rejects() -> None:
    doc = json.loads(example_paths()["state"].read_text())
    doc["tick"] = -3
    assert not _validator("state").is_valid(doc), "a negative tick should fail the schema"
    del doc["protocol"]
    doc["tick"] = 3
    assert not _validator("state").is_valid(doc), "a missing protocol should fail the schema"


def test_checked_in_schemas_are_current() -> None:
    assert stale_schemas() == [], "run `toyroom schema` and commit protocol/schema/"


def _toyroom(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "toyroom", *args], capture_output=True, text=True, timeout=60
    )


def test_schema_check_command(tmp_path: Path) -> None:
    ok = _toyroom("schema", "--check")
    assert ok.returncode == 0, f"toyroom schema --check failed on the checked-in schemas: {ok.stderr}"

    assert _toyroom("schema", "--dir", str(tmp_path)).returncode == 0
    assert _toyroom("schema", "--check", "--dir", str(tmp_path)).returncode == 0
    state = tmp_path / "state.json"
    state.write_text(state.read_text().replace('"minimum": 0', '"minimum": 1'))
    (tmp_path / "teleport.json").write_text("{}")
    stale = _toyroom("schema", "--check", "--dir", str(tmp_path))
    assert stale.returncode != 0, "a modified schema should make --check fail"
    assert "state.json" in stale.stderr and "teleport.json" in stale.stderr, stale.stderr


def _as_old_msgspec(node: Any) -> Any:
    """A schema written the way msgspec 0.18-0.22 did: descriptions indented as in the
    docstring, ``{"type": "null"}`` first in an ``anyOf``."""
    if isinstance(node, dict):
        out = {}
        for key, value in node.items():
            if key == "description" and isinstance(value, str):
                out[key] = value.replace("\n", "\n    ")
            elif key == "anyOf":
                out[key] = [v for v in value if v == NULL] + [_as_old_msgspec(v) for v in value if v != NULL]
            else:
                out[key] = _as_old_msgspec(value)
        return out
    if isinstance(node, list):
        return [_as_old_msgspec(v) for v in node]
    return node


def test_old_style_rewrite_changes_what_old_msgspec_changed() -> None:
    for cls in (BY_TAG["mind"], BY_TAG["command_status"]):  # nullable fields, multi-line docstrings
        newest = msgspec.json.schema(cls)
        assert _as_old_msgspec(newest) != newest, f"{cls.__name__}: the rewrite left the schema as it was"


@pytest.mark.parametrize("cls", MESSAGE_TYPES, ids=lambda c: c.__name__)
def test_schemas_do_not_depend_on_how_msgspec_formats(cls: type) -> None:
    newest = msgspec.json.schema(cls)  # what this msgspec writes (the lock pins the newest)
    old = _as_old_msgspec(newest)
    assert normalised(old) == normalised(newest), (
        f"{cls.__name__}: the schema normalised from old-style msgspec output differs from the "
        "one normalised from this msgspec's"
    )
    on_disk = json.loads((SCHEMA_DIR / f"{tag_of(cls)}.json").read_text())
    assert json.dumps(on_disk, sort_keys=True) == json.dumps(message_schema(cls), sort_keys=True)


def test_docs_examples_and_the_example_engine_carry_the_version() -> None:
    """One protocol version everywhere a peer reads it from."""
    import json
    import re
    from pathlib import Path

    from protocol import PROTOCOL_VERSION
    from protocol.examples import example_paths

    root = Path(__file__).resolve().parents[2]
    header = (root / "protocol" / "README.md").read_text().splitlines()[0]
    assert header.endswith(f"version {PROTOCOL_VERSION}"), f"protocol/README.md starts {header!r}"
    stale = {
        t: d["protocol"]
        for t, p in example_paths().items()
        if (d := json.loads(p.read_text()))["protocol"] != PROTOCOL_VERSION
    }
    assert not stale, f"examples of another version than {PROTOCOL_VERSION}: {stale}"
    engine = (root / "examples" / "grid_engine" / "grid_world.py").read_text()
    found = re.search(r'^PROTOCOL = "([0-9.]+)"', engine, re.MULTILINE)
    assert found and found.group(1) == PROTOCOL_VERSION, f"the grid engine speaks {found and found.group(1)}"
