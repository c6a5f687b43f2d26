"""The package direction is the architecture: protocol <- bridge <- sim2d, brain.

``brain`` and ``sim2d`` meet only on the wire; ``bridge`` starts them as processes and never
imports them; ``protocol`` depends on no other package of ours. Also: lint and types.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
ALLOWED = {
    "protocol": set(),
    "bridge": {"protocol"},
    "sim2d": {"protocol", "bridge"},
    "brain": {"protocol", "bridge"},
}


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split(".")[0])
    return found


@pytest.mark.parametrize("package", sorted(ALLOWED))
def test_package_imports_only_what_it_may(package: str) -> None:
    forbidden = set(ALLOWED) - ALLOWED[package] - {package}
    offenders = {
        str(path.relative_to(ROOT)): sorted(_imports(path) & forbidden)
        for path in (ROOT / package).rglob("*.py")
        if _imports(path) & forbidden
    }
    assert offenders == {}, f"{package} may import only {sorted(ALLOWED[package])}; found {offenders}"


def _run(*command: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_ruff_is_clean() -> None:
    result = _run(sys.executable, "-m", "ruff", "check", ".")
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_is_clean() -> None:
    result = _run(sys.executable, "-m", "mypy")
    assert result.returncode == 0, result.stdout + result.stderr


def _modules(path: Path) -> set[str]:
    """The full names of the modules ``path`` imports from (absolute imports only)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module)
    return found


def test_nodes_do_not_import_the_command_line() -> None:
    """The nodes take their shared flags from bridge.flags, never the ``toyroom`` CLI."""
    offenders = sorted(
        str(path.relative_to(ROOT))
        for package in ("sim2d", "brain")
        for path in (ROOT / package).rglob("*.py")
        if "bridge.app.cli" in _modules(path)
    )
    assert offenders == [], f"nodes importing bridge.app.cli (use bridge.flags): {offenders}"
