"""Screenshot an evaluation report (or any page) in headless Chromium and check it for console errors.

Usage::

    python scripts/report_screenshot.py eval-out/report.html -o report.png [--width 1280 --height 2400]

Runs :func:`navverse.eval.screenshot.screenshot_report` (``chromium``, ``chromium-browser`` or
``google-chrome`` on ``PATH``; ``scripts/system-deps.sh`` installs Debian's ``chromium``). Exits 1 with
the reason when no browser is found, it wrote no screenshot or timed out, or the page logged console
errors; 0 otherwise.
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from navverse.eval.screenshot import ScreenshotError, screenshot_report


def main(argv: Sequence[str] | None = None) -> int:
    """Parse the arguments, take the screenshot, print what went wrong; the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("html", help="the page, e.g. eval-out/report.html")
    parser.add_argument("-o", "--out", required=True, help="the PNG to write")
    parser.add_argument("--width", type=int, default=1280, help="window width in pixels (default 1280)")
    parser.add_argument("--height", type=int, default=2400, help="window height in pixels (default 2400)")
    parser.add_argument("--timeout", type=float, default=120.0, help="seconds to wait (default 120)")
    args = parser.parse_args(argv)
    try:
        errors = screenshot_report(
            args.html, args.out, width=args.width, height=args.height, timeout=args.timeout
        )
    except ScreenshotError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    if errors:
        print(f"error: {args.html} logged {len(errors)} console errors:", file=sys.stderr)
        for line in errors:
            print(f"  {line}", file=sys.stderr)
        return 1
    print(f"wrote {args.out} ({args.width} x {args.height}), no console errors")
    return 0


if __name__ == "__main__":
    sys.exit(main())
