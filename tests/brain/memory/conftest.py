"""A memory file this process cannot write: ``chmod 444`` for a user, the immutable flag
(``chattr +i``, by its ioctl) for root, whom file modes do not stop."""

from __future__ import annotations

import fcntl
import os
import struct
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

GET_FLAGS, SET_FLAGS, IMMUTABLE = 0x80086601, 0x40086602, 0x10
"""``FS_IOC_GETFLAGS``, ``FS_IOC_SETFLAGS`` and ``FS_IMMUTABLE_FL`` (Linux, 64-bit)."""


def _flags(path: Path, change: int | None = None) -> int:
    fd = os.open(path, os.O_RDONLY)
    try:
        if change is not None:
            fcntl.ioctl(fd, SET_FLAGS, struct.pack("i", change))
        return int(struct.unpack("i", fcntl.ioctl(fd, GET_FLAGS, struct.pack("i", 0)))[0])
    finally:
        os.close(fd)


@pytest.fixture
def read_only() -> Iterator[Callable[[Path], None]]:
    """Make a file unwritable by this process (undone at the test's end); skips the test
    where neither way works here."""
    made: list[tuple[Path, int]] = []

    def make(path: Path) -> None:
        if os.geteuid() != 0:
            path.chmod(0o444)
        else:
            try:
                before = _flags(path)
                _flags(path, before | IMMUTABLE)
                made.append((path, before))
            except OSError as err:
                pytest.skip(f"cannot make {path} immutable here (chattr +i: {err})")
        try:
            path.open("ab").close()
        except OSError:
            return
        pytest.skip(f"{path} is still writable by this process: no read-only file to test with")

    yield make
    for path, before in made:
        _flags(path, before)
