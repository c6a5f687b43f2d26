"""A page rendered to PNG in headless Chromium (Debian's ``chromium``), stopped with all its
helpers however the rendering ends."""

from __future__ import annotations

import shutil
import subprocess
import tempfile
import threading
import time
from pathlib import Path

from bridge.processes import POLL_S, stop_process_group

CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-quic",
    "--virtual-time-budget=8000",
)
"""Headless Chromium with nothing that reaches for the network (this machine's is closed)."""


def screenshot(
    url: str,
    path: Path,
    stop: threading.Event,
    *,
    width: int = 1000,
    height: int = 750,
    timeout: float = 120.0,
) -> bool:
    """Render ``url`` in headless Chromium (Debian's ``chromium``) and save a PNG; False when
    ``stop`` was set first. Chromium runs in its own process group, stopped with all its
    helpers however this returns."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    if browser is None:
        raise SystemExit("toyroom view: --screenshot needs chromium (apt-get install chromium)")
    with tempfile.TemporaryDirectory() as profile:
        command = [
            browser,
            *CHROMIUM_FLAGS,
            f"--user-data-dir={profile}",
            f"--window-size={width},{height}",
            f"--screenshot={path}",
            url,
        ]
        errors = Path(profile) / "stderr.txt"
        with errors.open("wb") as sink:  # a file, not a pipe nobody reads while it runs
            process = subprocess.Popen(
                command, stdout=subprocess.DEVNULL, stderr=sink, start_new_session=True
            )
        try:
            deadline = time.monotonic() + timeout
            while process.poll() is None:
                if stop.wait(POLL_S):
                    return False
                if time.monotonic() > deadline:
                    error = errors.read_text(errors="replace")[-2000:]
                    raise RuntimeError(f"chromium did not render {url} within {timeout:g} s: {error}")
            if process.returncode != 0:
                error = errors.read_text(errors="replace")[-2000:]
                raise RuntimeError(f"chromium exited with status {process.returncode}: {error}")
            return True
        finally:
            stop_process_group(process)
