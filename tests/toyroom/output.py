"""A command's output lines, collected as they come, for tests that wait on what a server
(``toyroom play``, ``toyroom rate``) prints."""

from __future__ import annotations

import re
import subprocess
import threading

from tests.toyroom.devtools import wait_until


class OutputLines:
    """Every line ``process`` writes to its stdout (its stderr merged in, as the tests start
    it), read by a daemon thread into :attr:`lines`, without the newline."""

    def __init__(self, process: subprocess.Popen[str], name: str) -> None:
        self.process = process
        self.name = name
        """What the process is, for a failure's message (its command line)."""
        self.lines: list[str] = []
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.append(line.rstrip("\n"))

    def wait(self, pattern: str, timeout: float) -> str:
        """The first line matching the regular expression ``pattern``, waiting up to
        ``timeout`` seconds; a process that exits before printing it fails at once, with its
        output."""

        def seen() -> str | None:
            found = next((x for x in self.lines if re.search(pattern, x)), None)
            if found is None and self.process.poll() is not None:
                output = "\n".join(self.lines)
                raise AssertionError(
                    f"`{self.name}` exited {self.process.returncode} before {pattern!r}:\n{output}"
                )
            return found

        return str(wait_until(seen, timeout, pattern))
