"""Screenshots of a page (an evaluation report) in headless Chromium, with the page's console errors,
and the DOM of a page once its scripts ran.

:func:`screenshot_report` runs Chromium with a throw-away profile and no network services, writes the
PNG and returns the console errors Chromium logged; ``scripts/report_screenshot.py`` is its command
line, and the report tests use it to check that ``report.html`` opens cleanly. :func:`page_dom` loads a
page (a file or a URL, e.g. the evaluation server's leaderboard) the same way and returns its DOM as
serialised after load (``--dump-dom``) with the console errors.
"""

from __future__ import annotations

import os
import re
import shutil
import signal
import subprocess
import tempfile
from pathlib import Path

from navverse.errors import NavverseError

__all__ = ["BROWSERS", "ScreenshotError", "find_browser", "page_dom", "screenshot_report"]

BROWSERS = ("chromium", "chromium-browser", "google-chrome", "google-chrome-stable")
"""Browser executables looked for on ``PATH``, in this order."""


class ScreenshotError(NavverseError):
    """No browser, a browser that fails or hangs, or no screenshot written."""


_CONSOLE_ERROR = re.compile(r"CONSOLE.*(ERROR|Uncaught|\bError\b)|Failed to load")
"""Chromium's stderr lines that tell of a page error. Its log carries no console level, so a plain
``console.error`` call is not told apart from ``console.log``; uncaught exceptions and error objects are."""
_FLAGS = (
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run", "--enable-logging=stderr", "--v=0",
)  # fmt: skip


def find_browser() -> str | None:
    """The first of :data:`BROWSERS` found on ``PATH``, or None."""
    for name in BROWSERS:
        found = shutil.which(name)
        if found is not None:
            return found
    return None


def _run_browser(
    target: str, flags: list[str], *, timeout: float, browser: str | None
) -> tuple[str, subprocess.Popen, str, str]:
    """Run the headless browser on `target` (a URI) with `flags`, in a throw-away profile: the
    executable, the ended process, its stdout and stderr; a ScreenshotError if there is no browser or
    it does not end within `timeout` s (it and its helpers are killed)."""
    executable = browser or find_browser()
    if executable is None:
        raise ScreenshotError(
            f"no headless browser found on PATH (looked for {', '.join(BROWSERS)}); on Debian install "
            "it with 'apt-get install chromium' (scripts/system-deps.sh does)"
        )
    with tempfile.TemporaryDirectory(prefix="navverse-chromium-", ignore_cleanup_errors=True) as profile:
        command = [executable, *_FLAGS, f"--user-data-dir={profile}", *flags, target]
        try:
            process = subprocess.Popen(
                command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, errors="replace",
                start_new_session=True,
            )  # fmt: skip
        except OSError as exc:
            raise ScreenshotError(f"cannot run the browser {executable}: {exc.strerror or exc}") from None
        try:
            stdout, stderr = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)  # the browser's own process group: it and its helpers
            process.communicate()
            raise ScreenshotError(
                f"{executable} did not finish rendering {target} within {timeout:g} s"
            ) from None
        finally:
            if process.poll() is None:
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
    return executable, process, stdout, stderr


def page_dom(
    page: str | os.PathLike[str], *, timeout: float = 120.0, browser: str | None = None
) -> tuple[str, list[str]]:
    """Load a page in headless Chromium and return its DOM once loaded (its scripts ran) and its console
    errors.

    Parameters
    ----------
    page : str or path
        A URL (``http://...``, ``file://...``) or an HTML file.
    timeout : float
        Seconds before the browser is stopped.
    browser : str, optional
        The browser executable; by default :func:`find_browser`.

    Returns
    -------
    tuple of (str, list of str)
        The serialised DOM (``--dump-dom``), and Chromium's stderr lines reporting console errors.

    Raises
    ------
    ScreenshotError
        If no browser is found, it times out, or it prints no DOM (with its last stderr lines).
    """
    text = os.fspath(page)
    target = text if "://" in text else Path(text).resolve().as_uri()
    executable, process, stdout, stderr = _run_browser(
        target, ["--dump-dom"], timeout=timeout, browser=browser
    )
    if "<html" not in stdout.lower():
        tail = "\n  ".join(stderr.splitlines()[-8:])
        raise ScreenshotError(
            f"{executable} printed no DOM of {target} (exit status {process.returncode}); its last output:\n"
            f"  {tail}"
        )
    return stdout, [line for line in stderr.splitlines() if _CONSOLE_ERROR.search(line)]


def screenshot_report(
    html_path: str | os.PathLike[str],
    png_path: str | os.PathLike[str],
    *,
    width: int = 1280,
    height: int = 2400,
    timeout: float = 120.0,
    browser: str | None = None,
) -> list[str]:
    """Render a page in headless Chromium, write a `width` × `height` PNG of it, return its console errors.

    Parameters
    ----------
    html_path : path
        The page (e.g. a ``report.html``).
    png_path : path
        The screenshot to write (replaced if present).
    width, height : int
        Window size in pixels, which is the screenshot's size.
    timeout : float
        Seconds before the browser is stopped.
    browser : str, optional
        The browser executable; by default :func:`find_browser`.

    Returns
    -------
    list of str
        Chromium's stderr lines reporting console errors (uncaught exceptions, errors, failed loads).

    Raises
    ------
    ScreenshotError
        If no browser is found, it times out, or it writes no screenshot (with its last stderr lines).
    """
    page = Path(html_path).resolve()
    png = Path(png_path).resolve()
    if not page.is_file():
        raise ScreenshotError(f"{page} does not exist")
    png.parent.mkdir(parents=True, exist_ok=True)
    png.unlink(missing_ok=True)
    flags = [f"--screenshot={png}", f"--window-size={int(width)},{int(height)}"]
    executable, process, stdout, stderr = _run_browser(page.as_uri(), flags, timeout=timeout, browser=browser)
    lines = (stdout + stderr).splitlines()
    if not png.is_file() or png.stat().st_size == 0:
        tail = "\n  ".join(lines[-8:])
        raise ScreenshotError(
            f"{executable} wrote no screenshot of {page} (exit status {process.returncode}); "
            f"its last output:\n  {tail}"
        )
    return [line for line in lines if _CONSOLE_ERROR.search(line)]
