"""Headless Chromium driven through the DevTools protocol over a WebSocket (the ``websockets``
library; no Selenium): open tabs, press keys, read the page's state, take screenshots."""

from __future__ import annotations

import base64
import json
import shutil
import subprocess
import tempfile
import time
import urllib.request
from collections.abc import Callable
from pathlib import Path
from typing import Any

from websockets.sync.client import ClientConnection, connect

from bridge.processes import stop_process_group
from bridge.view.screenshot import CHROMIUM_FLAGS

KEY_CODES = {"ArrowLeft": 37, "ArrowUp": 38, "ArrowRight": 39, "ArrowDown": 40, " ": 32}


class Tab:
    """One page of the browser, over its DevTools WebSocket."""

    def __init__(self, url: str) -> None:
        self.socket: ClientConnection = connect(url, max_size=64 * 1024 * 1024, open_timeout=30).__enter__()
        self._id = 0

    def call(self, method: str, timeout: float = 30.0, **params: Any) -> dict[str, Any]:
        """Call a DevTools method and return its result (events in between are skipped)."""
        self._id += 1
        self.socket.send(json.dumps({"id": self._id, "method": method, "params": params}))
        deadline = time.monotonic() + timeout
        while True:
            reply = json.loads(self.socket.recv(timeout=max(0.1, deadline - time.monotonic())))
            if reply.get("id") == self._id:
                assert "error" not in reply, f"{method} failed: {reply['error']}"
                return dict(reply.get("result", {}))

    def evaluate(self, expression: str) -> Any:
        """The value of a JavaScript expression in the page (JSON-able)."""
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        return result.get("result", {}).get("value")

    def navigate(self, url: str) -> None:
        self.call("Page.navigate", url=url)

    def press(self, key: str) -> None:
        """Press and release ``key`` (``KeyboardEvent.key``: ``"ArrowUp"``, ``"t"``, ``"2"``)."""
        code = KEY_CODES.get(key, ord(key.upper()) if len(key) == 1 else 0)
        down: dict[str, Any] = {"type": "keyDown", "key": key, "windowsVirtualKeyCode": code}
        if len(key) == 1:
            down["text"] = key
        self.call("Input.dispatchKeyEvent", **down)
        self.call("Input.dispatchKeyEvent", type="keyUp", key=key, windowsVirtualKeyCode=code)

    def wait_for(self, expression: str, timeout: float, what: str) -> Any:
        """Wait until ``expression`` is truthy in the page (polled); its value."""
        deadline = time.monotonic() + timeout
        value = None
        while time.monotonic() < deadline:
            value = self.evaluate(expression)
            if value:
                return value
            time.sleep(0.1)
        raise AssertionError(f"waited {timeout:g} s for {what} ({expression}); last value {value!r}")

    def screenshot(self, path: Path) -> None:
        data = self.call("Page.captureScreenshot", format="png")["data"]
        path.write_bytes(base64.b64decode(data))

    def close(self) -> None:
        self.socket.close()


class Browser:
    """Headless Chromium with remote debugging on a free port; a context manager."""

    def __init__(self, width: int = 1200, height: int = 800) -> None:
        binary = shutil.which("chromium") or shutil.which("chromium-browser")
        assert binary is not None, "chromium is not installed"
        self._profile = tempfile.TemporaryDirectory()
        flags = [f for f in CHROMIUM_FLAGS if not f.startswith("--virtual-time-budget")]
        self.process = subprocess.Popen(
            [binary, *flags, f"--user-data-dir={self._profile.name}", f"--window-size={width},{height}",
             "--remote-debugging-port=0", "--remote-allow-origins=*", "about:blank"],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
        )  # fmt: skip
        active = Path(self._profile.name) / "DevToolsActivePort"
        deadline = time.monotonic() + 60
        while not (active.exists() and active.read_text().strip()):
            assert self.process.poll() is None, f"chromium exited with status {self.process.returncode}"
            assert time.monotonic() < deadline, "chromium did not open its DevTools port within 60 s"
            time.sleep(0.1)
        self.port = int(active.read_text().split()[0])

    def _http(self, path: str, method: str = "GET") -> Any:
        request = urllib.request.Request(f"http://127.0.0.1:{self.port}{path}", method=method)
        with urllib.request.urlopen(request, timeout=30) as response:
            return json.loads(response.read())

    def open(self, url: str) -> Tab:
        """A new tab on ``url``."""
        target = self._http(f"/json/new?{url}", method="PUT")
        tab = Tab(target["webSocketDebuggerUrl"])
        tab.call("Page.enable")
        return tab

    def close_tab(self, tab: Tab) -> None:
        """Close ``tab`` as a participant closes theirs."""
        target = tab.call("Target.getTargetInfo")["targetInfo"]["targetId"]
        tab.close()
        urllib.request.urlopen(f"http://127.0.0.1:{self.port}/json/close/{target}", timeout=30).close()

    def close(self) -> None:
        stop_process_group(self.process)
        self._profile.cleanup()

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def wait_until(predicate: Callable[[], Any], timeout: float, what: str) -> Any:
    """Poll ``predicate`` until truthy; its value."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError(f"waited {timeout:g} s for {what}")
