"""Executors run stage tasks. The runner only talks to the :class:`Executor` protocol, so a
distributed engine (e.g. Ray) can be added beside these without touching stages or the runner."""

from __future__ import annotations

import multiprocessing
import os
import queue
from concurrent.futures import Future, ProcessPoolExecutor
from typing import Any, Protocol, runtime_checkable

from pipeline.worker import StageTask, TaskResult, run_task


@runtime_checkable
class Executor(Protocol):
    """Runs :class:`~pipeline.worker.StageTask` objects and reports :class:`TaskResult` futures.

    Attributes
    ----------
    jobs : int
        How many tasks may run at once.
    progress : queue-like
        Where tasks put ``(node_id, done, total, description)`` progress tuples; the runner drains it
        with ``get_nowait``.
    """

    jobs: int
    progress: Any

    def submit(self, task: StageTask) -> Future[TaskResult]:
        """Start ``task``; the future resolves to its result (or raises if the worker died)."""
        ...

    def restart(self) -> None:
        """Replace a broken pool (a worker was killed) so that remaining tasks can run."""
        ...

    def close(self) -> None:
        """Release workers."""
        ...


class InlineExecutor:
    """Runs each task in the calling process, one at a time (debugging, tests)."""

    def __init__(self) -> None:
        self.jobs = 1
        self.progress: queue.Queue[tuple[str, int, int, str]] = queue.Queue()

    def submit(self, task: StageTask) -> Future[TaskResult]:
        """Run ``task`` now and return a finished future."""
        future: Future[TaskResult] = Future()
        future.set_result(run_task(task, self.progress))
        return future

    def restart(self) -> None:
        """Nothing to restart."""

    def close(self) -> None:
        """Nothing to release."""


class LocalProcessExecutor:
    """Runs tasks in fresh local processes (one process per task, so peak memory is per task).

    Parameters
    ----------
    jobs : int, optional
        Parallel processes; default: the number of cores.
    """

    def __init__(self, jobs: int | None = None) -> None:
        self.jobs = max(1, jobs or os.cpu_count() or 1)
        self._context = multiprocessing.get_context("spawn")
        self._manager = self._context.Manager()
        self.progress = self._manager.Queue()
        self._pool = self._new_pool()

    def _new_pool(self) -> ProcessPoolExecutor:
        return ProcessPoolExecutor(max_workers=self.jobs, mp_context=self._context, max_tasks_per_child=1)

    def submit(self, task: StageTask) -> Future[TaskResult]:
        """Queue ``task`` on the pool."""
        return self._pool.submit(run_task, task, self.progress)

    def restart(self) -> None:
        """Drop the broken pool and start a new one."""
        self._pool.shutdown(wait=False, cancel_futures=True)
        self._pool = self._new_pool()

    def close(self) -> None:
        """Stop the workers and the progress channel."""
        self._pool.shutdown(wait=True, cancel_futures=True)
        self._manager.shutdown()


def make_executor(jobs: int | None) -> Executor:
    """``jobs == 0``: in this process; otherwise local processes (default: one per core)."""
    if jobs == 0:
        return InlineExecutor()
    return LocalProcessExecutor(jobs)
