"""The handshake: version checks on both sides, and the scene checked on arrival."""

from __future__ import annotations

import logging

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
    handshake(client, client="newer", hello=Hello(client="newer", protocol="1.4"), timeout=5.0)
    assert "client 'newer'" in caplog.text and "1.4" in caplog.text, caplog.text


def test_inconsistent_scene_fails_the_handshake(bridges: tuple[Bridge, Bridge]) -> None:
    engine, client = bridges
    info = _info()
    broken = msgspec.structs.replace(info.scene, doors=())
    serve_info(engine, lambda: msgspec.structs.replace(info, scene=broken))
    with pytest.raises(InvalidScene, match="unreachable"):
        handshake(client, client="test", timeout=5.0)


def test_no_engine_times_out_with_a_clear_error(bridges: tuple[Bridge, Bridge]) -> None:
    _, client = bridges
    with pytest.raises(NoReply, match="no engine answered the handshake"):
        handshake(client, client="test", timeout=0.5)
