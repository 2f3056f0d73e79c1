"""Headless Chromium driven over the DevTools protocol on a pipe (``--remote-debugging-pipe``).

No Playwright or WebSocket client is needed: Chromium reads commands from its file descriptor 3 and
writes answers and events to 4, each message JSON ended by a NUL byte. Clicks and typing are real input
events (``Input.dispatchMouseEvent`` at the element's centre, ``Input.insertText`` into the focused
field), so the page's own handlers run as they would for a person. The browser is the one the report
screenshot uses (:func:`navverse.eval.screenshot.find_browser`).
"""

from __future__ import annotations

import contextlib
import fcntl
import json
import os
import select
import signal
import subprocess
import sys
import tempfile
import time
from typing import Any

_FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run", "--remote-debugging-pipe",
)  # fmt: skip
_SPAWN = (
    "import os, sys; os.dup2(int(sys.argv[1]), 3); os.dup2(int(sys.argv[2]), 4); "
    "os.execvp(sys.argv[3], sys.argv[3:])"
)
"""Puts the pipe ends at descriptors 3 and 4 of the browser (what --remote-debugging-pipe reads); a shell
would do, but dash takes only one-digit descriptor numbers."""


def _high(fd: int) -> int:
    """``fd`` moved to a descriptor number of at least 10 (the old one closed)."""
    moved = fcntl.fcntl(fd, fcntl.F_DUPFD, 10)
    os.close(fd)
    return moved


class BrowserError(AssertionError):
    """The browser did not answer, or a page script failed."""


class Browser:
    """One headless Chromium with one page, attached over the pipe.

    Parameters
    ----------
    executable : str
        The browser.
    width, height : int
        Window size (pixels).
    timeout : float
        Seconds to wait for any one answer.
    """

    def __init__(
        self, executable: str, *, width: int = 1280, height: int = 1400, timeout: float = 60.0
    ) -> None:
        self.timeout = timeout
        self.events: list[dict[str, Any]] = []
        self._profile = tempfile.TemporaryDirectory(prefix="navverse-cdp-", ignore_cleanup_errors=True)
        to_browser_r, self._to_browser = os.pipe()
        self._from_browser, from_browser_w = os.pipe()
        # The browser's ends above 9, so that moving them to 3 and 4 never overwrites one with the other.
        to_browser_r, from_browser_w = (_high(fd) for fd in (to_browser_r, from_browser_w))
        command = [
            sys.executable, "-c", _SPAWN, str(to_browser_r), str(from_browser_w), executable, *_FLAGS,
            f"--user-data-dir={self._profile.name}", f"--window-size={width},{height}", "about:blank",
        ]  # fmt: skip
        self._log = tempfile.TemporaryFile()  # noqa: SIM115 (closed in close(); told when it fails)
        self.process = subprocess.Popen(
            command, pass_fds=(to_browser_r, from_browser_w), stdout=self._log, stderr=self._log,
            start_new_session=True,
        )  # fmt: skip
        os.close(to_browser_r)
        os.close(from_browser_w)
        self._buffer = b""
        self._next_id = 0
        self.session = ""
        try:
            self._attach()
        except BaseException:
            self.close()
            raise

    # ------------------------------------------------------------------ protocol

    def _attach(self) -> None:
        deadline = time.monotonic() + self.timeout
        while True:
            targets = self.send("Target.getTargets", session=None)["targetInfos"]
            pages = [t for t in targets if t["type"] == "page"]
            if pages or time.monotonic() > deadline:
                break
            time.sleep(0.1)
        if not pages:
            raise BrowserError("the browser opened no page")
        attached = self.send(
            "Target.attachToTarget", {"targetId": pages[0]["targetId"], "flatten": True}, session=None
        )
        self.session = attached["sessionId"]
        self.send("Runtime.enable")
        self.send("Page.enable")

    def send(self, method: str, params: dict[str, Any] | None = None, *, session: str | None = "") -> dict:
        """Send a command (to the page's session unless ``session`` is None) and return its result."""
        self._next_id += 1
        message: dict[str, Any] = {"id": self._next_id, "method": method, "params": params or {}}
        if session is not None:
            message["sessionId"] = session or self.session
        os.write(self._to_browser, json.dumps(message).encode("utf-8") + b"\0")
        while True:
            answer = self._receive()
            if answer.get("id") == self._next_id:
                if "error" in answer:
                    raise BrowserError(f"{method}: {answer['error']}")
                return answer.get("result", {})
            self.events.append(answer)

    def _receive(self) -> dict[str, Any]:
        deadline = time.monotonic() + self.timeout
        while b"\0" not in self._buffer:
            left = deadline - time.monotonic()
            ready, _, _ = select.select([self._from_browser], [], [], max(left, 0.0))
            if not ready:
                raise BrowserError(f"the browser did not answer within {self.timeout:g} s")
            chunk = os.read(self._from_browser, 1 << 16)
            if not chunk:
                raise BrowserError(f"the browser closed its pipe; its last output:\n{self._tail()}")
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def _tail(self, lines: int = 12) -> str:
        self._log.seek(0)
        return "\n".join(self._log.read().decode("utf-8", "replace").splitlines()[-lines:])

    # ------------------------------------------------------------------ page

    def goto(self, url: str) -> None:
        """Open ``url`` in the page."""
        self.send("Page.navigate", {"url": url})

    def evaluate(self, expression: str) -> Any:
        """The value of a JavaScript expression in the page (promises awaited)."""
        result = self.send(
            "Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True}
        )
        if "exceptionDetails" in result:
            raise BrowserError(f"{expression!r} threw: {result['exceptionDetails']}")
        return result["result"].get("value")

    def wait_for(self, expression: str, *, timeout: float | None = None) -> Any:
        """Poll an expression until it is truthy; its value."""
        deadline = time.monotonic() + (timeout or self.timeout)
        while True:
            value = self.evaluate(expression)
            if value:
                return value
            if time.monotonic() > deadline:
                raise BrowserError(f"{expression!r} still false after {timeout or self.timeout:g} s")
            time.sleep(0.1)

    def click(self, selector: str) -> None:
        """A left click at the centre of the element ``selector`` (scrolled into view first)."""
        found = self.evaluate(
            f"(() => {{ const e = document.querySelector({json.dumps(selector)}); if (!e) return null;"
            " e.scrollIntoView({block: 'center'}); const r = e.getBoundingClientRect();"
            " return [r.x + r.width / 2, r.y + r.height / 2]; })()"
        )
        if found is None:
            raise BrowserError(f"no element {selector!r} on the page")
        x, y = found
        self.send("Input.dispatchMouseEvent", {"type": "mouseMoved", "x": x, "y": y})
        for kind in ("mousePressed", "mouseReleased"):
            self.send(
                "Input.dispatchMouseEvent", {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1}
            )

    def type_into(self, selector: str, text: str) -> None:
        """Click a text field and type ``text`` into it."""
        self.click(selector)
        self.send("Input.insertText", {"text": text})

    def page_errors(self) -> list[str]:
        """Uncaught exceptions and console errors the page reported so far."""
        errors = []
        for event in self.events:
            if event.get("method") == "Runtime.exceptionThrown":
                errors.append(str(event["params"]["exceptionDetails"].get("text")))
            elif event.get("method") == "Runtime.consoleAPICalled" and event["params"]["type"] == "error":
                errors.append(str(event["params"]["args"]))
        return errors

    def close(self) -> None:
        """End the browser and its helper processes."""
        try:
            os.killpg(self.process.pid, signal.SIGTERM)
            self.process.wait(timeout=5)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.process.pid, signal.SIGKILL)
            self.process.wait()
        for fd in (self._to_browser, self._from_browser):
            with contextlib.suppress(OSError):
                os.close(fd)
        self._profile.cleanup()
        self._log.close()

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
