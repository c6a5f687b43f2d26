"""``toyroom schema``: write the protocol's JSON Schemas (``--check``: report stale ones), or
with ``--csharp`` the C# SDK's message classes."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..subcommand import Subcommand

CSHARP_MESSAGES = "clients/unity/Runtime/Protocol/Messages.g.cs"
"""The C# SDK's generated message classes, in the source checkout."""


def options(schema: argparse.ArgumentParser) -> None:
    """``toyroom schema``'s options."""
    schema.add_argument("--check", action="store_true", help="exit 1 when the checked-in schemas are stale")
    schema.add_argument("--dir", type=Path, help="schema directory (default: the package's)")
    schema.add_argument(
        "--csharp",
        action="store_true",
        help="the C# SDK's message classes (clients/unity/Runtime/Protocol/Messages.g.cs) instead",
    )


def csharp_main(check: bool) -> int:
    """Write the C# message classes from the schemas, or with ``check`` return 1 when stale."""
    from bridge.processes import CHECKOUT
    from protocol.csharp import render_from_schemas

    path = CHECKOUT / CSHARP_MESSAGES
    if not (CHECKOUT / "clients" / "unity").is_dir():
        print(f"toyroom schema --csharp needs a source checkout ({CSHARP_MESSAGES})", file=sys.stderr)
        return 2
    text = render_from_schemas()
    if check:
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            print(f"stale C# classes {path}: run `toyroom schema --csharp`", file=sys.stderr)
            return 1
        print(f"C# classes in {path} are up to date")
        return 0
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    print(f"wrote {path}")
    return 0


def schema_main(check: bool, directory: Path | None = None, csharp: bool = False) -> int:
    """Write the JSON Schemas, or with ``check`` report stale ones and return 1; with
    ``csharp``, the C# SDK's message classes instead."""
    from protocol.schema import SCHEMA_DIR, stale_schemas, write_schemas

    if csharp:
        return csharp_main(check)

    target = directory or SCHEMA_DIR
    if check:
        problems = stale_schemas(target)
        for line in problems:
            print(f"stale schema {target / line}", file=sys.stderr)
        if problems:
            print("run `toyroom schema` to regenerate them", file=sys.stderr)
            return 1
        print(f"schemas in {target} are up to date")
        return 0
    for path in write_schemas(target):
        print(f"wrote {path}")
    return 0


def handle(args: argparse.Namespace) -> int:
    """``toyroom schema``: :func:`schema_main` with the parsed options."""
    return schema_main(args.check, args.dir, args.csharp)


COMMAND = Subcommand("schema", "write the JSON Schemas into protocol/schema/", options, handle)
