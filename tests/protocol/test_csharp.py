"""The C# SDK's generated message classes: up to date with the schemas, and shaped as the
generator promises (checked on the text here; compiled and run under Mono in tests/clients)."""

from __future__ import annotations

import re
from pathlib import Path

from protocol.csharp import pascal, render_from_schemas
from protocol.registry import MESSAGE_TYPES, tag_of

GENERATED = Path(__file__).resolve().parents[2] / "clients/unity/Runtime/Protocol/Messages.g.cs"


def test_the_checked_in_classes_are_up_to_date() -> None:
    assert GENERATED.read_text(encoding="utf-8") == render_from_schemas(), (
        "run `toyroom schema --csharp` and commit clients/unity/Runtime/Protocol/Messages.g.cs"
    )


def test_every_message_has_a_class_with_its_tag() -> None:
    text = render_from_schemas()
    for cls in MESSAGE_TYPES:
        body = re.search(rf"public sealed class {cls.__name__}\n    \{{(.*?)\n    \}}", text, re.DOTALL)
        assert body is not None, f"no C# class {cls.__name__}"
        assert f'public const string Tag = "{tag_of(cls)}";' in body.group(1), f"{cls.__name__}: tag"
        assert "public string Protocol { get; set; } = Version.Protocol;" in body.group(1)


def test_names_and_nullables() -> None:
    assert pascal("held_by") == "HeldBy" and pascal("p") == "P"
    text = render_from_schemas()
    assert '[JsonProperty("held_by")]\n        public string HeldBy' in text
    assert "public bool? Answer { get; set; }" in text, "a nullable bool must stay nullable"
    assert "public List<AgentState> Agents { get; set; } = new List<AgentState>();" in text
    assert 'case "navigate": concrete = typeof(Navigate); break;' in text
    assert "public JToken Payload { get; set; }" in text, "an optional frame payload is a JToken"
