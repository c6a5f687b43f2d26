"""``toyroom doctor``: check an installation end to end, in a few seconds.

It says whether the shipped JSON Schemas match what this install's msgspec generates (a
mismatch is a warning for developers, who regenerate them with ``toyroom schema``, never a
failure of the user's install: the wire does not depend on them), opens two Zenoh sessions on
loopback, performs the handshake against a stand-in engine queryable that serves the golden
``engine_info`` example, and sends every golden example through a publisher and a
subscriber in both encodings, timing each round trip.
"""

from __future__ import annotations

import argparse
import statistics
import threading
import time
from pathlib import Path

from rich.console import Console
from rich.table import Table

from bridge.bridge import Bridge
from bridge.handshake import handshake, serve_info
from bridge.pubsub import Received
from bridge.session import SessionSettings, add_network_args, settings_from_args, world_endpoint
from protocol import BY_TAG, Encoding, EngineInfo, Message, decode, encode
from protocol.examples import example_paths
from protocol.schema import SCHEMA_DIR, stale_schemas

from ..subcommand import Subcommand


def _round_trip(sender: Bridge, receiver: Bridge, message: Message, key: str, repeats: int) -> float:
    """Median seconds for ``message`` to go from ``sender`` to ``receiver`` and be decoded."""
    arrived = threading.Event()
    got: list[Message] = []

    def on_message(msg: Message, _: Received) -> None:
        got.append(msg)
        arrived.set()

    times = []
    with receiver.subscribe(key, on_message, expected=type(message)):
        publisher = sender.publisher(key)
        if not publisher.wait_matched(5.0):
            raise RuntimeError(f"'{key}': the subscription never reached the publisher")
        for _ in range(repeats):
            arrived.clear()
            start = time.perf_counter()
            publisher.put(message)
            if not arrived.wait(2.0):
                raise RuntimeError(f"'{key}': the message did not arrive within 2 s")
            times.append(time.perf_counter() - start)
        publisher.close()
    if got[-1] != message:
        raise RuntimeError(f"'{key}': sent {message!r}, received {got[-1]!r}")
    return statistics.median(times)


def schema_line(directory: Path = SCHEMA_DIR) -> str:
    """The doctor's line about the schemas in ``directory``: current, or a warning."""
    stale = stale_schemas(directory)
    if not stale:
        return "[green]schemas up to date[/]"
    return (
        f"[yellow]warning: the schemas in {directory} differ from what this msgspec generates[/] "
        f"({'; '.join(stale)}). Not a fault of this install; in a source checkout, "
        "developers run `toyroom schema` and commit protocol/schema/."
    )


def run_doctor(
    world: str, settings: SessionSettings | None = None, repeats: int = 20, schema_dir: Path = SCHEMA_DIR
) -> int:
    """Run every check, print a table, and return 0 when all pass (stale schemas only warn)."""
    console = Console()
    failures = 0
    console.print(schema_line(schema_dir))
    examples = {tag: decode(path.read_bytes(), BY_TAG[tag]) for tag, path in example_paths().items()}
    info = examples["engine_info"]
    assert isinstance(info, EngineInfo)
    table = Table(title=f"golden examples over loopback Zenoh (world '{world}', median of {repeats})")
    table.add_column("message")
    for encoding in Encoding:
        table.add_column(f"{encoding.name} bytes", justify="right")
        table.add_column(f"{encoding.name} us", justify="right")
    console.print(f"world '{world}': default endpoint {world_endpoint(world)}")
    with Bridge(world, settings) as engine, Bridge(world, settings) as client:
        serve_info(engine, lambda: info)
        got = handshake(client, client="toyroom-doctor", role="doctor")
        console.print(f"handshake: engine '{got.engine}', protocol {got.protocol}, scene '{got.scene.name}'")
        senders = {
            encoding: Bridge(world, settings, encoding=encoding, session=engine.session)
            for encoding in Encoding
        }
        for tag, message in examples.items():
            row = [tag]
            for encoding, sender in senders.items():
                size = len(encode(message, encoding))
                try:
                    # a key per encoding: a subscription just undeclared on a shared key can
                    # still match the next publisher, which then sends into the void
                    key = f"{client.keys.prefix}/doctor/{tag}/{encoding.name.lower()}"
                    seconds = _round_trip(sender, client, message, key, repeats)
                    row += [str(size), f"{seconds * 1e6:.0f}"]
                except RuntimeError as err:
                    failures += 1
                    row += [str(size), f"[red]{err}[/]"]
            table.add_row(*row)
        for sender in senders.values():
            sender.close()
    console.print(table)
    console.print("[green]all checks passed[/]" if not failures else f"[red]{failures} check(s) failed[/]")
    return 0 if not failures else 1


def options(doctor: argparse.ArgumentParser) -> None:
    """``toyroom doctor``'s options."""
    add_network_args(doctor)


def handle(args: argparse.Namespace) -> int:
    """``toyroom doctor``: :func:`run_doctor` on the parsed world."""
    return run_doctor(args.world, settings_from_args(args))


COMMAND = Subcommand(
    "doctor", "check the install: schemas, and every message over loopback Zenoh", options, handle
)
