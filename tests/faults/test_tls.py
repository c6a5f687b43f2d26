"""The multi-machine setup of docs/deployment.md on loopback: a router with TLS and mutual
authentication; a brain with its certificate reaches the engine's command key, a session
without a certificate cannot connect, so it cannot publish robot commands."""

from __future__ import annotations

import json
import queue
import subprocess
import sys
from pathlib import Path

import pytest
from support import free_port

from bridge import Bridge, ConfigError, SessionSettings
from protocol import Navigate, RobotCommand
from protocol.geometry import Cell


def make_certificates(directory: Path) -> None:
    """A throw-away CA, and a router and a client certificate signed by it."""

    def openssl(*args: str) -> None:
        subprocess.run(["openssl", *args], cwd=directory, check=True, capture_output=True)

    openssl(
        "req",
        "-x509",
        "-newkey",
        "rsa:2048",
        "-nodes",
        "-keyout",
        "ca.key",
        "-out",
        "ca.pem",
        "-days",
        "1",
        "-subj",
        "/CN=toyroom-test-ca",
    )
    (directory / "ext.cnf").write_text(
        "[v3]\nsubjectAltName = IP:127.0.0.1, DNS:localhost\nbasicConstraints = CA:FALSE\n"
        "extendedKeyUsage = serverAuth, clientAuth\n"
    )
    for name in ("router", "client"):
        openssl(
            "req",
            "-newkey",
            "rsa:2048",
            "-nodes",
            "-keyout",
            f"{name}.key",
            "-out",
            f"{name}.csr",
            "-subj",
            "/CN=localhost",
        )
        openssl(
            "x509",
            "-req",
            "-in",
            f"{name}.csr",
            "-CA",
            "ca.pem",
            "-CAkey",
            "ca.key",
            "-CAcreateserial",
            "-out",
            f"{name}.pem",
            "-days",
            "1",
            "-extfile",
            "ext.cnf",
            "-extensions",
            "v3",
        )


def config(path: Path, body: dict) -> Path:  # type: ignore[type-arg]
    path.write_text(json.dumps(body, indent=2))
    return path


def test_tls_router_admits_only_certified_sessions(tmp_path: Path, world: str) -> None:
    make_certificates(tmp_path)
    endpoint = f"tls/127.0.0.1:{free_port()}"
    tls = {"root_ca_certificate": str(tmp_path / "ca.pem"), "enable_mtls": True}
    router_cfg = config(
        tmp_path / "router.json5",
        {
            "mode": "router",
            "listen": {"endpoints": [endpoint]},
            "scouting": {"multicast": {"enabled": False}},
            "transport": {
                "link": {
                    "tls": {
                        **tls,
                        "listen_private_key": str(tmp_path / "router.key"),
                        "listen_certificate": str(tmp_path / "router.pem"),
                    }
                }
            },
        },
    )
    client = {
        "mode": "client",
        "connect": {"endpoints": [endpoint]},
        "scouting": {"multicast": {"enabled": False}},
    }
    with_cert = config(
        tmp_path / "client.json5",
        {
            **client,
            "transport": {
                "link": {
                    "tls": {
                        **tls,
                        "connect_private_key": str(tmp_path / "client.key"),
                        "connect_certificate": str(tmp_path / "client.pem"),
                    }
                }
            },
        },
    )
    without_cert = config(tmp_path / "stranger.json5", {**client, "transport": {"link": {"tls": tls}}})

    router = subprocess.Popen(
        [sys.executable, "-m", "toyroom", "router", "--zenoh-config", str(router_cfg)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert router.stdout is not None and endpoint in router.stdout.readline()
        with (
            Bridge(world, SessionSettings(config_file=with_cert)) as engine,
            Bridge(world, SessionSettings(config_file=with_cert)) as brain,
        ):
            inbox: queue.Queue = queue.Queue()
            engine.subscribe(engine.keys.command("robot"), lambda m, _: inbox.put(m), expected=RobotCommand)
            publisher = brain.publisher(brain.keys.command("robot"))
            assert publisher.wait_matched(10.0), "the certified brain never reached the engine"
            command = RobotCommand(id="c1", robot="robot", action=Navigate(cell=Cell(1, 1)))
            publisher.put(command)
            assert inbox.get(timeout=5.0) == command
            with pytest.raises(ConfigError, match="cannot open"):
                Bridge(world, SessionSettings(config_file=without_cert))
            assert inbox.empty()
    finally:
        router.terminate()
        router.wait(timeout=10)
