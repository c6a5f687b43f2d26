"""The gateway's ``--token FILE``: the secret every client must present in its hello.

Like ssh with a private key, the gateway refuses a token file that anyone but its owner
may read or write (mode ``0600`` or stricter is asked for), and a file that is not a
regular one (a FIFO would block the gateway before it serves, deaf to SIGTERM).
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from bridge.errors import ConfigError
from bridge.flags import open_regular

OTHERS = 0o077
"""The permission bits of the group and of others: a token file must have none of them."""


def read_secret(path: Path) -> str:
    """The token in ``path`` (surrounding whitespace dropped).

    Raises:
        ConfigError: one line naming the file: it cannot be read, is not a regular file,
            may be read or written by others than its owner (its mode is named), is not
            UTF-8 text, or is empty."""
    try:
        with open_regular(path) as handle:
            mode = stat.S_IMODE(os.fstat(handle.fileno()).st_mode)
            if mode & OTHERS:
                raise ConfigError(
                    f"the --token file {path} has mode {mode:04o}: others than its owner may read or "
                    f"change it; make it the owner's alone (chmod 600 {path})"
                )
            secret = handle.read().decode("utf-8").strip()
    except OSError as err:
        raise ConfigError(f"cannot read the --token file {path}: {err.strerror}") from None
    except UnicodeDecodeError as err:
        raise ConfigError(f"the --token file {path} is not UTF-8 text (byte {err.start})") from None
    if not secret:
        raise ConfigError(f"the --token file {path} is empty")
    return secret
