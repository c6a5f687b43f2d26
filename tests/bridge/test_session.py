"""Session defaults: loopback only, a port per world, and overrides."""

from __future__ import annotations

import json
import logging
import queue
from pathlib import Path

import pytest
from support import free_port, golden_examples

from bridge import Bridge, ConfigError, SessionSettings, build_config, is_loopback, world_port
from protocol import State


def test_world_port_is_stable_and_distinct() -> None:
    assert world_port("alpha") == world_port("alpha")
    assert world_port("alpha") != world_port("beta")
    assert all(17000 <= world_port(f"w{i}") < 27000 for i in range(200))


def test_default_config_is_loopback_peer_without_multicast(world: str) -> None:
    config = build_config(world, SessionSettings())
    assert json.loads(config.get_json("mode")) == "peer"
    assert json.loads(config.get_json("scouting/multicast/enabled")) is False
    delay = json.loads(config.get_json("scouting/delay"))
    assert delay == SessionSettings().scout_delay_ms == 100, f"scouting/delay {delay}, expected 100 ms"
    listen = json.loads(config.get_json("listen/endpoints"))
    connect = json.loads(config.get_json("connect/endpoints"))
    assert listen == connect == [f"tcp/127.0.0.1:{world_port(world)}"]


def test_loopback_detection() -> None:
    assert (
        is_loopback("tcp/127.0.0.1:7447") and is_loopback("tcp/localhost:1") and is_loopback("tcp/[::1]:7447")
    )
    assert not is_loopback("tcp/0.0.0.0:7447") and not is_loopback("tls/192.168.1.4:7447")


def test_non_loopback_listen_warns_without_opening(world: str, caplog: pytest.LogCaptureFixture) -> None:
    caplog.set_level(logging.WARNING, logger="toyroom.bridge")
    build_config(world, SessionSettings(listen=("tcp/0.0.0.0:7447",)))
    assert "non-loopback" in caplog.text and "0.0.0.0" in caplog.text


def test_second_session_falls_back_and_a_third_takes_over(world: str) -> None:
    """The first session holds the world port; when it leaves, a newcomer takes the port
    and the remaining session reconnects to it."""
    state = golden_examples()["state"]
    first = Bridge(world)
    second = Bridge(world)
    inbox: queue.Queue = queue.Queue()
    second.subscribe(second.keys.state, lambda m, _: inbox.put(m), expected=State)
    publisher = first.publisher(first.keys.state)
    assert publisher.wait_matched(5.0)
    publisher.put(state)
    assert inbox.get(timeout=5.0) == state
    first.close()

    third = Bridge(world)
    try:
        publisher = third.publisher(third.keys.state)
        assert publisher.wait_matched(5.0), "the remaining session never reconnected"
        publisher.put(state)
        assert inbox.get(timeout=5.0) == state
    finally:
        third.close()
        second.close()


def test_config_file_override(world: str, tmp_path: Path) -> None:
    port = free_port()
    config = tmp_path / "zenoh.json5"
    config.write_text(
        "{ mode: 'peer', scouting: { multicast: { enabled: false } },"
        f" listen: {{ endpoints: ['tcp/127.0.0.1:{port}'] }} }}"
    )
    with Bridge(world, SessionSettings(config_file=config)) as listener:
        with Bridge(
            world, SessionSettings(connect=(f"tcp/127.0.0.1:{port}",), listen=("tcp/127.0.0.1:0",))
        ) as talker:
            inbox: queue.Queue = queue.Queue()
            listener.subscribe(listener.keys.state, lambda m, _: inbox.put(m), expected=State)
            publisher = talker.publisher(talker.keys.state)
            assert publisher.wait_matched(5.0)
            publisher.put(golden_examples()["state"])
            assert inbox.get(timeout=5.0).tick == 42


def test_bad_config_is_a_clear_error(world: str, tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="cannot read Zenoh config file"):
        Bridge(world, SessionSettings(config_file=tmp_path / "missing.json5"))
    with pytest.raises(ConfigError, match="cannot open a Zenoh session"):
        Bridge(world, SessionSettings(listen=("tcp/127.0.0.1:notaport",)))
