"""Progress of the long data commands (eval, run-agent, validate dataset --replay): a rich bar on a
terminal, plain lines on stderr otherwise (:class:`PlainProgress`)."""

from __future__ import annotations

import sys
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from rich.console import Console

__all__ = ["PLAIN_PROGRESS_PARTS", "PLAIN_PROGRESS_SECONDS", "PlainProgress", "TimeLeft", "show_progress"]


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


class TimeLeft:
    """How long the items not done yet will take, from the items finished so far in this run.

    Told ``update(done, now)`` as items finish (the first call starts the run: items done by then, e.g.
    resumed from an interrupted run, do not count), :meth:`seconds` estimates the time left as the
    larger of:

    - the items left at the pace of this run: the time since it started per item finished since.
      Taken over the whole run, the pace is that of every worker together and is not fooled by
      items that finish in bursts;
    - the time the first item of the run took (from the start, so with the workers' start-up). The
      pace is a throughput: with several workers, the items left once fewer than the workers still
      take about one item's time, not a fraction of it (with eight workers on 60 s episodes, the two
      left are 60 s away; the pace alone says 15 s). This accounts for the work in flight at the end
      of a run, when the last items run side by side.

    No estimate before an item has finished in this run, nor once every item is done.
    """

    def __init__(self) -> None:
        self._start: tuple[float, int] | None = None
        self._first: float | None = None

    @property
    def start(self) -> tuple[float, int] | None:
        """``(clock time, items done)`` at the first call, or None before it."""
        return self._start

    def update(self, done: int, now: float) -> None:
        """Take the count of items done at clock time ``now`` (s)."""
        if self._start is None:
            self._start = (now, done)
        elif self._first is None and done > self._start[1]:
            self._first = now - self._start[0]

    def seconds(self, done: int, total: int, now: float) -> float | None:
        """The estimated seconds left with ``done`` of ``total`` items done at clock time ``now``, or None."""
        if self._start is None or self._first is None or done >= total:
            return None
        start_time, start_done = self._start
        finished, elapsed = done - start_done, now - start_time
        if finished <= 0 or elapsed <= 0:
            return None
        return max((total - done) * elapsed / finished, self._first)


class PlainProgress:
    """Progress as plain lines, for output that is not a terminal (a log file, a pipe, a batch job).

    Called as ``progress(done, total)``. A line is written once both ``every`` more items are done and
    ``seconds`` have passed since the last line (whichever comes later), and once when the last item is
    done, e.g. ``run-agent oracle on eval: 12/157 episodes, 45 s, ~9 min left``. The time left is
    :class:`TimeLeft`'s estimate: from the items finished since the first call (items already done
    then, resumed from an interrupted run, do not count), and never less than the first item took.

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
        self.time_left = TimeLeft()
        self._last: tuple[float, int] | None = None
        self._finished = False

    def __call__(self, done: int, total: int) -> None:
        """Take the count of items done of ``total``; write a line when one is due."""
        now = self.clock()
        self.time_left.update(done, now)
        if self._last is None:
            self._last = (now, done)
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
        start_time, _ = self.time_left.start or (now, done)
        text = f"{self.label}: {done}/{total} {self.unit}, {_duration(now - start_time)}"
        left = self.time_left.seconds(done, total, now)
        if left is not None:
            text += f", ~{_duration(left)} left"
        return text


@contextmanager
def show_progress(
    console: Console, label: str, *, unit: str, columns: tuple = ()
) -> Iterator[Callable[[int, int], None]]:
    """A ``progress(done, total)`` callable: a rich bar on a terminal (with ``columns``, or rich's
    default ones), plain lines on stderr otherwise (:class:`PlainProgress`), where a bar is not shown.

    The time left is :class:`TimeLeft`'s estimate on both: on the bar, a rich ``TimeRemainingColumn``
    among the columns shows it, counting down between items (rich's own estimate is a speed over the
    last 30 s, which items finishing together in a burst send soaring).
    """
    if not console.is_terminal:
        yield PlainProgress(label, unit=unit)
        return
    from rich.progress import Progress, TimeRemainingColumn

    shown = tuple(
        _time_left_column() if isinstance(column, TimeRemainingColumn) else column
        for column in (columns or Progress.get_default_columns())
    )
    estimate = TimeLeft()
    with Progress(*shown, console=console, transient=True) as bar:
        task = bar.add_task(label, total=None, left=(None, 0.0))

        def update(done: int, total: int) -> None:
            now = time.monotonic()
            estimate.update(done, now)
            bar.update(task, completed=done, total=total, left=(estimate.seconds(done, total, now), now))

        yield update


def _time_left_column() -> Any:
    """A rich progress column: ``~9 min left``, the task's ``left`` field ``(seconds or None, clock
    time of the estimate)`` counted down since it was made."""
    from rich.progress import ProgressColumn, Task
    from rich.text import Text

    class TimeLeftColumn(ProgressColumn):
        def render(self, task: Task) -> Text:
            seconds, at = task.fields.get("left", (None, 0.0))
            if seconds is None or task.finished:
                return Text("")
            left = max(0.0, seconds - (time.monotonic() - at))
            return Text(f"~{_duration(left)} left", style="progress.remaining")

    return TimeLeftColumn()
