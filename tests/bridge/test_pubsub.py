"""Typed publish/subscribe over real Zenoh sessions on loopback."""

from __future__ import annotations

import logging
import queue
import threading

import pytest
import zenoh
from support import golden_examples

from bridge import Bridge, Received
from protocol import PROTOCOL_VERSION, Encoding, Message, State, encode


def _collector() -> tuple[queue.Queue, object]:
    inbox: queue.Queue = queue.Queue()

    def on_message(message: Message, received: Received) -> None:
        inbox.put((message, received))

    return inbox, on_message


@pytest.mark.parametrize("encoding", list(Encoding))
def test_every_message_type_round_trips(world: str, encoding: Encoding) -> None:
    examples = golden_examples()
    with Bridge(world, encoding=encoding) as sender, Bridge(world) as receiver:
        inbox, on_message = _collector()
        receiver.subscribe(f"{receiver.keys.prefix}/test/**", on_message)
        for tag, message in examples.items():
            publisher = sender.publisher(f"{sender.keys.prefix}/test/{tag}")
            assert publisher.wait_matched(5.0), "the subscription never reached the publisher"
            publisher.put(message)
            got, received = inbox.get(timeout=5.0)
            assert got == message, f"{tag}: sent {message}, received {got}"
            assert received.encoding is encoding, f"{tag}: sent as {encoding}, read as {received.encoding}"
            assert received.key.endswith(f"/test/{tag}")


def test_malformed_and_unknown_payloads_are_logged_and_dropped(
    bridges: tuple[Bridge, Bridge], caplog: pytest.LogCaptureFixture
) -> None:
    sender, receiver = bridges
    inbox, on_message = _collector()
    state = golden_examples()["state"]
    subscriber = receiver.subscribe(receiver.keys.state, on_message, expected=State)
    raw = sender.session.declare_publisher(sender.keys.state)
    typed = sender.publisher(sender.keys.state)
    assert typed.wait_matched(5.0)
    caplog.set_level(logging.WARNING, logger="toyroom.bridge")

    raw.put(b"{not json", encoding=zenoh.Encoding.APPLICATION_JSON)
    raw.put(b'{"type": "teleport", "protocol": "1.0"}', encoding=zenoh.Encoding.APPLICATION_JSON)
    raw.put(encode(state).replace(b'"tick":42', b'"tick":"x"'), encoding=zenoh.Encoding.APPLICATION_JSON)
    typed.put(state)

    got, _ = inbox.get(timeout=5.0)
    assert got == state, "the good message after three bad ones should arrive intact"
    assert subscriber.dropped == 3 and subscriber.received == 1, (subscriber.dropped, subscriber.received)
    text = caplog.text
    assert sender.keys.state in text, f"the key should be logged: {text}"
    assert "unknown message type 'teleport'" in text
    assert "not a JSON message" in text
    assert "$.tick" in text

    typed.put(state)
    assert inbox.get(timeout=5.0)[0] == state, "the subscriber should keep receiving"
    raw.undeclare()


def test_other_major_version_is_dropped_with_one_warning(
    bridges: tuple[Bridge, Bridge], caplog: pytest.LogCaptureFixture
) -> None:
    sender, receiver = bridges
    inbox, on_message = _collector()
    subscriber = receiver.subscribe(receiver.keys.state, on_message)
    state = golden_examples()["state"]
    publisher = sender.publisher(sender.keys.state)
    assert publisher.wait_matched(5.0)
    caplog.set_level(logging.WARNING, logger="toyroom.bridge")
    future = State(**{**{f: getattr(state, f) for f in state.__struct_fields__}, "protocol": "2.0"})
    for _ in range(5):
        publisher.put(future)
    publisher.put(state)
    assert inbox.get(timeout=5.0)[0] == state
    assert subscriber.dropped == 5
    warnings = [r for r in caplog.records if "version mismatch" in r.getMessage()]
    assert len(warnings) == 1, f"expected one warning for five messages, got {len(warnings)}"
    assert PROTOCOL_VERSION in warnings[0].getMessage() and "2.0" in warnings[0].getMessage()


def test_failing_handler_does_not_stop_the_subscriber(
    bridges: tuple[Bridge, Bridge], caplog: pytest.LogCaptureFixture
) -> None:
    sender, receiver = bridges
    calls: list[int] = []
    done = threading.Event()

    def handler(message: State, _: Received) -> None:
        calls.append(message.tick)
        if len(calls) == 1:
            raise RuntimeError("boom")
        done.set()

    receiver.subscribe(receiver.keys.state, handler, expected=State)
    publisher = sender.publisher(sender.keys.state)
    assert publisher.wait_matched(5.0)
    state = golden_examples()["state"]
    publisher.put(state)
    publisher.put(state)
    assert done.wait(5.0), f"second message not handled; calls: {calls}"
    assert "boom" in caplog.text
