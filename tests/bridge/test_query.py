"""Typed queries and queryables: answers, refusals, and what happens when nobody answers."""

from __future__ import annotations

import time

import pytest

from bridge import Bridge, NoReply, Refused, RemoteError
from protocol import ControlReply, Encoding, ErrorCode, Message, ProtocolError, Reset, Step


def _answer(request: Message | None, key: str) -> ControlReply:
    if isinstance(request, Reset) and request.scenario == "nowhere":
        raise Refused(ErrorCode.UNKNOWN_SCENARIO, "no scenario named 'nowhere'")
    if isinstance(request, Reset) and request.scenario == "crash":
        raise RuntimeError("engine fell over")
    tick = request.n if isinstance(request, Step) else 0
    return ControlReply(episode=1, tick=tick, time=tick * 0.1)


@pytest.mark.parametrize("inline", [False, True], ids=["worker-thread", "inline"])
@pytest.mark.parametrize("encoding", list(Encoding))
def test_query_round_trip_and_refusals(world: str, encoding: Encoding, inline: bool) -> None:
    """The same answers and refusals whether queries are handed to the queryable's worker
    thread or answered in Zenoh's callback thread (as a lock-step engine does)."""
    with Bridge(world) as engine, Bridge(world, encoding=encoding) as client:
        served = engine.queryable(engine.keys.control, _answer, expected=(Reset, Step), inline=inline)
        key = client.keys.control
        deadline = time.monotonic() + 5
        while True:  # wait for the queryable to be known to the client
            try:
                reply = client.query(key, Step(n=7), ControlReply, timeout=2.0)
                break
            except NoReply:
                assert time.monotonic() < deadline
                time.sleep(0.02)
        assert (reply.tick, reply.time) == (7, pytest.approx(0.7))

        with pytest.raises(RemoteError) as refused:
            client.query(key, Reset(scenario="nowhere"), ControlReply)
        assert refused.value.code is ErrorCode.UNKNOWN_SCENARIO and "nowhere" in str(refused.value)

        with pytest.raises(RemoteError) as crashed:
            client.query(key, Reset(scenario="crash"), ControlReply)
        assert crashed.value.code is ErrorCode.INTERNAL and "engine fell over" in crashed.value.message

        with pytest.raises(RemoteError) as wrong:
            client.query(key, ControlReply(episode=0, tick=0, time=0.0), ControlReply)
        assert wrong.value.code is ErrorCode.BAD_REQUEST and "'control_reply'" in wrong.value.message

        raw = list(client.session.get(key, payload=b"garbage", timeout=2.0))
        assert raw and raw[0].err is not None, "a malformed request should get an error reply"
        assert b"bad_request" in raw[0].err.payload.to_bytes()

        with pytest.raises(ProtocolError, match="expected a 'step' message"):
            client.query(key, Step(n=1), Step)

        assert client.query(key, Step(n=2), ControlReply).tick == 2, "it should keep serving"
        assert served.handled == 3


def test_nobody_answers_fails_fast(bridges: tuple[Bridge, Bridge]) -> None:
    _, client = bridges
    started = time.monotonic()
    with pytest.raises(NoReply, match="nobody answers"):
        client.query(client.keys.control, Step(n=1), ControlReply, timeout=3.0)
    assert time.monotonic() - started < 1.0


def test_a_request_asked_again_under_its_id_gets_its_first_answer(bridges: tuple[Bridge, Bridge]) -> None:
    """A query repeating a request id is answered with the answer that id got, without the
    handler: a step asked again is not carried out twice. The last 16 ids are kept."""
    from bridge.queries import REMEMBERED_ANSWERS

    engine, client = bridges
    handled: list[Message | None] = []

    def count(request: Message | None, _: str) -> ControlReply:
        handled.append(request)
        return ControlReply(episode=1, tick=len(handled), time=0.0)

    engine.queryable(engine.keys.control, count, expected=(Step,), inline=True)
    key = client.keys.control
    deadline = time.monotonic() + 5
    while True:  # wait for the queryable to be known to the client
        try:
            first = client.query(key, Step(n=1), ControlReply, timeout=2.0, request_id="c-1")
            break
        except NoReply:
            assert time.monotonic() < deadline, "the queryable never became known"
            time.sleep(0.02)
    again = client.query(key, Step(n=1), ControlReply, request_id="c-1")
    assert (again, len(handled)) == (first, 1), (
        f"request c-1 asked again: its first answer (tick {first.tick}) and the handler called once "
        f"were expected; got tick {again.tick}, the handler called {len(handled)} times"
    )
    assert client.query(key, Step(n=1), ControlReply, request_id="c-2").tick == 2, "another id is handled"
    assert client.query(key, Step(n=1), ControlReply).tick == 3, "so is a query without an id"
    for n in range(REMEMBERED_ANSWERS):
        client.query(key, Step(n=1), ControlReply, request_id=f"d-{n}")
    assert client.query(key, Step(n=1), ControlReply, request_id="c-1").tick == len(handled), (
        f"after {REMEMBERED_ANSWERS} newer ids, c-1's answer should be forgotten and c-1 handled anew"
    )
