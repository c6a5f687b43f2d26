"""``toyroom bench``: the performance numbers, all measured in one run (``suite``), and the
measurements it is made of, each also runnable alone (``python -m toyroom.bench.NAME``).

The one room of the application, with ``fitting``, that imports the libraries it runs: it
times the engine core's tick and the brain's update in-process (on ticks the engine core
produced, untimed), which running them as processes would hide behind the wire. Importing
this package imports none of its modules (the echo peers start light)."""

__all__ = [
    "brainstep",
    "echo",
    "engine_ab",
    "gateway",
    "gateway_load",
    "lockstep",
    "perfreport",
    "scaling",
    "suite",
    "summary",
    "typed_echo",
]
