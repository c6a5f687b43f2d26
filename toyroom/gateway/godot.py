"""The Godot add-on's sample engine (``clients/godot/``), run headless with Debian's
``godot3-server`` (Godot 3.2; ``make test`` installs it).

``clients/godot/`` is a Godot 3.2 project in text formats only (``project.godot``, ``.tscn``,
``.gd``): nothing to build. Its main scene plays the scenarios that ``toyroom
export-scenario`` writes, as an engine of the world a ``toyroom gateway`` carries; its options
come after ``--`` on Godot's command line.
"""

from __future__ import annotations

import shutil
from pathlib import Path

from bridge.errors import BridgeError
from bridge.processes import CHECKOUT

from .csharp import export_scenario

__all__ = ["PROJECT", "GODOT", "engine_command", "export_scenario", "godot"]

PROJECT = CHECKOUT / "clients" / "godot"
GODOT = "godot3-server"
INSTALL_HINT = "apt-get install godot3-server (make test does it)"


def godot() -> str:
    """The path of ``godot3-server``.

    Raises:
        BridgeError: it is not installed, or there is no source checkout to run.
    """
    if not (PROJECT / "project.godot").is_file():
        raise BridgeError(
            "the Godot sample needs a source checkout (clients/godot/ is not in the installed package)"
        )
    found = shutil.which(GODOT)
    if found is None:
        raise BridgeError(f"Godot 3's headless server ({GODOT}) is not installed: {INSTALL_HINT}")
    return found


def engine_command(gateway: str, scenarios: Path, *args: str) -> list[str]:
    """The Godot sample's command line, on the gateway at ``gateway`` with the exports in
    ``scenarios`` (``args``: ``--scenario``, ``--robot``, ``--realtime RATE``...)."""
    return [godot(), "--path", str(PROJECT), "--", "--gateway", gateway, "--scenarios", str(scenarios), *args]
