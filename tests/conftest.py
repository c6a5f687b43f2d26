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


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Under ``pytest -n`` with ``--dist loadgroup`` (``make test``): the tests of a module that
    share a module- or package-scoped fixture (a recorded run, engines, a browser page, a Ray
    cluster) run on one worker, so the fixture is built once, not once per worker; every other
    test goes to whichever worker is free."""
    for item in items:
        infos = getattr(item, "_fixtureinfo", None)
        if infos is None:
            continue
        shared = [
            name
            for name, defs in infos.name2fixturedefs.items()
            if defs and defs[-1].scope in ("module", "package")
        ]
        if shared:
            group = item.module.__name__ if item.module is not None else item.nodeid
            item.add_marker(pytest.mark.xdist_group(name=group))
