"""Executors run stage tasks. The runner only talks to the :class:`Executor` protocol, so a
distributed engine (e.g. Ray) can be added beside these without touching stages or the runner.

:class:`LocalProcessExecutor` starts one spawned process per task (so peak memory is per task) and
talks to it over a pipe of its own: no server process (no ``multiprocessing.Manager``), nothing a
killed build leaves behind. Workers ignore SIGINT and die with the build process; :meth:`abort`
ends them (and their own children) at once. :class:`~pipeline.ray_executor.RayExecutor` runs the
same tasks as Ray tasks (``make_executor(kind="ray")``).

Each executor tells the tasks it starts where their ``ctx.map`` runs (:class:`~pipeline.context.FanOut`):
in the stage's process (:class:`InlineExecutor`), on a pool of the stage's share of the cores
(:class:`LocalProcessExecutor`: ``cores // jobs`` processes), or as Ray tasks.
"""

from __future__ import annotations

import contextlib
import multiprocessing
import os
import queue
import signal
import threading
import time
from collections.abc import Iterator
from concurrent.futures import Future
from dataclasses import dataclass, replace
from multiprocessing import connection, resource_tracker
from typing import Any, Literal, Protocol, runtime_checkable

import psutil

from pipeline.context import FanOut
from pipeline.errors import PipelineError
from pipeline.worker import StageTask, TaskResult, child_main, run_task, salvage_log

TERMINATE_GRACE_S = 3.0
"""How long aborted workers get to end on SIGTERM before they are killed."""


class WorkerDiedError(RuntimeError):
    """A worker process ended without a result (killed, out of memory, or the build was interrupted)."""


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
        """Start ``task``; the future resolves to its result, or raises :class:`WorkerDiedError`."""
        ...

    def abort(self) -> None:
        """Stop every running task now (the build was interrupted); their work is discarded."""
        ...

    def close(self) -> None:
        """Release workers (after the last result)."""
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

    def abort(self) -> None:
        """Nothing runs in the background."""

    def close(self) -> None:
        """Nothing to release."""


@dataclass(eq=False)
class _Job:
    task: StageTask
    process: Any  # multiprocessing.context.SpawnProcess
    reader: connection.Connection
    future: Future[TaskResult]
    result: TaskResult | None = None
    eof: bool = False


class LocalProcessExecutor:
    """Runs tasks in fresh local processes, one process per task.

    Parameters
    ----------
    jobs : int, optional
        Parallel processes; default: the number of cores.
    map_workers : int, optional
        Pool processes of a stage's ``ctx.map``; default: the stage's share of the cores
        (``cores // jobs``); with one, ``ctx.map`` runs in the stage's process.
    """

    def __init__(self, jobs: int | None = None, *, map_workers: int | None = None) -> None:
        self.jobs = max(1, jobs or os.cpu_count() or 1)
        share = max(1, map_workers or (os.cpu_count() or 1) // self.jobs)
        self.fanout = FanOut("processes", share) if share > 1 else FanOut("inline", 1)
        self.progress: queue.Queue[tuple[str, int, int, str]] = queue.Queue()
        self._context = multiprocessing.get_context("spawn")
        self._jobs: list[_Job] = []
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._watcher = threading.Thread(target=self._watch, name="navverse-executor", daemon=True)
        self._watcher.start()

    def submit(self, task: StageTask) -> Future[TaskResult]:
        """Start a worker process for ``task``."""
        task = replace(task, fanout=self.fanout)
        reader, writer = self._context.Pipe(duplex=False)
        process = self._context.Process(
            target=child_main, args=(task, writer, os.getpid()), name=f"navverse-stage {task.node_id}"
        )
        future: Future[TaskResult] = Future()
        future.set_running_or_notify_cancel()
        # Started here, not inside the block: starting it unblocks SIGINT instead of restoring the mask.
        resource_tracker.ensure_running()
        try:
            with _sigint_blocked(), _main_script_hidden():  # the child blocks SIGINT until it ignores it
                process.start()
                with self._lock:
                    self._jobs.append(_Job(task, process, reader, future))
        except BaseException:
            if process.pid is not None and process.is_alive():
                process.kill()
                process.join()
            raise
        finally:
            writer.close()
        return future

    def abort(self) -> None:
        """End every worker (SIGTERM, then SIGKILL after :data:`TERMINATE_GRACE_S`) and its children."""
        self._stop_watching()
        with self._lock:
            jobs, self._jobs = self._jobs, []
        _end_processes([job.process for job in jobs])
        for job in jobs:
            salvage_log(job.task, job.process.pid, "interrupted: the build was stopped")
            job.reader.close()
            if not job.future.done():
                job.future.set_exception(WorkerDiedError("interrupted"))

    def close(self) -> None:
        """Stop watching the workers (aborting any still running)."""
        with self._lock:
            busy = bool(self._jobs)
        if busy:
            self.abort()
        self._stop_watching()

    # -- the watcher thread: reads the pipes, resolves futures when workers end ------------------
    def _stop_watching(self) -> None:
        self._stop.set()
        if self._watcher.is_alive() and threading.current_thread() is not self._watcher:
            self._watcher.join()

    def _watch(self) -> None:
        while not self._stop.is_set():
            with self._lock:
                jobs = list(self._jobs)
            if not jobs:
                self._stop.wait(0.05)
                continue
            waitables: dict[Any, _Job] = {job.process.sentinel: job for job in jobs}
            waitables.update({job.reader: job for job in jobs if not job.eof})
            ready = connection.wait(list(waitables), timeout=0.1)
            for item in ready:
                if isinstance(item, connection.Connection):
                    self._receive(waitables[item])
            for item in ready:
                if not isinstance(item, connection.Connection):
                    self._finish(waitables[item])

    def _receive(self, job: _Job) -> None:
        try:
            kind, payload = job.reader.recv()
        except (EOFError, OSError):
            job.eof = True
            return
        if kind == "progress":
            self.progress.put(payload)
        elif kind == "result":
            job.result = payload

    def _finish(self, job: _Job) -> None:
        """The worker of ``job`` ended: read what is left in its pipe, then resolve its future."""
        while not job.eof and job.reader.poll():
            self._receive(job)
        job.process.join()
        job.reader.close()
        with self._lock:
            if job not in self._jobs:  # aborted meanwhile
                return
            self._jobs.remove(job)
        if job.result is not None:
            job.future.set_result(job.result)
            return
        reason = _death(job.process.exitcode)
        salvage_log(job.task, job.process.pid, f"the worker process {reason}")
        job.future.set_exception(WorkerDiedError(f"the worker process {reason}"))


def _death(exitcode: int | None) -> str:
    """How a worker that sent no result ended, in words."""
    if exitcode is not None and exitcode < 0:
        try:
            name = signal.Signals(-exitcode).name
        except ValueError:
            name = f"signal {-exitcode}"
        return f"died ({name}: killed, or out of memory)"
    return f"exited with code {exitcode} before reporting a result"


_MAIN_LOCK = threading.Lock()


@contextlib.contextmanager
def _main_script_hidden() -> Iterator[None]:
    """Start processes that do not run the caller's ``__main__`` again.

    A spawned process imports the parent's main script or module before its target runs, so a script
    that builds (``navverse.api.build``) without an ``if __name__ == "__main__":`` guard would run again
    in every worker, and wait there for the workspace lock its parent holds. Workers need only the stage
    modules (imported by name), so the main module's file and spec are hidden while a process starts.
    """
    import sys

    main = sys.modules.get("__main__")
    if main is None:
        yield
        return
    with _MAIN_LOCK:
        saved = {name: main.__dict__[name] for name in ("__file__", "__spec__") if name in main.__dict__}
        main.__dict__.pop("__file__", None)
        main.__spec__ = None  # multiprocessing reads it: present, but naming no module
        try:
            yield
        finally:
            main.__dict__.pop("__spec__", None)
            main.__dict__.update(saved)


@contextlib.contextmanager
def _sigint_blocked() -> Iterator[None]:
    """Block SIGINT in this thread for the duration (a process started meanwhile inherits the block)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _end_processes(processes: list[Any]) -> None:
    """SIGTERM ``processes`` and their descendants, SIGKILL what is left after the grace time, reap."""
    descendants: list[psutil.Process] = []
    for process in processes:
        with contextlib.suppress(psutil.Error, ValueError):
            descendants += psutil.Process(process.pid).children(recursive=True)
    for process in processes:
        with contextlib.suppress(OSError, ValueError):
            process.terminate()
    for child in descendants:
        with contextlib.suppress(psutil.Error):
            child.terminate()
    deadline = time.monotonic() + TERMINATE_GRACE_S
    for process in processes:
        process.join(max(0.0, deadline - time.monotonic()))
        if process.exitcode is None:
            process.kill()
            process.join()
    for child in _still_running(descendants, deadline):
        with contextlib.suppress(psutil.Error):
            child.kill()


def _still_running(processes: list[psutil.Process], deadline: float) -> list[psutil.Process]:
    """Those of ``processes`` (not our children) still running at ``deadline``; zombies count as ended."""
    alive = list(processes)
    while alive:
        alive = [p for p in alive if _running(p)]
        if not alive or time.monotonic() >= deadline:
            break
        time.sleep(0.02)
    return alive


def _running(process: psutil.Process) -> bool:
    try:
        return process.is_running() and process.status() != psutil.STATUS_ZOMBIE
    except psutil.Error:
        return False


ExecutorKind = Literal["local", "ray"]


def make_executor(jobs: int | None, *, kind: ExecutorKind = "local", address: str | None = None) -> Executor:
    """The executor of a build.

    Parameters
    ----------
    jobs : int or None
        Tasks at once. Local: ``0`` runs in this process, default one process per core. Ray: the
        CPUs of the Ray instance started here, or a cap on the tasks sent to a cluster (default: its CPUs).
    kind : {"local", "ray"}
        Local processes, or Ray tasks (:class:`~pipeline.ray_executor.RayExecutor`).
    address : str, optional
        Ray only: ``None`` starts a Ray instance on this machine; ``"auto"``, ``host:port`` or
        ``ray://host:port`` connects to a running cluster.

    Raises
    ------
    PipelineError
        Ray is not installed, ``jobs == 0`` with Ray, or ``address`` without Ray.
    """
    if kind == "local":
        if address is not None:
            raise PipelineError("--address names a Ray cluster: use it with --executor ray")
        return InlineExecutor() if jobs == 0 else LocalProcessExecutor(jobs)
    if kind != "ray":
        raise PipelineError(f"unknown executor {kind!r}: use 'local' or 'ray'")
    if jobs == 0:
        raise PipelineError("--jobs 0 runs stages in this process; it does not combine with --executor ray")
    try:
        from pipeline.ray_executor import RayExecutor
    except ImportError as exc:
        raise PipelineError(
            f"--executor ray needs Ray ({exc}): pip install 'navverse[cluster]' (ray>=2.40,<3)"
        ) from None
    return RayExecutor(address, jobs)
