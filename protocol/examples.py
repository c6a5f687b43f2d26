"""The golden examples: one hand-checked JSON document per message in ``protocol/examples/``."""

from __future__ import annotations

from pathlib import Path

from .bundled import bundled_dir

EXAMPLES_DIR = bundled_dir("protocol", "examples")
"""Where the golden examples live; each is named ``<type>.json``."""


def example_paths() -> dict[str, Path]:
    """The golden example of each message type, keyed by type tag."""
    return {path.stem: path for path in sorted(EXAMPLES_DIR.glob("*.json"))}
