"""The handshake: version checks on both sides, and the scene checked on arrival."""

from __future__ import annotations

import logging
import re
import uuid

import msgspec
import pytest
from support import golden_examples

from bridge import Bridge, NoReply, handshake, serve_info
from protocol import PROTOCOL_VERSION, EngineInfo, Hello, InvalidScene, VersionMismatch


def _info(protocol: str = PROTOCOL_VERSION) -> EngineInfo:
    info = golden_examples()["engine_info"]
    assert isinstance(info, EngineInfo)
    return msgspec.structs.replace(info, protocol=protocol)


def test_same_version(bridges: tuple[Bridge, Bridge]) -> None:
    engine, client = bridges
    serve_info(engine, _info)
    info = handshake(client, client="test", timeout=5.0)
    assert info == _info()


def test_engine_of_another_major_version_is_an_error_naming_both(bridges: tuple[Bridge, Bridge]) -> None:
    engine, client = bridges
    serve_info(engine, lambda: _info("2.0"))
    with pytest.raises(VersionMismatch) as caught:
        handshake(client, client="test", timeout=5.0)
    text = str(caught.value)
    assert f"this side speaks {PROTOCOL_VERSION}" in text and "the peer speaks 2.0" in text, text


def test_client_of_another_major_version_is_refused_naming_both(bridges: tuple[Bridge, Bridge]) -> None:
    engine, client = bridges
    serve_info(engine, _info)
    with pytest.raises(VersionMismatch) as caught:
        handshake(client, client="test", hello=Hello(client="old", protocol="0.9"), timeout=5.0)
    assert caught.value.ours == "0.9" and caught.value.theirs == PROTOCOL_VERSION, str(caught.value)
    assert "0.9" in str(caught.value) and PROTOCOL_VERSION in str(caught.value)


def test_minor_mismatch_only_warns(bridges: tuple[Bridge, Bridge], caplog: pytest.LogCaptureFixture) -> None:
    engine, client = bridges
    serve_info(engine, lambda: _info("1.9"))
    caplog.set_level(logging.WARNING, logger="toyroom.bridge")
    info = handshake(client, client="test", timeout=5.0)
    assert info.protocol == "1.9"
    assert "minor versions differ" in caplog.text and "1.9" in caplog.text, caplog.text


def test_minor_mismatch_of_client_warns_on_engine(
    bridges: tuple[Bridge, Bridge], caplog: pytest.LogCaptureFixture
) -> None:
    engine, client = bridges
    serve_info(engine, _info)
    caplog.set_level(logging.WARNING, logger="toyroom.bridge")
    newer = f"{PROTOCOL_VERSION.split('.')[0]}.{int(PROTOCOL_VERSION.split('.')[1]) + 1}"  # a newer minor
    handshake(client, client="newer", hello=Hello(client="newer", protocol=newer), timeout=5.0)
    assert "client 'newer'" in caplog.text and newer in caplog.text, caplog.text


def test_a_custom_engine_is_warned_about_once_however_many_handshakes(
    bridges: tuple[Bridge, Bridge], caplog: pytest.LogCaptureFixture
) -> None:
    """An engine of protocol 1.1 with a region kind and an item shape of its own, met by a
    brain that handshakes again at every reset: the minor version, each custom value and the
    client's version are said once, not at every handshake."""
    engine, client = bridges
    tag = uuid.uuid4().hex[:8]
    caplog.set_level(logging.WARNING)
    info = _info("1.1")
    scene = info.scene
    regions = (msgspec.structs.replace(scene.regions[0], kind=f"corridor-{tag}"), *scene.regions[1:])
    items = (msgspec.structs.replace(scene.items[0], shape=f"backpack-{tag}"), *scene.items[1:])
    custom = msgspec.structs.replace(
        info, engine=f"school-{tag}", scene=msgspec.structs.replace(scene, regions=regions, items=items)
    )
    serve_info(engine, lambda: custom)
    hello = Hello(client=f"brain-{tag}", role="brain", protocol="1.1")
    for _ in range(3):
        got = handshake(client, client=hello.client, hello=hello, timeout=5.0)
        assert got.scene.regions[0].kind == f"corridor-{tag}" and got.protocol == "1.1"
    said = {
        "the engine's minor version": f"engine 'school-{tag}' speaks protocol 1.1",
        "the client's minor version": f"client 'brain-{tag}' (brain) speaks protocol 1.1",
        "the custom region kind": f"a peer sent RegionKind 'corridor-{tag}'",
        "the custom item shape": f"a peer sent ItemShape 'backpack-{tag}'",
    }
    for what, text in said.items():
        assert caplog.text.count(text) == 1, f"{what}: said {caplog.text.count(text)} times:\n{caplog.text}"


def test_inconsistent_scene_fails_the_handshake(bridges: tuple[Bridge, Bridge]) -> None:
    engine, client = bridges
    info = _info()
    broken = msgspec.structs.replace(info.scene, doors=())
    serve_info(engine, lambda: msgspec.structs.replace(info, scene=broken))
    with pytest.raises(InvalidScene, match="unreachable"):
        handshake(client, client="test", timeout=5.0)


def test_no_engine_times_out_with_a_clear_error(bridges: tuple[Bridge, Bridge]) -> None:
    _, client = bridges
    with pytest.raises(NoReply, match="no engine answered the handshake") as caught:
        handshake(client, client="test", timeout=1.5)
    message = str(caught.value)
    assert re.search(r"waited \d+\.\d s \(the limit, 1\.5 s\)", message) and "within 0" not in message, (
        f"expected how long it waited and its limit (never the last try's own timeout), got: {message}"
    )
