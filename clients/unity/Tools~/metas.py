"""The Unity package's ``.meta`` files: one beside every file and folder Unity imports.

Installed from a git URL, a package is immutable: Unity cannot write the ``.meta`` files it
would make in a project, and it ignores every asset without one ("has no meta file, but it's
in an immutable folder"). So they are committed, each with a GUID that is stable (the MD5 of
the package name and the asset's path in the package: the same path always gets the same
GUID) and unique, and the importer block Unity writes for that type.

Unity skips names that start with ``.`` or end with ``~`` (and ``cvs``, ``*.tmp``), with all
they hold: this folder (``Tools~``), ``Samples~`` (copied into a project, which then makes its
own metas) and ``.build`` (the Mono builds) need none.

Usage, from the repository root::

    python "clients/unity/Tools~/metas.py"          # write the missing metas
    python "clients/unity/Tools~/metas.py" --check  # list missing, stray or stale ones; exit 1

A new file or folder in the package needs its meta committed with it (the tests check).
Renaming one gives it a new GUID: references to it from users' scenes would break, so rename
assets only when nobody refers to them.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import sys
from collections.abc import Iterator
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1]
"""The package's folder, ``clients/unity``."""

TAIL = "  externalObjects: {}\n  userData: \n  assetBundleName: \n  assetBundleVariant: \n"
"""The lines every importer block ends with, as Unity writes them."""

MONO_IMPORTER = (
    "MonoImporter:\n  externalObjects: {}\n  serializedVersion: 2\n  defaultReferences: []\n"
    "  executionOrder: 0\n  icon: {instanceID: 0}\n  userData: \n  assetBundleName: \n"
    "  assetBundleVariant: \n"
)


def ignored(name: str) -> bool:
    """Whether Unity's asset database skips a file or folder of this name (and its contents)."""
    return name.startswith(".") or name.endswith("~") or name == "cvs" or name.endswith(".tmp")


def assets(package: Path = PACKAGE) -> Iterator[Path]:
    """Every file and folder under ``package`` that Unity imports (metas excluded), sorted."""
    for path in sorted(package.iterdir()):
        if ignored(path.name) or path.suffix == ".meta":
            continue
        yield path
        if path.is_dir():
            yield from assets(path)


def guid(package_name: str, relative: str) -> str:
    """The asset's GUID: 32 lowercase hex digits from its package and its path in it."""
    return hashlib.md5(f"{package_name}/{relative}".encode()).hexdigest()


def importer(path: Path, package: Path = PACKAGE) -> str:
    """The importer block Unity writes for this asset of ``package``."""
    if path.is_dir():
        return "folderAsset: yes\nDefaultImporter:\n" + TAIL
    if path.suffix == ".cs":
        return MONO_IMPORTER
    if path.suffix == ".asmdef":
        return "AssemblyDefinitionImporter:\n" + TAIL
    if path == package / "package.json":
        return "PackageManifestImporter:\n" + TAIL
    if path.suffix in (".md", ".json", ".txt", ".xml", ".yaml", ".csv"):
        return "TextScriptImporter:\n" + TAIL
    return "DefaultImporter:\n" + TAIL


def meta_text(path: Path, package: Path = PACKAGE) -> str:
    """The ``.meta`` file's text for ``path`` in ``package``."""
    name = json.loads((package / "package.json").read_text(encoding="utf-8"))["name"]
    relative = path.relative_to(package).as_posix()
    return f"fileFormatVersion: 2\nguid: {guid(name, relative)}\n{importer(path, package)}"


def meta_of(path: Path) -> Path:
    """The ``.meta`` beside an asset."""
    return path.with_name(path.name + ".meta")


def problems(package: Path = PACKAGE) -> list[str]:
    """What is wrong with the committed metas: missing, stale (not what :func:`meta_text`
    makes) or stray (beside nothing Unity imports); empty when all is well."""
    found = []
    wanted = set()
    for path in assets(package):
        meta = meta_of(path)
        wanted.add(meta)
        rel = meta.relative_to(package)
        if not meta.is_file():
            found.append(f"missing: {rel}")
        elif meta.read_text(encoding="utf-8") != meta_text(path, package):
            found.append(f"stale: {rel} (not what this script makes)")
    for meta in sorted(package.rglob("*.meta")):
        inside = meta.relative_to(package).parts
        if meta not in wanted and not any(ignored(part) for part in inside[:-1]):
            found.append(f"stray: {meta.relative_to(package)} (no asset beside it)")
    return found


def write_missing(package: Path = PACKAGE) -> list[Path]:
    """Write the metas that are missing (existing ones are kept as they are); the new ones."""
    written = []
    for path in assets(package):
        meta = meta_of(path)
        if not meta.exists():
            meta.write_text(meta_text(path, package), encoding="utf-8")
            written.append(meta)
    return written


def main(check: bool) -> int:
    """Write the missing metas, or with ``check`` list every problem; the exit status."""
    if check:
        found = problems()
        for line in found:
            print(line)
        return 1 if found else 0
    for meta in write_missing():
        print(f"wrote {meta.relative_to(PACKAGE)}")
    return 0


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="list missing, stale or stray metas; exit 1")
    sys.exit(main(parser.parse_args().check))
