"""Runs stage tasks as Ray tasks: ``navverse build --executor ray [--address ADDR]``.

Tasks
    Each :class:`~pipeline.worker.StageTask` becomes one Ray task that calls the same
    :func:`~pipeline.worker.run_task` a local worker process runs, in a Ray worker process of its
    own (``max_calls=1``: fresh state and a per-task peak memory, as locally). It requests
    ``num_cpus=1`` and, when the target's last build of the stage recorded its peak (the manifest's
    ``run.peak_rss_mb``), ``memory`` = that peak plus :data:`MEMORY_MARGIN` (capped at the largest
    node's memory, so a request never makes a task unschedulable). Nothing in ``run_task`` depends
    on the executor, so artifacts are byte-identical to a local build's.
Environment
    Local workers inherit the build's environment and import path; Ray workers get the same
    variables that matter through ``runtime_env={"env_vars": ...}`` (see :func:`worker_env`:
    ``NAVVERSE_*``, ``PYTHONHASHSEED``, the thread-count variables, and ``PYTHONPATH`` = the build's
    import path but the interpreter's own folders) and start in the build's working directory.
Progress
    A task's ``ctx.progress`` calls go to a small mailbox actor; a thread of the build drains it
    into :attr:`RayExecutor.progress` (a ``queue.Queue``), so the runner's bars work unchanged.
Lost workers
    A task whose worker or node dies (killed, out of memory, node lost) is retried by Ray
    (:data:`MAX_RETRIES` times); after that its future raises
    :class:`~pipeline.executors.WorkerDiedError`, like a local worker's death: the runner fails
    that stage and spares independent targets. The dead worker's log is published with a note.
Shared store
    Workers write artifacts straight into the store, so it must be on a filesystem every node
    mounts at the same path (NFS, etc.). Before the first task the build writes a token file into
    the store's ``tmp/`` and runs a tiny task on every alive node that reads it back; a node that
    cannot see it stops the build with :class:`StoreNotSharedError` naming the store.
Stopping
    :meth:`RayExecutor.abort` ends the running tasks by leaving Ray: a Ray instance the build started
    is shut down with its workers; from a cluster it joined the build disconnects, and the cluster
    ends the workers of the build's job (within a second). :meth:`RayExecutor.close` shuts Ray down
    only if it started it.
Cancellation
    Nothing here calls ``ray.cancel``: Ray's owner process can abort when a task is cancelled while
    its reply is arriving (a check in Ray's task manager: "Tried to complete task that was not
    pending"). ``ctx.map`` lets the chunks after a failing one end on their own.
"""

from __future__ import annotations

import contextlib
import logging
import os
import queue
import secrets
import signal
import sys
import threading
from collections.abc import Callable, Mapping
from concurrent.futures import Future
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import ray
from ray.util.scheduling_strategies import NodeAffinitySchedulingStrategy

from pipeline.context import FanOut, MapError, apply_chunk
from pipeline.errors import PipelineError
from pipeline.executors import WorkerDiedError
from pipeline.store import ArtifactStore
from pipeline.worker import StageTask, TaskResult, run_task, salvage_log

MAX_RETRIES = 2
"""How many times Ray re-runs a task whose worker or node died."""

MEMORY_MARGIN = 1.25
"""Memory request = recorded peak RSS times this."""

ENV_PREFIXES = ("NAVVERSE_",)
"""Environment variables with these prefixes reach the Ray workers."""

ENV_NAMES = ("PYTHONHASHSEED", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS")
"""Further environment variables that reach the Ray workers when the build has them."""

STORE_CHECK_TIMEOUT_S = 120.0
"""How long the shared-store check waits for its tasks (they may wait for a free worker)."""

_MB = 1024 * 1024


class StoreNotSharedError(PipelineError):
    """The Ray workers cannot see the artifact store (it is not on a shared filesystem)."""


# -- the worker side ---------------------------------------------------------------------------
@ray.remote(num_cpus=0)
class _Mailbox:
    """Collects progress and start messages of the tasks; the build drains it."""

    def __init__(self) -> None:
        self._items: list[tuple[Any, ...]] = []

    def put(self, item: tuple[Any, ...]) -> None:
        """Keep ``item``."""
        self._items.append(item)

    def drain(self) -> list[tuple[Any, ...]]:
        """Everything kept so far (and forget it)."""
        items, self._items = self._items, []
        return items


class _MailboxProgress:
    """Queue-like progress channel of a task on Ray (``put``)."""

    def __init__(self, mailbox: Any) -> None:
        self._mailbox = mailbox

    def put(self, item: tuple[str, int, int, str]) -> None:
        self._mailbox.put.remote(("progress", item))


def _end_at_once_on_sigterm() -> None:
    """Make SIGTERM end this worker at once.

    Ray stops a worker (its instance shut down, the build's job gone, the node drained) with
    SIGTERM, which it turns into ``SystemExit`` inside the running task: the stage would log that as
    its own failure and publish its log over the build's "interrupted" note, or report a failure
    where Ray should retry. Ending the process instead leaves the task to the build and to Ray.
    """
    with contextlib.suppress(ValueError):  # not the main thread: keep Ray's handler
        signal.signal(signal.SIGTERM, lambda signum, frame: os._exit(128 + signum))


def _stage_on_ray(task: StageTask, mailbox: Any, cwd: str) -> TaskResult:
    """Body of a stage's Ray task: say which process runs it, then :func:`run_task` (as locally)."""
    _end_at_once_on_sigterm()  # the worker runs one task (max_calls=1): the handler ends with it
    mailbox.put.remote(("started", task.node_id, os.getpid()))
    logging.raiseExceptions = False
    with contextlib.suppress(OSError):
        os.chdir(cwd)
    return run_task(task, _MailboxProgress(mailbox))


_remote_stage = ray.remote(max_calls=1)(_stage_on_ray)


@ray.remote(num_cpus=0, max_retries=0)
def _probe_store(root: str, token: str) -> tuple[str, str, str]:
    """On a node: ``(node address, token content, problem)``; ``problem`` is empty if the store is seen."""
    where = ray.util.get_node_ip_address()
    if not Path(root).is_dir():
        return where, "", f"{root} is not a directory there"
    try:
        return where, Path(token).read_text(encoding="utf-8"), ""
    except OSError as exc:
        return where, "", f"cannot read {token} there ({exc.strerror or exc})"


_remote_chunk = ray.remote(max_retries=MAX_RETRIES)(apply_chunk)


# -- ctx.map on Ray ------------------------------------------------------------------------------
def ray_map(
    fn: Callable[[Any], Any], chunks: list[tuple[int, list[Any]]], total: int, report: Callable[[int], None]
) -> list[Any]:
    """Run the chunks of a ``ctx.map`` as Ray tasks (one per chunk); results in item order.

    Called inside a stage's Ray task (Ray is initialised there); a blocked stage task lends its CPU
    to its chunks. On a :class:`~pipeline.context.MapError` the error of the lowest failing item is
    raised, as locally; later chunks are not cancelled (see "Cancellation" above), their results are
    dropped.
    """
    refs = [_remote_chunk.remote(fn, start, total, chunk) for start, chunk in chunks]
    results: list[Any] = []
    for ref in refs:
        try:
            results += ray.get(ref)
        except ray.exceptions.RayTaskError as exc:
            cause = getattr(exc, "cause", None)
            if isinstance(cause, MapError):
                raise MapError(*cause.args) from None
            raise
        report(len(results))
    return results


# -- the build side -----------------------------------------------------------------------------
def worker_env(environ: Mapping[str, str] | None = None, path: list[str] | None = None) -> dict[str, str]:
    """The environment variables Ray workers get so that they run stages as local workers do.

    Parameters
    ----------
    environ : mapping, optional
        The build's environment (default ``os.environ``).
    path : list of str, optional
        The build's import path (default ``sys.path``).

    Returns
    -------
    dict
        ``NAVVERSE_*`` and :data:`ENV_NAMES` as set in the build, and ``PYTHONPATH``: the build's
        import path (``''`` as the working directory) without the interpreter's own folders, so
        stage modules outside the installed packages import on workers as they do in spawned ones.
    """
    environ = os.environ if environ is None else environ
    env = {k: v for k, v in environ.items() if k.startswith(ENV_PREFIXES) or k in ENV_NAMES}
    own = tuple({os.path.realpath(p) for p in (sys.prefix, sys.base_prefix, sys.exec_prefix)})
    entries: list[str] = []
    for entry in sys.path if path is None else path:
        resolved = os.path.realpath(entry or os.getcwd())
        if os.path.isdir(resolved) and not resolved.startswith(own) and resolved not in entries:
            entries.append(resolved)
    if entries:
        env["PYTHONPATH"] = os.pathsep.join(entries)
    return env


def memory_request(task: StageTask, *, cap_bytes: float | None = None) -> int | None:
    """Bytes of memory to request for ``task``: the last recorded peak of the stage for the target.

    Read from the manifest the target's current artifact of the stage has (``run.peak_rss_mb``),
    times :data:`MEMORY_MARGIN`, capped at ``cap_bytes``; None when no build recorded one.
    """
    store = ArtifactStore(Path(task.store_root))
    peaks = []
    for out in task.outputs:
        path = store.target_output(task.target, out.name)
        manifest = store.read_manifest(path) if path is not None else None
        if manifest and manifest.get("stage") == task.stage:
            peak = manifest.get("run", {}).get("peak_rss_mb")
            if isinstance(peak, (int, float)) and peak > 0:
                peaks.append(float(peak))
    if not peaks:
        return None
    wanted = max(peaks) * MEMORY_MARGIN * _MB
    return int(min(wanted, cap_bytes) if cap_bytes else wanted)


def _token_for_workers(token: Path) -> str:
    """The path of the store-check token the workers are told to read (the same path: a shared store)."""
    return str(token)


def check_store_shared(store_root: Path, *, timeout_s: float = STORE_CHECK_TIMEOUT_S) -> int:
    """Refuse a store the Ray workers cannot see; returns how many nodes were checked.

    Writes a token file with random content into the store's ``tmp/``, runs
    :func:`_probe_store` on every alive node with CPUs (pinned to it) and compares what each read.

    Raises
    ------
    StoreNotSharedError
        A node does not see the store or the token, names the store path and what to do.
    """
    store = ArtifactStore(store_root)
    store.tmp_dir.mkdir(parents=True, exist_ok=True)
    content = secrets.token_hex(16)
    token = store.tmp_dir / f"ray-store-check.{os.getpid()}.{content[:8]}"
    token.write_text(content, encoding="utf-8")
    try:
        nodes = [n["NodeID"] for n in ray.nodes() if n.get("Alive") and n.get("Resources", {}).get("CPU")]
        probes = [
            _probe_store.options(
                scheduling_strategy=NodeAffinitySchedulingStrategy(node_id, soft=False)
            ).remote(str(store.root.resolve()), _token_for_workers(token))
            for node_id in nodes
        ] or [_probe_store.remote(str(store.root.resolve()), _token_for_workers(token))]
        answers = ray.get(probes, timeout=timeout_s)
    except ray.exceptions.RayError as exc:  # a node lost meanwhile, or no worker free in time
        raise StoreNotSharedError(
            f"could not check that the Ray workers see the artifact store {store.root}: {exc}"
        ) from None
    finally:
        token.unlink(missing_ok=True)
    for where, seen, problem in answers:
        if seen != content:
            problem = problem or "the token file the build wrote there has other content"
            raise StoreNotSharedError(
                f"the artifact store {store.root} is not visible to the Ray workers on node {where}: "
                f"{problem}. With --executor ray the store must be on a shared filesystem (NFS, etc.) "
                "mounted at the same path on every node."
            )
    return len(answers)


@dataclass(eq=False)
class _RayJob:
    task: StageTask
    future: Future[TaskResult]


class RayExecutor:
    """Runs stage tasks as Ray tasks, on this machine or on a cluster (see the module docstring).

    Parameters
    ----------
    address : str or None
        ``None``: start a Ray instance here with ``jobs`` CPUs (unless this process is already
        connected to one); ``"auto"``, ``host:port`` or ``ray://host:port``: connect to a cluster.
    jobs : int or None
        CPUs of a Ray instance started here (default: the cores); with a cluster, a cap on the
        tasks sent at once (default: the cluster's CPUs).
    max_retries : int
        Re-runs of a task whose worker or node died.
    """

    def __init__(
        self, address: str | None = None, jobs: int | None = None, *, max_retries: int = MAX_RETRIES
    ) -> None:
        self._started = False
        if not ray.is_initialized():
            if address is None:
                ray.init(
                    num_cpus=max(1, jobs or os.cpu_count() or 1),
                    include_dashboard=False,
                    log_to_driver=False,
                    configure_logging=False,
                )
            else:
                ray.init(address=address, log_to_driver=False, configure_logging=False)
            self._started = True
        cpus = max(1, int(ray.cluster_resources().get("CPU", 1)))
        self.jobs = max(1, jobs or cpus)
        self.progress: queue.Queue[tuple[str, int, int, str]] = queue.Queue()
        self.max_retries = max_retries
        self.fanout = FanOut("ray", cpus)
        self._env = worker_env()
        self._cwd = os.getcwd()
        self._memory_cap = max(
            (n["Resources"].get("memory", 0.0) for n in ray.nodes() if n.get("Alive")), default=0
        )
        self._mailbox = _Mailbox.remote()
        self._checked: set[str] = set()
        self._jobs: dict[Any, _RayJob] = {}
        self._started_pids: dict[str, list[int]] = {}
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._watcher = threading.Thread(target=self._watch, name="navverse-ray-executor", daemon=True)
        self._watcher.start()

    def submit(self, task: StageTask) -> Future[TaskResult]:
        """Send ``task`` to Ray (checking first, once per store, that the workers see the store)."""
        if task.store_root not in self._checked:
            check_store_shared(Path(task.store_root))
            self._checked.add(task.store_root)
        options: dict[str, Any] = {
            "num_cpus": 1,
            "max_retries": self.max_retries,
            "retry_exceptions": False,
            "runtime_env": {"env_vars": self._env},
            "name": f"navverse-stage {task.node_id}",
        }
        memory = memory_request(task, cap_bytes=self._memory_cap or None)
        if memory:
            options["memory"] = memory
        future: Future[TaskResult] = Future()
        future.set_running_or_notify_cancel()
        ref = _remote_stage.options(**options).remote(
            replace(task, fanout=self.fanout), self._mailbox, self._cwd
        )
        with self._lock:
            self._jobs[ref] = _RayJob(task, future)
        return future

    def abort(self) -> None:
        """End every running task by leaving Ray (see "Stopping" above); their futures raise
        :class:`WorkerDiedError`."""
        self._stop_watching()
        with self._lock:
            jobs, self._jobs = self._jobs, {}
        self._drain_mailbox()
        with contextlib.suppress(Exception):
            ray.shutdown()
        self._started = False
        for job in jobs.values():
            self._salvage(job, "interrupted: the build was stopped")
            if not job.future.done():
                job.future.set_exception(WorkerDiedError("interrupted"))

    def close(self) -> None:
        """Stop watching (aborting what still runs); shut Ray down if this executor started it."""
        with self._lock:
            busy = bool(self._jobs)
        if busy:
            self.abort()
        self._stop_watching()
        if not ray.is_initialized():  # abort left Ray (a call now would start a new one)
            return
        with contextlib.suppress(Exception):
            ray.kill(self._mailbox)
        if self._started:
            ray.shutdown()
        self._started = False

    # -- the watcher thread: drains progress, resolves futures as tasks end ----------------------
    def _stop_watching(self) -> None:
        self._stop.set()
        if self._watcher.is_alive() and threading.current_thread() is not self._watcher:
            self._watcher.join()

    def _watch(self) -> None:
        while not self._stop.is_set():
            self._drain_mailbox()
            with self._lock:
                refs = list(self._jobs)
            if not refs:
                self._stop.wait(0.05)
                continue
            ready, _ = ray.wait(refs, num_returns=len(refs), timeout=0.1, fetch_local=False)
            if ready:
                self._drain_mailbox()
            for ref in ready:
                self._finish(ref)

    def _drain_mailbox(self) -> None:
        try:
            items = ray.get(self._mailbox.drain.remote(), timeout=10)
        except Exception:  # Ray is shutting down: nothing more to show
            return
        for item in items:
            if item[0] == "progress":
                self.progress.put(item[1])
            elif item[0] == "started":
                self._started_pids.setdefault(item[1], []).append(item[2])

    def _finish(self, ref: Any) -> None:
        with self._lock:
            job = self._jobs.pop(ref, None)
        if job is None:  # aborted meanwhile
            return
        try:
            result = ray.get(ref)
        except ray.exceptions.TaskCancelledError:
            self._salvage(job, "interrupted: the task was cancelled")
            job.future.set_exception(WorkerDiedError("interrupted"))
            return
        except ray.exceptions.RayError as exc:
            reason = _death(exc, self.max_retries)
            self._salvage(job, f"the Ray worker {reason}")
            job.future.set_exception(WorkerDiedError(f"the Ray worker {reason}"))
            return
        job.future.set_result(result)

    def _salvage(self, job: _RayJob, note: str) -> None:
        """Publish the logs the task's dead workers left (one per attempt; the last one wins)."""
        for pid in self._started_pids.pop(job.task.node_id, []):
            salvage_log(job.task, pid, note)


def _death(exc: BaseException, retries: int) -> str:
    """How a Ray task that returned no result ended, in words."""
    first = (str(exc).strip().splitlines() or [type(exc).__name__])[0]
    if isinstance(exc, ray.exceptions.RayTaskError):
        return f"raised {first}"
    cause = f"{type(exc).__name__}: killed, out of memory, or its node was lost; {retries} retries"
    return f"died ({cause}): {first}"
