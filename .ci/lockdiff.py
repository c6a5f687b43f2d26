"""Print which installed packages differ from the lock (``make test-latest`` runs this before
the suite, so a failure there can be traced to the release that caused it). pip, and the
setuptools a venv is seeded with, are not dependencies and are left out.

Usage: python .ci/lockdiff.py constraints.txt
"""

from __future__ import annotations

import sys
from importlib import metadata
from pathlib import Path

from packaging.requirements import Requirement
from packaging.utils import canonicalize_name


def pins(lock: Path) -> dict[str, str]:
    """Package name -> pinned version, for the lines of the lock that apply here."""
    out = {}
    for line in lock.read_text().splitlines():
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        req = Requirement(line)
        if req.marker is None or req.marker.evaluate():
            out[canonicalize_name(req.name)] = next(iter(req.specifier)).version
    return out


def main(lock: Path) -> int:
    installed = {canonicalize_name(d.metadata["Name"]): d.version for d in metadata.distributions()}
    locked = pins(lock)
    rows = [
        (name, locked.get(name, "-"), installed.get(name, "-"))
        for name in sorted(set(locked) | set(installed) - {"toyroom", "pip", "setuptools"})
        if locked.get(name) != installed.get(name)
    ]
    if not rows:
        print(f"the newest releases are those of {lock}")
    for name, old, new in rows:
        print(f"{name:30} {old:>14} (lock) -> {new} (under test)")
    return 0


if __name__ == "__main__":
    sys.exit(main(Path(sys.argv[1])))
