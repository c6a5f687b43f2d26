"""``toyroom replay FILE.mcap``: republish a recording so brains and viewers run on it.

Messages go out on their recorded keys (moved to another world with ``world``), spaced as
recorded divided by ``speed`` (0: as fast as possible). Only messages on toyroom keys go
out: those on other topics (a foreign recorder's, or keys Zenoh would refuse) are named in
one warning and never reach Zenoh; damaged ones were dropped on reading (:mod:`.readable`).
The recorded handshake is served on ``engine/info`` with a real-time clock, so a brain
follows the replay as it would a live real-time engine, and a viewer draws it.
"""

from __future__ import annotations

import logging
import threading
import time
from pathlib import Path

import msgspec
import zenoh

from protocol import ClockMode, EngineInfo, Keys, ProtocolError, decode

from ..bridge import Bridge
from ..handshake import serve_info
from .readable import Recorded, Recording, read_recording

_JSON = zenoh.Encoding("application/json")
log = logging.getLogger("toyroom.recording")


def replay(
    bridge: Bridge,
    source: Path | Recording,
    *,
    speed: float = 1.0,
    stop: threading.Event | None = None,
    until_tick: int | None = None,
    wait_subscribers: float = 0.0,
    resend_minds: bool = False,
) -> int:
    """Republish a recording (a file, or one already read) into ``bridge``'s world (up to
    tick ``until_tick``, when given: every message of a tick up to it, in recorded order,
    though in real time a brain's mind of tick t may be logged after the engine's state of
    t + 1); return the number of messages sent. With
    ``wait_subscribers``, first wait up to that many seconds for someone to subscribe to
    the world's state. With ``resend_minds`` (a replay that then holds still for a
    viewer), the last ``brain/mind`` is sent once more half a second after the end: as fast
    as possible, a slow subscriber may have had the last ones dropped, and the mind is what
    a viewer draws over the scene."""
    recording = source if isinstance(source, Recording) else read_recording(source)
    records = recording.records
    if recording.foreign:
        log.warning(
            "%s: not replayed: the messages on %d topics that are not toyroom keys (%s)",
            recording.path,
            len(recording.foreign),
            ", ".join(repr(t) for t in recording.foreign[:3])
            + (", ..." if len(recording.foreign) > 3 else ""),
        )
    _serve_recorded_info(bridge, records)
    publishers: dict[str, object] = {}
    if wait_subscribers > 0:
        state_key = f"{Keys(bridge.world).prefix}/engine/state"
        probe = publishers[state_key] = bridge.session.declare_publisher(state_key, encoding=_JSON)
        deadline = time.monotonic() + wait_subscribers
        while not probe.matching_status.matching and time.monotonic() < deadline:  # type: ignore[attr-defined]
            time.sleep(0.05)
        time.sleep(0.2)  # let every other subscription of the newcomer arrive too
    sent = 0
    last_mind: tuple[object, bytes] | None = None
    first = records[0].log_time if records else 0
    started = time.monotonic()
    prefix = Keys(bridge.world).prefix
    for record in _up_to(records, until_tick):
        if record.key.endswith("/engine/info"):
            continue
        if stop is not None and stop.is_set():
            break
        if speed > 0:
            due = started + (record.log_time - first) / 1e9 / speed
            delay = due - time.monotonic()
            if delay > 0:
                time.sleep(delay)
        parts = record.key.split("/", 2)  # toyroom/<world>/<rest>
        key = f"{prefix}/{parts[2]}" if len(parts) == 3 else record.key
        if key not in publishers:
            publishers[key] = _publisher(bridge, key)
        publisher = publishers[key]
        if publisher is None:
            continue
        publisher.put(record.data)  # type: ignore[attr-defined]
        sent += 1
        if key.endswith("/brain/mind"):
            last_mind = (publisher, record.data)
    if resend_minds and last_mind is not None and not (stop is not None and stop.is_set()):
        time.sleep(0.5)
        last_mind[0].put(last_mind[1])  # type: ignore[attr-defined]
    return sent


def _serve_recorded_info(bridge: Bridge, records: tuple[Recorded, ...]) -> None:
    """Answer the handshake with the recording's first readable engine info, moved to
    ``bridge``'s world and to the real-time clock (a replay runs in real time); nothing when
    the recording has none."""
    infos = (r.data for r in records if r.key.endswith("/engine/info"))
    found = next((info for data in infos if (info := _info(data)) is not None), None)
    if found is not None:
        served = msgspec.structs.replace(found, world=bridge.world, clock=ClockMode.REALTIME)
        serve_info(bridge, lambda: served)


def _info(data: bytes) -> EngineInfo | None:
    """The engine info of a payload, ``None`` when it does not decode as one."""
    try:
        return decode(data, EngineInfo)
    except ProtocolError:
        return None


def _up_to(records: tuple[Recorded, ...], until_tick: int | None) -> list[Recorded]:
    """The records a replay up to ``until_tick`` sends, in recorded order: every one through
    the last of a tick at most ``until_tick``, less those of later ticks (all of them without
    a limit). Each payload's tick is read once."""
    if until_tick is None:
        return list(records)
    ticks = [_tick(record.data) for record in records]
    inside = [i for i, tick in enumerate(ticks) if 0 <= tick <= until_tick]
    end = inside[-1] + 1 if inside else 0
    return [record for record, tick in zip(records[:end], ticks, strict=False) if tick <= until_tick]


def _tick(data: bytes) -> int:
    """The tick of a JSON message (-1 when it has none)."""
    try:
        tick = msgspec.json.decode(data).get("tick", -1)
    except (msgspec.DecodeError, AttributeError):
        return -1
    return tick if isinstance(tick, int) else -1


def _publisher(bridge: Bridge, key: str) -> object | None:
    """A publisher on ``key``; ``None`` (and one warning) when Zenoh refuses the key (a
    recording's keys are checked on reading, so this is a last guard)."""
    try:
        return bridge.session.declare_publisher(key, encoding=_JSON)
    except zenoh.ZError as err:
        log.warning("not replayed: the messages on %r, not a key Zenoh takes (%s)", key, err)
        return None
