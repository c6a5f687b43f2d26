"""Headless Chromium (Debian's ``chromium``) driven through the DevTools protocol over a
WebSocket (the ``websockets`` library): navigate, evaluate, await a page's promises, and
wait for page events. No Selenium, no driver binary."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import threading
import urllib.request
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from websockets.sync.client import ClientConnection, connect

from bridge.processes import stop_process_group
from bridge.view.screenshot import CHROMIUM_FLAGS

LISTENING = re.compile(r"DevTools listening on (ws://\S+)")


class Page:
    """One page target: :meth:`call` sends a command and returns its result; events that
    arrive meanwhile are kept for :meth:`wait_event`."""

    def __init__(self, socket: ClientConnection, port: str) -> None:
        self.socket = socket
        self.port = port
        """The browser's DevTools port (:func:`another_page` opens a tab there)."""
        self.events: list[dict[str, Any]] = []
        self._next = 0

    def call(self, method: str, timeout: float = 30.0, **params: Any) -> dict[str, Any]:
        self._next += 1
        self.socket.send(json.dumps({"id": self._next, "method": method, "params": params}))
        while True:
            message = json.loads(self.socket.recv(timeout=timeout))
            if message.get("id") == self._next:
                assert "error" not in message, f"{method} failed: {message['error']}"
                return message.get("result", {})
            self.events.append(message)

    def wait_event(self, name: str, timeout: float = 30.0) -> dict[str, Any]:
        """The first event ``name`` not yet consumed (waiting for it), consuming it."""
        while True:
            for n, event in enumerate(self.events):
                if event.get("method") == name:
                    return self.events.pop(n)
            self.events.append(json.loads(self.socket.recv(timeout=timeout)))

    def evaluate(self, expression: str, timeout: float = 30.0) -> Any:
        """The value of ``expression`` in the page (awaited when it is a promise)."""
        result = self.call(
            "Runtime.evaluate", timeout, expression=expression, awaitPromise=True, returnByValue=True
        )
        assert "exceptionDetails" not in result, f"{expression!r} threw: {result['exceptionDetails']}"
        return result["result"].get("value")

    def goto(self, url: str) -> None:
        """Load ``url`` and wait for its load event."""
        self.events.clear()
        self.call("Page.navigate", url=url)
        self.wait_event("Page.loadEventFired")


def _devtools_url(process: subprocess.Popen[str], timeout: float) -> str:
    """Chromium's DevTools WebSocket URL, read from the line it prints when listening."""
    found: list[str] = []
    done = threading.Event()

    def read() -> None:
        assert process.stderr is not None
        for line in process.stderr:
            if match := LISTENING.search(line):
                found.append(match.group(1))
                done.set()
        done.set()

    threading.Thread(target=read, daemon=True).start()
    assert done.wait(timeout) and found, "chromium printed no DevTools address"
    return found[0]


@contextmanager
def chromium(profile: Path, width: int = 1000, height: int = 750) -> Iterator[Page]:
    """A headless Chromium with one blank page, stopped with all its helpers on exit."""
    browser = shutil.which("chromium") or shutil.which("chromium-browser")
    assert browser is not None, "chromium is not installed (apt-get install chromium)"
    flags = [f for f in CHROMIUM_FLAGS if not f.startswith("--virtual-time-budget")]
    process = subprocess.Popen(
        [
            browser,
            *flags,
            f"--user-data-dir={profile}",
            f"--window-size={width},{height}",
            "--remote-debugging-port=0",
            "about:blank",
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        port = re.search(r":(\d+)/", _devtools_url(process, 60.0)).group(1)  # type: ignore[union-attr]
        with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list", timeout=10) as reply:
            targets = json.load(reply)
        page = next(t for t in targets if t.get("type") == "page")
        with _attached(page["webSocketDebuggerUrl"], port) as tab:
            yield tab
    finally:
        stop_process_group(process)  # type: ignore[arg-type]


@contextmanager
def _attached(url: str, port: str) -> Iterator[Page]:
    with connect(url, max_size=None, open_timeout=10) as socket:
        tab = Page(socket, port)
        tab.call("Page.enable")
        yield tab


@contextmanager
def another_page(first: Page) -> Iterator[Page]:
    """A second tab of ``first``'s browser (its own page, the same browser profile)."""
    request = urllib.request.Request(f"http://127.0.0.1:{first.port}/json/new?about:blank", method="PUT")
    with urllib.request.urlopen(request, timeout=10) as reply:
        target = json.load(reply)
    with _attached(target["webSocketDebuggerUrl"], first.port) as tab:
        yield tab
