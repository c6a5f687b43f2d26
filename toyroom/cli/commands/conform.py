"""``toyroom conform``: check that the engine serving a world speaks the protocol (the
conformance kit, :mod:`bridge.conformance`)."""

from __future__ import annotations

import argparse

from bridge.session import SessionSettings, add_network_args, settings_from_args

from ..floors import timeout_problem
from ..subcommand import Subcommand


def options(conform: argparse.ArgumentParser) -> None:
    """``toyroom conform``'s options."""
    conform.add_argument("--timeout", type=float, default=5.0, help="seconds per request (at least 1)")
    conform.add_argument(
        "--strict",
        action="store_true",
        help="fail on a skipped check too (one that applies to the engine but found nothing to exercise)",
    )
    add_network_args(conform)


def problem(args: argparse.Namespace) -> str | None:
    """``--timeout`` below its floor (:mod:`toyroom.cli.floors`; no 0 here), or ``None``."""
    return timeout_problem(args.timeout, none=False)


def conform_main(world: str, settings: SessionSettings, timeout: float, strict: bool = False) -> int:
    """Run the conformance kit against the engine of ``world``; 1 when a check fails (or,
    with ``strict``, is skipped)."""
    from bridge.bridge import Bridge
    from bridge.conformance.checks import check_engine, summary
    from bridge.conformance.probe import CheckOutcome

    with Bridge(world, settings) as bridge:
        results = check_engine(bridge, timeout)
    for result in results:
        print(result.line())
    print(summary(results))
    skipped = any(r.outcome is CheckOutcome.SKIPPED for r in results)
    if strict and skipped:
        print("conform --strict: a skipped check counts as failed (run a scene where each can run)")
    return 1 if any(r.failed for r in results) or (strict and skipped) else 0


def handle(args: argparse.Namespace) -> int:
    """``toyroom conform``: :func:`conform_main` on the parsed world."""
    return conform_main(args.world, settings_from_args(args), args.timeout, args.strict)


COMMAND = Subcommand(
    "conform", "check that the engine serving a world speaks the protocol", options, handle, problem
)
