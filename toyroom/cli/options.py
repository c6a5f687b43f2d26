"""Options more than one ``toyroom`` command takes, each defined once: ``--observer`` (``run``,
``infer``) and ``--strict`` (``infer``, ``replay``)."""

from __future__ import annotations

import argparse

from protocol import Observer


def observer_option(parser: argparse.ArgumentParser, help: str) -> None:
    """Add ``--observer`` (one of :class:`protocol.Observer`, ``btom`` by default), said as ``help``."""
    parser.add_argument("--observer", choices=Observer.names(), default=Observer.BTOM.value, help=help)


def strict_option(parser: argparse.ArgumentParser) -> None:
    """Add ``--strict``: refuse a recording that is not whole instead of using its readable part."""
    parser.add_argument(
        "--strict",
        action="store_true",
        help="refuse a cut-off or damaged recording (exit 1) instead of using the part before the "
        "break with a warning",
    )
