"""``clients/unity`` loads in Unity as an immutable package (installed from a git URL): every
file and folder Unity imports has a committed ``.meta`` with a valid, unique GUID and the
importer for its type; each assembly definition's references resolve; the Mono test
assembly never reaches a user's player build. Regenerate with
``python "clients/unity/Tools~/metas.py"``."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "clients" / "unity"
METAS = PACKAGE / "Tools~" / "metas.py"
GUID = re.compile(r"^guid: ([0-9a-f]{32})$", re.MULTILINE)

UNITY_ASSEMBLIES = {"UnityEngine.TestRunner", "UnityEditor.TestRunner"}
"""Assemblies of Unity's own (the Test Framework's) an asmdef may name."""
PRECOMPILED = {"Newtonsoft.Json.dll": "com.unity.nuget.newtonsoft-json", "nunit.framework.dll": None}
"""Precompiled DLLs an asmdef may reference, and the package dependency that brings each."""


def unity_skips(name: str) -> bool:
    """Unity's asset database skips hidden names, names ending in ``~``, ``cvs`` and ``*.tmp``."""
    return name.startswith(".") or name.endswith("~") or name == "cvs" or name.endswith(".tmp")


def imported(folder: Path = PACKAGE) -> list[Path]:
    """Every file and folder Unity imports from the package (metas aside)."""
    found = []
    for path in sorted(folder.iterdir()):
        if unity_skips(path.name) or path.suffix == ".meta":
            continue
        found.append(path)
        if path.is_dir():
            found += imported(path)
    return found


def meta(path: Path) -> str:
    return path.with_name(path.name + ".meta").read_text(encoding="utf-8")


def expected_importer(path: Path) -> str:
    if path.is_dir():
        return "folderAsset: yes\nDefaultImporter:"
    if path == PACKAGE / "package.json":
        return "PackageManifestImporter:"
    return {".cs": "MonoImporter:", ".asmdef": "AssemblyDefinitionImporter:"}.get(
        path.suffix, "TextScriptImporter:"
    )


def asmdefs() -> dict[Path, dict]:
    return {p: json.loads(p.read_text(encoding="utf-8")) for p in imported() if p.suffix == ".asmdef"}


def test_every_file_and_folder_has_a_meta() -> None:
    assets = imported()
    assert {p.relative_to(PACKAGE).as_posix() for p in assets} >= {
        "package.json",
        "Runtime",
        "Runtime/Toyroom.Runtime.asmdef",
        "Runtime/Engine/EngineHost.cs",
    }
    missing = [str(p.relative_to(PACKAGE)) for p in assets if not p.with_name(p.name + ".meta").is_file()]
    assert missing == [], f"no .meta (Unity ignores these in an immutable package): {missing}"
    stray = [
        str(m.relative_to(PACKAGE))
        for m in PACKAGE.rglob("*.meta")
        if not any(unity_skips(part) for part in m.relative_to(PACKAGE).parts)
        and not m.with_name(m.name.removesuffix(".meta")).exists()
    ]
    assert stray == [], f".meta files beside nothing: {stray}"


def test_guids_are_valid_unique_and_the_importers_fit_the_types() -> None:
    seen: dict[str, str] = {}
    for path in imported():
        rel = str(path.relative_to(PACKAGE))
        text = meta(path)
        assert text.startswith("fileFormatVersion: 2\n"), f"{rel}.meta: {text[:60]!r}"
        guids = GUID.findall(text)
        assert len(guids) == 1, f"{rel}.meta: want one guid of 32 lowercase hex digits, got {text!r}"
        assert guids[0] not in seen, f"{rel} and {seen.get(guids[0])} share the guid {guids[0]}"
        seen[guids[0]] = rel
        assert expected_importer(path) in text, f"{rel}.meta lacks {expected_importer(path)!r}: {text!r}"


def test_the_metas_are_what_the_committed_script_makes() -> None:
    result = subprocess.run(
        [sys.executable, "-B", str(METAS), "--check"], capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 0, f"run python {METAS.relative_to(PACKAGE.parents[1])}:\n{result.stdout}"


def test_every_assembly_reference_resolves() -> None:
    defs = asmdefs()
    names = {d["name"]: p for p, d in defs.items()}
    assert len(names) == len(defs), f"two asmdefs share a name: {sorted(d['name'] for d in defs.values())}"
    guids = {GUID.findall(meta(p))[0]: d["name"] for p, d in defs.items()}
    dependencies = json.loads((PACKAGE / "package.json").read_text())["dependencies"]
    for path, definition in defs.items():
        assert path.stem == definition["name"], f"{path.name} names its assembly {definition['name']}"
        for ref in definition.get("references", []):
            target = guids.get(ref.removeprefix("GUID:")) if ref.startswith("GUID:") else ref
            assert target in names or target in UNITY_ASSEMBLIES, f"{path.name}: unresolved reference {ref!r}"
        for dll in definition.get("precompiledReferences", []):
            assert dll in PRECOMPILED, f"{path.name}: unknown precompiled reference {dll!r}"
            assert PRECOMPILED[dll] is None or PRECOMPILED[dll] in dependencies, (
                f"{path.name} uses {dll}, but package.json does not depend on {PRECOMPILED[dll]}"
            )


def test_every_script_is_in_an_assembly() -> None:
    """A package script outside every asmdef is not compiled the way its author meant."""
    owners = {p.parent for p in asmdefs()}
    for script in (p for p in imported() if p.suffix == ".cs"):
        assert any(folder in owners for folder in script.parents), f"{script} is in no assembly definition"
        text = script.read_text(encoding="utf-8")
        behaviour = re.search(r"class (\w+)\s*:\s*MonoBehaviour", text)
        name = behaviour.group(1) if behaviour else script.stem
        assert name == script.stem, f"{script.name}: a MonoBehaviour needs a file of its name ({name})"


@pytest.mark.parametrize(
    "asmdef", sorted(str(p.relative_to(PACKAGE)) for p in (PACKAGE / "Tests").rglob("*.asmdef"))
)
def test_the_test_assemblies_stay_out_of_player_builds(asmdef: str) -> None:
    definition = json.loads((PACKAGE / asmdef).read_text())
    assert definition.get("includePlatforms") == ["Editor"], f"{asmdef}: {definition}"
    assert "UNITY_INCLUDE_TESTS" in definition.get("defineConstraints", []), f"{asmdef}: {definition}"
    assert definition.get("autoReferenced") is False, f"{asmdef}: user code must not see the tests"
    runtime = [d for p, d in asmdefs().items() if "Tests" not in p.relative_to(PACKAGE).parts]
    for other in runtime:
        assert definition["name"] not in other.get("references", []), f"{other['name']} uses the tests"


def test_the_samples_and_tools_are_hidden_from_unity() -> None:
    manifest = json.loads((PACKAGE / "package.json").read_text())
    for sample in manifest["samples"]:
        assert (PACKAGE / sample["path"]).is_dir() and sample["path"].split("/")[0].endswith("~"), sample
    assert unity_skips(METAS.parent.name) and unity_skips(".build")
