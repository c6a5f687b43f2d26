"""JSON Schemas: generated, checked in, current, and every golden example validates."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import jsonschema
import pytest

from protocol import BY_TAG
from protocol.examples import example_paths
from protocol.schema import SCHEMA_DIR, stale_schemas


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
    return subprocess.run([sys.executable, "-m", "bridge", *args], capture_output=True, text=True, timeout=60)


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
