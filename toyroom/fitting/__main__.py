"""``python -m toyroom.fitting RECORDINGS... --params beta,hazard --out DIR`` (what ``toyroom
fit`` runs): the model's parameters fitted to recordings, cross-validated, models compared."""

from __future__ import annotations

import sys
from collections.abc import Sequence

from brain import BrainError
from brain.settings import load_settings
from bridge import BridgeError
from bridge.flags import configure_logging
from bridge.recording.atomic import OutputError, disk_full, output_error
from protocol import Error as ProtocolError

from .command import fit_main, fit_parser


def main(argv: Sequence[str] | None = None) -> int:
    """``toyroom fit`` on ``argv``; the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    args = fit_parser().parse_args(argv)
    configure_logging(args.log_level)
    try:
        return fit_main(args, load_settings(args.settings, args.overrides), ["toyroom", "fit", *argv])
    except (BrainError, BridgeError, ProtocolError) as err:
        print(f"toyroom fit: {err}", file=sys.stderr)
        return 2
    except OSError as err:  # a full disk: one line, and the outputs all written or none
        if not (isinstance(err, OutputError) or disk_full(err)):
            raise
        print(f"toyroom fit: {output_error(err)}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
