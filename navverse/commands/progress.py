"""Progress of the long data commands (eval, run-agent, validate dataset --replay): a rich bar on a
terminal, plain lines on stderr otherwise (:class:`PlainProgress`)."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

from rich.console import Console

__all__ = ["PLAIN_PROGRESS_PARTS", "PLAIN_PROGRESS_SECONDS", "PlainProgress", "show_progress"]


PLAIN_PROGRESS_SECONDS = 10.0
"""Without a terminal, the least wall time between two progress lines (s)."""

PLAIN_PROGRESS_PARTS = 20
"""Without a terminal, the least work between two progress lines: this fraction of the total (1/20)."""


def _stderr_line(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _duration(seconds: float) -> str:
    """A wall time for people: ``45 s``, ``9 min``, ``2.5 h``."""
    if seconds < 99.5:
        return f"{seconds:.0f} s"
    if seconds < 99.5 * 60:
        return f"{seconds / 60:.0f} min"
    return f"{seconds / 3600:.1f} h"


class PlainProgress:
    """Progress as plain lines, for output that is not a terminal (a log file, a pipe, a batch job).

    Called as ``progress(done, total)``. A line is written once both ``every`` more items are done and
    ``seconds`` have passed since the last line (whichever comes later), and once when the last item is
    done, e.g. ``run-agent oracle on eval: 12/157 episodes, 45 s, ~9 min left``. The time left is
    estimated from the rate since the first call, so items already done then (resumed from an
    interrupted run) do not count.

    Parameters
    ----------
    label : str
        What is going on; starts each line.
    unit : str
        What is counted (``episodes``, ``scenes``).
    write : callable, optional
        Called with each line (default: print it to stderr and flush).
    every : int, optional
        Items between lines (default: the total / :data:`PLAIN_PROGRESS_PARTS`, at least 1).
    seconds : float, optional
        Wall time between lines (default: :data:`PLAIN_PROGRESS_SECONDS`).
    clock : callable, optional
        Seconds of a monotonic clock (default: :func:`time.monotonic`).
    """

    def __init__(
        self,
        label: str,
        *,
        unit: str,
        write: Callable[[str], None] = _stderr_line,
        every: int | None = None,
        seconds: float | None = None,
        clock: Callable[[], float] = time.monotonic,
    ) -> None:
        self.label, self.unit, self.write, self.every, self.clock = label, unit, write, every, clock
        self.seconds = PLAIN_PROGRESS_SECONDS if seconds is None else seconds
        self._start: tuple[float, int] | None = None
        self._last: tuple[float, int] = (0.0, 0)
        self._finished = False

    def __call__(self, done: int, total: int) -> None:
        """Take the count of items done of ``total``; write a line when one is due."""
        now = self.clock()
        if self._start is None:
            self._start = self._last = (now, done)
        every = self.every if self.every is not None else max(1, total // PLAIN_PROGRESS_PARTS)
        last_time, last_done = self._last
        finished = total > 0 and done >= total
        due = done - last_done >= every and now - last_time >= self.seconds
        if (finished and not self._finished) or (due and not finished):
            self.write(self.line(done, total, now))
            self._last = (now, done)
        self._finished = self._finished or finished

    def line(self, done: int, total: int, now: float) -> str:
        """The progress line for ``done`` of ``total`` items at clock time ``now``."""
        start_time, start_done = self._start if self._start is not None else (now, done)
        elapsed = now - start_time
        text = f"{self.label}: {done}/{total} {self.unit}, {_duration(elapsed)}"
        if done < total and done > start_done and elapsed > 0:
            left = (total - done) * elapsed / (done - start_done)
            text += f", ~{_duration(left)} left"
        return text


@contextmanager
def show_progress(
    console: Console, label: str, *, unit: str, columns: tuple = ()
) -> Iterator[Callable[[int, int], None]]:
    """A ``progress(done, total)`` callable: a rich bar on a terminal (with ``columns``, or rich's
    default ones), plain lines on stderr otherwise (:class:`PlainProgress`), where a bar is not shown."""
    if not console.is_terminal:
        yield PlainProgress(label, unit=unit)
        return
    from rich.progress import Progress

    with Progress(*columns, console=console, transient=True) as bar:
        task = bar.add_task(label, total=None)
        yield lambda done, total: bar.update(task, completed=done, total=total)
