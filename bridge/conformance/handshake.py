"""The conformance checks of what the engine declares: the handshake (fields, version,
capabilities by name), a consistent scene (ids unique, doors joining walkable cells, every
location reachable, visibility naming known locations) and its liveliness token."""

from __future__ import annotations

from protocol import PROTOCOL_VERSION, Hello, Version, scene_problems

from ..handshake import ask_engine
from ..presence import PresenceWatcher
from .probe import CheckFailed, Probe


def check_handshake(probe: Probe) -> str:
    """The engine answers ``engine/info`` with its name, this world and a protocol of this major version."""
    info = ask_engine(probe.bridge, Hello(client="toyroom-conform", role="conform"), probe.timeout)
    probe.info = info
    ours, theirs = Version.parse(PROTOCOL_VERSION), Version.parse(info.protocol)
    if theirs.major != ours.major:
        raise CheckFailed(f"expected protocol {ours.major}.x, got {info.protocol}")
    if info.world != probe.bridge.world:
        raise CheckFailed(f"expected world '{probe.bridge.world}', got '{info.world}'")
    if not info.engine:
        raise CheckFailed("expected an engine name, got an empty string")
    return f"engine '{info.engine}', protocol {info.protocol}, capabilities " + (
        ", ".join(str(c) for c in info.capabilities) or "none"
    )


def check_scene(probe: Probe) -> str:
    """The scene is consistent (:func:`protocol.scene_problems` finds nothing)."""
    assert probe.info is not None
    problems = scene_problems(probe.info.scene)
    if problems:
        raise CheckFailed("expected a consistent scene, got: " + "; ".join(problems))
    scene = probe.info.scene
    return (
        f"{len(scene.regions)} regions, {len(scene.locations)} locations, {len(scene.agents)} agents, "
        f"{len(scene.items)} items"
    )


def check_liveliness(probe: Probe) -> str:
    """The engine holds a liveliness token under ``@alive/engine/*``."""
    watcher = PresenceWatcher(probe.bridge.session, probe.keys.alive("engine", "*"))
    try:
        if not watcher.wait_alive(timeout=probe.timeout):
            raise CheckFailed(
                f"expected a liveliness token under '{probe.keys.alive('engine', '*')}', got none"
            )
        return ", ".join(p.name for p in watcher.alive)
    finally:
        watcher.close()
