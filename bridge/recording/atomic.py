"""Output files written whole or not at all, for every command that writes results
(``toyroom eval``, ``fit``, ``infer`` and the brain's outputs).

Each file is written to a temporary file beside it (``.NAME.partial-PID-THREAD.SUFFIX``, the
suffix kept so a figure's format is still known) and renamed over it only once complete, so
a full disk, a crash or Ctrl-C leaves the earlier file or none, never a half-written one. A
write that fails is one :class:`OutputError` naming the file and why (``no space left on
device writing out/fit/settings.toml``), which a command says in one line (exit 1).
:func:`disk_full` tells a full disk (``ENOSPC``, ``EDQUOT``, ``EFBIG``) from other errors: it
is no fault of what was being run, and trying again would fail the same way.
"""

from __future__ import annotations

import contextlib
import errno
import os
import threading
from collections.abc import Iterator, Mapping
from pathlib import Path

DISK_FULL = frozenset({errno.ENOSPC, errno.EDQUOT, errno.EFBIG})
"""The errors of a write that found no room: no space left on the device, the user's disk
quota exceeded, and a file larger than allowed (``RLIMIT_FSIZE``, the file system's limit)."""


def disk_full(err: BaseException) -> bool:
    """Whether ``err`` is a write that found no room (:data:`DISK_FULL`)."""
    return isinstance(err, OSError) and err.errno in DISK_FULL


def disk_full_in(text: str) -> tuple[int, str] | None:
    """The error and the last line of ``text`` (a node's log) that reports a full disk, by
    the system's words for it (``No space left on device``, ``Disk quota exceeded``, ``File
    too large``, whatever the case), or ``None``."""
    said = {code: os.strerror(code).lower() for code in sorted(DISK_FULL)}
    for line in reversed(text.splitlines()):
        for code, words in said.items():
            if words in line.lower():
                return code, line.strip()
    return None


class OutputError(OSError):
    """An output file could not be written: ``str()`` is one line naming the file (when
    known) and why (``line``: another line to say instead)."""

    def __init__(self, err: OSError, path: Path | None, line: str | None = None) -> None:
        super().__init__(err.errno, err.strerror or str(err), None if path is None else str(path))
        what = err.strerror or str(err)
        self.path = path
        self.line = line or f"{what[:1].lower()}{what[1:]}" + ("" if path is None else f" writing {path}")

    def __str__(self) -> str:
        return self.line

    def __reduce__(self) -> tuple[object, tuple[object, ...]]:  # pickled whole (a Ray task's error)
        return _rebuilt, (self.errno, self.strerror, self.path, self.line)


def _rebuilt(code: int, strerror: str, path: Path | None, line: str) -> OutputError:
    return OutputError(OSError(code, strerror), path, line)


def output_error(err: OSError) -> OutputError:
    """``err`` as an :class:`OutputError` (naming its file when it has one)."""
    if isinstance(err, OutputError):
        return err
    return OutputError(err, None if err.filename is None else Path(os.fsdecode(err.filename)))


def partial_path(path: Path) -> Path:
    """The temporary file beside ``path`` that this thread writes it to."""
    return path.with_name(f".{path.stem}.partial-{os.getpid()}-{threading.get_ident()}{path.suffix}")


@contextlib.contextmanager
def replacing(path: Path) -> Iterator[Path]:
    """A temporary path to write ``path``'s content to: renamed to ``path`` when the block
    ends without an error, else removed.

    Raises:
        OutputError: an ``OSError`` while writing (in the block) or renaming it.
    """
    partial = partial_path(path)
    try:
        yield partial
        os.replace(partial, path)
    except BaseException as err:
        with contextlib.suppress(OSError):
            partial.unlink(missing_ok=True)
        if isinstance(err, OSError) and not isinstance(err, OutputError):
            raise OutputError(err, path) from err
        raise


def write_text(path: Path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` whole or not at all (:func:`replacing`).

    Raises:
        OutputError: it could not be written; ``path`` is as it was.
    """
    with replacing(path) as partial:
        partial.write_text(text, encoding="utf-8")


def write_texts(folder: Path, texts: Mapping[str, str]) -> None:
    """Write each of ``texts`` (a file name in ``folder`` -> its text, UTF-8) all whole or
    none: every one to its temporary file first, and only then all renamed into place.

    Raises:
        OutputError: one could not be written; ``folder`` is as it was.
    """
    with contextlib.ExitStack() as files:
        for name, text in texts.items():
            files.enter_context(replacing(folder / name)).write_text(text, encoding="utf-8")


def write_bytes(path: Path, data: bytes) -> None:
    """Write ``data`` to ``path`` whole or not at all (:func:`replacing`).

    Raises:
        OutputError: it could not be written; ``path`` is as it was.
    """
    with replacing(path) as partial:
        partial.write_bytes(data)


def appended(path: Path, line: str) -> None:
    """Append ``line`` (UTF-8, with its newline) to ``path`` whole or not at all: a write that
    fails part way is cut back off, so the file never ends in half a line.

    Raises:
        OutputError: it could not be appended; ``path`` is as it was.
    """
    data = line.encode("utf-8")
    try:
        fd = os.open(path, os.O_WRONLY | os.O_APPEND | os.O_CREAT | os.O_CLOEXEC, 0o666)
    except OSError as err:
        raise OutputError(err, path) from err
    try:
        size = os.fstat(fd).st_size
        written = 0
        try:
            while written < len(data):
                written += os.write(fd, data[written:])
        except OSError:
            with contextlib.suppress(OSError):
                os.ftruncate(fd, size)
            raise
    except OSError as err:
        raise OutputError(err, path) from err
    finally:
        os.close(fd)
