"""Files shipped inside the packages (maps, scenarios, ground truth, schemas, examples),
found with :mod:`importlib.resources` so they work from a source checkout and an installed
wheel alike."""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path


def bundled_dir(package: str, name: str) -> Path:
    """The package-data folder ``name`` of ``package`` as a filesystem path.

    Raises:
        RuntimeError: when the package is not installed as files (e.g. imported from a zip),
            naming the package.
    """
    folder = files(package) / name
    if not isinstance(folder, Path):
        raise RuntimeError(f"package {package!r} is not installed as files ({folder!r}); install it unpacked")
    return folder
