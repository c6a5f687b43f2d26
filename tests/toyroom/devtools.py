"""Headless Chromium (Debian's ``chromium``) driven through the DevTools protocol over a
WebSocket (the ``websockets`` library; no Selenium, no driver binary), for the page tests of
``toyroom play`` and ``toyroom rate``: open tabs, navigate, evaluate (awaiting promises),
wait for page events or for an expression to hold, press keys, take screenshots."""

from __future__ import annotations

import base64
import json
import shutil
import subprocess
import tempfile
import time
import urllib.request
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from websockets.sync.client import ClientConnection, connect

from bridge.processes import stop_process_group
from toyroom.view.screenshot import CHROMIUM_FLAGS

KEY_CODES = {"ArrowLeft": 37, "ArrowUp": 38, "ArrowRight": 39, "ArrowDown": 40, " ": 32}


class Tab:
    """One page target: :meth:`call` sends a command and returns its result; events that
    arrive meanwhile are kept for :meth:`wait_event`."""

    def __init__(self, url: str, port: int) -> None:
        connection = connect(url, max_size=64 * 1024 * 1024, open_timeout=30)
        self.socket: ClientConnection = connection.__enter__()  # left in close()
        self.port = port
        """The browser's DevTools port (:func:`another_page` opens a tab there)."""
        self.events: list[dict[str, Any]] = []
        self._next = 0

    def call(self, method: str, timeout: float = 30.0, **params: Any) -> dict[str, Any]:
        """Call a DevTools method and return its result."""
        self._next += 1
        self.socket.send(json.dumps({"id": self._next, "method": method, "params": params}))
        deadline = time.monotonic() + timeout
        while True:
            message = json.loads(self.socket.recv(timeout=max(0.1, deadline - time.monotonic())))
            if message.get("id") == self._next:
                assert "error" not in message, f"{method} failed: {message['error']}"
                return dict(message.get("result", {}))
            self.events.append(message)

    def wait_event(self, name: str, timeout: float = 30.0) -> dict[str, Any]:
        """The first event ``name`` not yet consumed (waiting for it), consuming it."""
        while True:
            for n, event in enumerate(self.events):
                if event.get("method") == name:
                    return self.events.pop(n)
            self.events.append(json.loads(self.socket.recv(timeout=timeout)))

    def evaluate(self, expression: str, timeout: float = 30.0, *, strict: bool = True) -> Any:
        """The value of ``expression`` in the page (awaited when it is a promise); one that
        throws fails the test when ``strict``, else gives ``None``."""
        result = self.call(
            "Runtime.evaluate", timeout, expression=expression, awaitPromise=True, returnByValue=True
        )
        if "exceptionDetails" in result:
            assert not strict, f"{expression!r} threw: {result['exceptionDetails']}"
            return None
        return result.get("result", {}).get("value")

    def goto(self, url: str) -> None:
        """Load ``url`` and wait for its load event."""
        self.events.clear()
        self.call("Page.navigate", url=url)
        self.wait_event("Page.loadEventFired")

    def press(self, key: str) -> None:
        """Press and release ``key`` (``KeyboardEvent.key``: ``"ArrowUp"``, ``"t"``, ``"2"``)."""
        code = KEY_CODES.get(key, ord(key.upper()) if len(key) == 1 else 0)
        down: dict[str, Any] = {"type": "keyDown", "key": key, "windowsVirtualKeyCode": code}
        if len(key) == 1:
            down["text"] = key
        self.call("Input.dispatchKeyEvent", **down)
        self.call("Input.dispatchKeyEvent", type="keyUp", key=key, windowsVirtualKeyCode=code)

    def hold(self, key: str, repeats: int) -> None:
        """Hold ``key`` down as a keyboard does: one press, then ``repeats`` auto-repeats
        (``KeyboardEvent.repeat`` true), sent as fast as the link takes them, then release."""
        code = KEY_CODES.get(key, ord(key.upper()) if len(key) == 1 else 0)
        self.call("Input.dispatchKeyEvent", type="keyDown", key=key, windowsVirtualKeyCode=code)
        for _ in range(repeats):
            self.call(
                "Input.dispatchKeyEvent", type="keyDown", key=key, windowsVirtualKeyCode=code, autoRepeat=True
            )
        self.call("Input.dispatchKeyEvent", type="keyUp", key=key, windowsVirtualKeyCode=code)

    def wait_for(self, expression: str, timeout: float, what: str) -> Any:
        """Wait until ``expression`` is truthy in the page (polled; throwing counts as not yet)."""
        value = wait_until(lambda: self.evaluate(expression, strict=False), timeout, f"{what} ({expression})")
        return value

    def screenshot(self, path: Path) -> None:
        data = self.call("Page.captureScreenshot", format="png")["data"]
        path.write_bytes(base64.b64decode(data))

    def close(self) -> None:
        self.socket.close()


class Browser:
    """Headless Chromium with remote debugging on a free port, its profile in ``profile`` (a
    temporary folder when ``None``); a context manager that stops it with all its helpers."""

    def __init__(self, profile: Path | None = None, width: int = 1200, height: int = 800) -> None:
        binary = shutil.which("chromium") or shutil.which("chromium-browser")
        assert binary is not None, "chromium is not installed (apt-get install chromium)"
        self._temporary = tempfile.TemporaryDirectory() if profile is None else None
        self.profile = Path(self._temporary.name) if self._temporary is not None else profile
        assert self.profile is not None
        flags = [f for f in CHROMIUM_FLAGS if not f.startswith("--virtual-time-budget")]
        self.process = subprocess.Popen(
            [binary, *flags, f"--user-data-dir={self.profile}", f"--window-size={width},{height}",
             "--remote-debugging-port=0", "--remote-allow-origins=*", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
        )  # fmt: skip
        active = self.profile / "DevToolsActivePort"
        wait_until(
            lambda: self._running() and active.exists() and active.read_text().strip(),
            60,
            "chromium's DevTools port",
        )
        self.port = int(active.read_text().split()[0])

    def _running(self) -> bool:
        assert self.process.poll() is None, f"chromium exited with status {self.process.returncode}"
        return True

    def _http(self, path: str, method: str = "GET") -> Any:
        request = urllib.request.Request(f"http://127.0.0.1:{self.port}{path}", method=method)
        with urllib.request.urlopen(request, timeout=30) as response:
            return json.loads(response.read())

    def first_tab(self) -> Tab:
        """The blank page the browser started with."""
        page = next(t for t in self._http("/json/list") if t.get("type") == "page")
        return _enabled(Tab(page["webSocketDebuggerUrl"], self.port))

    def open(self, url: str) -> Tab:
        """A new tab on ``url``."""
        return open_tab(self.port, url)

    def close_tab(self, tab: Tab) -> None:
        """Close ``tab`` as a participant closes theirs."""
        target = tab.call("Target.getTargetInfo")["targetInfo"]["targetId"]
        tab.close()
        urllib.request.urlopen(f"http://127.0.0.1:{self.port}/json/close/{target}", timeout=30).close()

    def close(self) -> None:
        stop_process_group(self.process)
        if self._temporary is not None:
            self._temporary.cleanup()

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _enabled(tab: Tab) -> Tab:
    tab.call("Page.enable")
    return tab


def open_tab(port: int, url: str = "about:blank") -> Tab:
    """A new tab on ``url`` in the browser whose DevTools port is ``port``."""
    request = urllib.request.Request(f"http://127.0.0.1:{port}/json/new?{url}", method="PUT")
    with urllib.request.urlopen(request, timeout=30) as response:
        target = json.loads(response.read())
    return _enabled(Tab(target["webSocketDebuggerUrl"], port))


@contextmanager
def chromium(profile: Path, width: int = 1000, height: int = 750) -> Iterator[Tab]:
    """A headless Chromium with one blank page, stopped with all its helpers on exit."""
    with Browser(profile, width, height) as browser:
        tab = browser.first_tab()
        try:
            yield tab
        finally:
            tab.close()


@contextmanager
def another_page(first: Tab) -> Iterator[Tab]:
    """A second tab of ``first``'s browser (its own page, the same browser profile)."""
    tab = open_tab(first.port)
    try:
        yield tab
    finally:
        tab.close()


def wait_until(predicate: Callable[[], Any], timeout: float, what: str) -> Any:
    """Poll ``predicate`` until truthy; its value."""
    deadline = time.monotonic() + timeout
    value = None
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"waited {timeout:g} s for {what}; last value {value!r}")
