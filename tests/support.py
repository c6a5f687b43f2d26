"""Helpers shared by the tests (importable as ``support``)."""

from __future__ import annotations

import socket

from protocol import BY_TAG, Message, decode
from protocol.examples import example_paths


def free_port() -> int:
    """A TCP port on 127.0.0.1 that nothing listens on right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def golden_examples() -> dict[str, Message]:
    """Every golden example, decoded, keyed by message type."""
    return {tag: decode(path.read_bytes(), BY_TAG[tag]) for tag, path in example_paths().items()}


class EngineProcess:
    """``python -m sim2d`` as a real process on a world; a context manager that kills it."""

    def __init__(self, world: str, *args: str) -> None:
        import subprocess
        import sys

        self.world = world
        self.process = subprocess.Popen(
            [sys.executable, "-m", "sim2d", "--world", world, "--log-level", "WARNING", *args],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )

    def __enter__(self) -> EngineProcess:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except Exception:
                self.process.kill()
                self.process.wait(timeout=10)
