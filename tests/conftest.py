"""Shared fixtures: unique worlds (so tests never meet each other's nodes) and bridges."""

from __future__ import annotations

import uuid
from collections.abc import Iterator

import pytest

from bridge import Bridge

pytest_plugins = ["tiers"]


@pytest.fixture
def world() -> str:
    """A world name of this test alone: its own keys and its own loopback port."""
    return f"t{uuid.uuid4().hex[:12]}"


@pytest.fixture
def bridges(world: str) -> Iterator[tuple[Bridge, Bridge]]:
    """Two bridges (two Zenoh sessions) on the test's world, over loopback."""
    with Bridge(world) as first, Bridge(world) as second:
        yield first, second
