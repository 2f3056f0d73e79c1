"""The time left that long commands show (run-agent, eval): sound when several workers finish items
together, at the end of a run, and after a resume."""

from __future__ import annotations

import heapq
import io
import time

import pytest
from rich.console import Console
from rich.progress import Task, TaskID, TimeRemainingColumn

from navverse.commands.progress import PlainProgress, TimeLeft, _time_left_column, show_progress


class FakeClock:
    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def _finish_times(durations: list[float], workers: int, *, start_up: float = 0.0) -> list[float]:
    """When each item finishes, items taken in order by ``workers`` workers that start together."""
    free = [start_up] * workers
    finished = []
    for duration in durations:
        begin = heapq.heappop(free)
        finished.append(begin + duration)
        heapq.heappush(free, begin + duration)
    return sorted(finished)


def _run(finishes: list[float], *, resumed: int = 0) -> list[tuple[float, float | None]]:
    """``(true seconds left, estimate)`` at each finish, with progress called as items finish."""
    clock, lines = FakeClock(), []
    total = resumed + len(finishes)
    progress = PlainProgress("run", unit="episodes", write=lines.append, every=1, seconds=0.0, clock=clock)
    progress(resumed, total)
    seen = []
    for index, at in enumerate(finishes, 1):
        clock.now = at
        progress(resumed + index, total)
        seen.append((finishes[-1] - at, progress.time_left.seconds(resumed + index, total, at)))
    return seen


def test_the_last_episodes_of_a_parallel_run_are_an_episode_away_not_a_fraction_of_one():
    # Eight workers, ten 60 s episodes: eight finish together at 60 s, the last two start then.
    clock, lines = FakeClock(), []
    progress = PlainProgress("run-agent oracle on eval", unit="episodes", write=lines.append, every=1,
                             seconds=0.0, clock=clock)  # fmt: skip
    progress(0, 10)
    clock.now = 60.0
    for done in range(1, 9):
        progress(done, 10)
    # The pace alone (8 episodes per 60 s) would say 2 episodes are 15 s away: they are 60 s away.
    assert lines[-1] == "run-agent oracle on eval: 8/10 episodes, 60 s, ~60 s left"
    clock.now = 120.0
    progress(9, 10)
    progress(10, 10)
    assert lines[-1] == "run-agent oracle on eval: 10/10 episodes, 2 min"


@pytest.mark.parametrize("workers", [1, 2, 4, 8, 16])
@pytest.mark.parametrize("start_up", [0.0, 5.0])
def test_the_estimate_never_falls_short_of_the_work_in_flight(workers, start_up):
    seen = _run(_finish_times([60.0] * 50, workers, start_up=start_up))
    assert seen[-1][1] is None  # all done
    for index, (truth, estimate) in enumerate(seen[:-1], 1):
        assert estimate is not None
        assert estimate >= min(truth, 60.0), (index, truth, estimate)  # an episode left is 60 s away
        if index > workers:  # every worker has finished an episode: the pace is theirs together
            assert truth / 2 <= estimate <= 2 * truth + 60.0 + start_up, (index, truth, estimate)


def test_bursts_of_several_workers_do_not_fool_the_pace():
    # Sixteen workers on 40 s episodes: 16 finish at once every 40 s, and nothing between bursts.
    seen = _run(_finish_times([40.0] * 160, 16))
    for burst_end in range(32, 160, 16):  # once a burst is told in full, the estimate is the time left
        truth, estimate = seen[burst_end - 1]
        assert estimate == pytest.approx(truth)


def test_items_resumed_from_an_interrupted_run_do_not_count():
    # 50 of 100 done before; 25 more in an hour: an hour left, not 20 minutes.
    seen = _run([144.0 * (i + 1) for i in range(50)], resumed=50)
    assert seen[24] == (3600.0, pytest.approx(3600.0))


def test_no_estimate_before_an_item_finishes_in_this_run():
    estimate = TimeLeft()
    estimate.update(50, 0.0)  # resumed
    assert estimate.seconds(50, 100, 30.0) is None
    estimate.update(51, 40.0)
    assert estimate.seconds(51, 100, 40.0) == pytest.approx(49 * 40.0)
    assert estimate.seconds(100, 100, 50.0) is None


def test_the_bar_on_a_terminal_shows_the_same_estimate_instead_of_rich_s_own():
    column = _time_left_column()
    now = time.monotonic()
    task = Task(TaskID(0), "run", 10, 8, _get_time=time.monotonic, fields={"left": (60.0, now)})
    assert column.render(task).plain in ("~60 s left", "~59 s left")
    task = Task(TaskID(0), "run", 10, 8, _get_time=time.monotonic, fields={"left": (None, now)})
    assert column.render(task).plain == ""
    terminal = Console(file=io.StringIO(), force_terminal=True, width=100)
    with show_progress(terminal, "run", unit="episodes", columns=(TimeRemainingColumn(),)) as progress:
        progress(0, 3)
        progress(1, 3)
    drawn = terminal.file.getvalue()  # the bar's last frame, before it is cleared
    assert "~0 s left" in drawn and "0:00" not in drawn
