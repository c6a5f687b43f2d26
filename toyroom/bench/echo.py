"""A raw zenoh-python echo peer in its own process, for ``toyroom bench``: it republishes
every ``bench/ping`` sample on ``bench/pong`` and answers every query on ``bench/query``
with the query's payload, in Zenoh's callback thread (the fastest Python can do).

    python -m toyroom.bench.echo WORLD     (stops on SIGTERM or when stdin closes)
"""

from __future__ import annotations

import sys

import zenoh

from bridge.session import SessionSettings, build_config


def main(world: str) -> None:
    """Echo on ``world`` until stdin closes."""
    session = zenoh.open(build_config(world, SessionSettings(listen=("tcp/127.0.0.1:0",))))
    pong = session.declare_publisher("bench/pong")
    session.declare_subscriber("bench/ping", lambda sample: pong.put(sample.payload))

    def answer(query: zenoh.Query) -> None:
        query.reply(query.key_expr, query.payload if query.payload is not None else b"")

    session.declare_queryable("bench/query", answer)
    print("ready", flush=True)
    sys.stdin.read()  # until the parent closes our stdin
    session.close()


if __name__ == "__main__":
    main(sys.argv[1])
