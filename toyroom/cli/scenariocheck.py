"""``toyroom run``'s scenario, checked before any node starts: sim2d's loader reads it (and
its map) in a process of its own (``python -m sim2d scene``: the application never imports
sim2d), while the brain checks the settings, so a broken scenario (an id with a space, a
``tick_seconds`` below its floor, an unknown item) is one line and exit 2, with no node
started and no folder made, instead of an engine that fails at its start or at the handshake.
"""

from __future__ import annotations

import contextlib
import subprocess
import sys
from collections.abc import Iterator

from bridge.errors import BridgeError
from bridge.processes import node_environment

CHECK_TIMEOUT_S = 120.0
"""The most the check may take (the largest scene allowed loads in about 2 s)."""


@contextlib.contextmanager
def scenario_checked(scenario: str) -> Iterator[None]:
    """Check ``scenario`` (a bundled name or a ``.toml`` path) while the block runs.

    Raises:
        BridgeError: after the block, the loader's refusal in one line (naming the file, the
            entry and what is wrong).
    """
    command = [sys.executable, "-m", "sim2d", "scene", "--scenario", scenario]
    process = subprocess.Popen(
        command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True, env=node_environment()
    )
    try:
        yield
        _, errors = process.communicate(timeout=CHECK_TIMEOUT_S)
    finally:
        if process.poll() is None:  # the block failed, or the check hangs: it is not needed
            process.kill()
            process.communicate()
    if process.returncode != 0:
        lines = [line.removeprefix("sim2d: ") for line in errors.splitlines() if line.strip()]
        raise BridgeError(lines[-1] if lines else f"scenario {scenario}: exit status {process.returncode}")
