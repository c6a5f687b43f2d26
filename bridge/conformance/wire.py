"""The conformance checks of what crosses the wire: MessagePack understood and answered in
kind on every key a client writes, events naming known ids, each tick's events before its
state, ``truth`` when declared, and the engine still serving after malformed input."""

from __future__ import annotations

from protocol import (
    Capability,
    Cell,
    ControlReply,
    Encoding,
    EngineInfo,
    Hello,
    Navigate,
    Step,
    decode,
    encode,
)

from ..pubsub import zenoh_encoding
from .probe import CheckFailed, NotApplicable, Probe


def _raw_query(probe: Probe, key: str, payload: bytes) -> tuple[bytes, Encoding]:
    replies = list(
        probe.bridge.session.get(
            key, payload=payload, encoding=zenoh_encoding(Encoding.MSGPACK), timeout=probe.timeout
        )
    )
    if not replies or replies[0].ok is None:
        got = "none" if not replies else "an error"
        raise CheckFailed(f"a MessagePack query on '{key}': expected a reply, got {got}")
    sample = replies[0].ok
    return sample.payload.to_bytes(), Encoding.from_mime(str(sample.encoding))


def check_messagepack(probe: Probe) -> str:
    """MessagePack is understood and answered in kind on every key a client writes."""
    hello = encode(Hello(client="toyroom-conform", role="conform"), Encoding.MSGPACK)
    data, encoding = _raw_query(probe, probe.keys.info, hello)
    if encoding is not Encoding.MSGPACK:
        raise CheckFailed(
            f"engine/info asked in MessagePack: expected a MessagePack reply, got {encoding.value}"
        )
    decode(data, EngineInfo, Encoding.MSGPACK)
    said = ["engine/info"]
    if not probe.realtime:
        before = probe.step(1).tick  # the engine may have run before the kit came (no reset yet)
        data, encoding = _raw_query(probe, probe.keys.control, encode(Step(n=1), Encoding.MSGPACK))
        if encoding is not Encoding.MSGPACK:
            raise CheckFailed(
                f"a step asked in MessagePack: expected a MessagePack reply, got {encoding.value}"
            )
        reply = decode(data, ControlReply, Encoding.MSGPACK)
        if reply.tick != before + 1:
            raise CheckFailed(f"a step asked in MessagePack: expected tick {before + 1}, got {reply.tick}")
        probe.tick, probe.last = reply.tick, reply
        said.append("engine/control")
    if probe.robot is not None and Capability.ROBOT in (probe.info.capabilities if probe.info else ()):
        here = probe.cell_of(probe.robot)
        command = probe.send(Navigate(cell=Cell(*here)), Encoding.MSGPACK)
        if not probe.wait_status(command):
            raise CheckFailed("a robot command sent in MessagePack: expected a status, got none")
        if not probe.realtime:
            probe.finish(command, "a navigate sent in MessagePack")
        said.append("robot/<id>/command")
    return "understood on " + ", ".join(said)


def check_events(probe: Probe) -> str:
    """Every event names known ids (agents, items, places)."""
    assert probe.info is not None
    probe.step(20 if probe.realtime else 60)
    scene = probe.info.scene
    agents = {a.id for a in scene.agents}
    items = {i.id for i in scene.items}
    places = {r.id for r in scene.regions} | {loc.id for loc in scene.locations} | {d.id for d in scene.doors}
    for event in probe.stream.events:
        for name, value, known in (
            ("actor", event.actor, agents),
            ("target", event.target, agents),
            ("item", event.item, items),
            ("offer", event.offer, items),
            ("location", event.location, places),
        ):
            if value is not None and value not in known:
                raise CheckFailed(f"event {event.kind} at tick {event.tick}: {name} '{value}' is no known id")
    return f"{len(probe.stream.events)} events, all with known ids"


def check_event_order(probe: Probe) -> str:
    """Each tick's events arrive before its state."""
    with probe.stream.cond:
        arrivals = list(probe.stream.arrivals)
    stated: set[tuple[int, int]] = set()
    events = 0
    for kind, episode, tick in arrivals:
        if kind == "state":
            stated.add((episode, tick))
        elif (episode, tick) in stated:
            raise CheckFailed(
                f"expected each tick's events before its state, got an event of tick {tick} after it"
            )
        else:
            events += 1
    return f"{events} events, each before its tick's state"


def check_truth(probe: Probe) -> str:
    """An engine declaring ``truth`` publishes it on ``engine/truth``."""
    assert probe.info is not None
    if Capability.TRUTH not in probe.info.capabilities:
        raise NotApplicable("the engine does not declare 'truth'")
    before = len(probe.stream.truths)
    probe.step(3)
    if not probe.stream.wait(lambda: len(probe.stream.truths) > before, probe.timeout):
        raise CheckFailed("the engine declares 'truth' but published nothing on engine/truth in 3 ticks")
    return f"{len(probe.stream.truths) - before} truth messages in 3 ticks"


def check_malformed_input(probe: Probe) -> str:
    """Malformed queries get error replies, and the engine still steps after them."""
    for payload in (b"{not json", b'{"type": "teleport", "protocol": "1.0"}', b"\xff\x00"):
        replies = list(probe.bridge.session.get(probe.keys.control, payload=payload, timeout=probe.timeout))
        if not replies or replies[0].err is None:
            raise CheckFailed(
                f"control query with payload {payload!r}: expected an error reply, got "
                f"{'none' if not replies else 'a success'}"
            )
    if probe.robot is not None:
        probe.bridge.session.put(probe.keys.command(probe.robot), b"\x00 garbage")
    probe.bridge.session.put(probe.keys.control, b"{}")
    before = probe.latest().tick if probe.realtime else probe.tick
    reply = probe.step(1)
    if reply.tick != before + 1 and not (probe.realtime and reply.tick > before):
        raise CheckFailed(f"after malformed input, expected step to tick {before + 1}, got {reply.tick}")
    return (
        "error replies to bad queries, and still stepping (this check also puts '{}' on "
        "engine/control and garbage on the robot's command key: an engine or gateway that logs "
        "them as dropped is right to)"
    )
