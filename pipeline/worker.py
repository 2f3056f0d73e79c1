"""Runs one stage task where an executor puts it (this process or another) and commits its outputs.

A task's log is written by one process only: the worker writes it to a file of its own in
``tmp/`` (``log-<target>-<stage>.<pid>.log``, where a running stage's log can be followed) and moves
it to ``logs/<target>/<stage>.log`` in one step when the stage ends, after copying it into each
output as ``stage.log``. Writing it never prints a "Logging error" (a full disk included): the
error is kept and the stage fails with one line saying what to do.
"""

from __future__ import annotations

import contextlib
import errno
import logging
import os
import resource
import shutil
import signal
import sys
import threading
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pipeline.context import FanOut, StageContext
from pipeline.hashing import hash_tree
from pipeline.processes import die_with_parent
from pipeline.seeds import make_rng
from pipeline.stage import import_stage
from pipeline.store import LOG_NAME, MANIFEST_NAME, ArtifactStore

__all__ = ["LOG_NAME", "StageTask", "TaskOutput", "TaskResult", "child_main", "run_task", "salvage_log"]

_NO_SPACE = (errno.ENOSPC, errno.EDQUOT)


@dataclass(frozen=True)
class TaskOutput:
    """Where one output of a task goes."""

    name: str
    key: str
    final: str
    replace: bool = False
    """Replace a committed artifact at ``final`` (forced, or found corrupt) instead of keeping it."""


@dataclass(frozen=True)
class StageTask:
    """Everything needed to run a stage for a target, as plain picklable data.

    Attributes
    ----------
    node_id, target, stage, module : str
        Identity; ``module`` is imported to find the stage.
    recipe, recipe_hash : str
        Provenance of the target.
    seed : int
        Derived seed.
    node_key : str
        Cache key of the run.
    params : dict
        The params as JSON data (re-validated in the worker).
    inputs : dict
        ``{name: [artifact paths]}``; ``many`` says which are lists.
    input_keys : dict
        ``{name: [artifact keys]}`` (for the manifest).
    outputs : tuple of TaskOutput
        Outputs to commit.
    store_root : str
        The build directory.
    code_version : str
        Stage code version (for the manifest).
    fanout : FanOut
        Where the stage's ``ctx.map`` runs; the executor sets it when it starts the task (not part
        of the cache key: results do not depend on it).
    """

    node_id: str
    target: str
    stage: str
    module: str
    recipe: str
    recipe_hash: str
    seed: int
    node_key: str
    params: dict[str, Any]
    inputs: dict[str, list[str]]
    many: dict[str, bool]
    input_keys: dict[str, list[str]]
    outputs: tuple[TaskOutput, ...]
    store_root: str
    code_version: str
    fanout: FanOut = field(default_factory=FanOut)


@dataclass
class TaskResult:
    """Outcome of a task."""

    node_id: str
    ok: bool
    error: str = ""
    log_path: str = ""
    wall_s: float = 0.0
    cpu_s: float = 0.0
    peak_rss_mb: float = 0.0
    stats: dict[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)
    """What the stage logged at WARNING level (at most :data:`MAX_WARNINGS`; the log has them all)."""


MAX_WARNINGS = 20
"""Warnings of one task kept in its :class:`TaskResult` (for the build summary)."""


class _WarningCollector(logging.Handler):
    """Keeps the messages a stage logs at WARNING level or above, so the build summary can show them."""

    def __init__(self) -> None:
        super().__init__(level=logging.WARNING)
        self.messages: list[str] = []
        self.dropped = 0

    def emit(self, record: logging.LogRecord) -> None:
        """Keep the record's message (up to :data:`MAX_WARNINGS`)."""
        if len(self.messages) < MAX_WARNINGS:
            try:
                self.messages.append(record.getMessage())
            except Exception:  # a malformed log call must not fail the stage
                self.messages.append(str(record.msg))
        else:
            self.dropped += 1

    def kept(self) -> list[str]:
        """The messages, with a last line counting those left out."""
        more = [f"... and {self.dropped} more warnings (in the log)"] if self.dropped else []
        return [*self.messages, *more]


def _peak_rss_mb() -> float:
    # ru_maxrss is in KiB on Linux; with one process per task it is the task's own peak.
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


class QuietFileHandler(logging.FileHandler):
    """A file handler that keeps its first write error instead of printing a traceback.

    Attributes
    ----------
    error : OSError or None
        The first error met while writing (e.g. ``ENOSPC`` on a full disk).
    """

    error: BaseException | None = None

    def handleError(self, record: logging.LogRecord) -> None:  # noqa: N802 (logging's name)
        """Remember the error; print nothing."""
        self._keep(sys.exc_info()[1])

    def flush(self) -> None:
        """Flush, keeping a write error instead of raising it."""
        try:
            super().flush()
        except OSError as exc:
            self._keep(exc)

    def close(self) -> None:
        """Close, keeping a write error (of the last buffered lines) instead of raising it."""
        try:
            super().close()
        except OSError as exc:
            self._keep(exc)

    def _keep(self, exc: BaseException | None) -> None:
        if self.error is None:
            self.error = exc


def running_log_path(store: ArtifactStore, target: str, stage: str, pid: int) -> Path:
    """Where the worker ``pid`` writes the log of ``stage`` for ``target`` while it runs."""
    return store.tmp_dir / f"log-{target}-{stage}.{pid}.log"


class _StageLog:
    """The log of one task: written to a file of this process, published whole at the end."""

    def __init__(self, store: ArtifactStore, task: StageTask) -> None:
        self.path = running_log_path(store, task.target, task.stage, os.getpid())
        self.final = store.log_path(task.target, task.stage)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.logger = logging.getLogger(f"pipeline.stage.{task.node_id}")
        self.logger.setLevel(logging.INFO)
        self.logger.propagate = False
        self.handler = QuietFileHandler(self.path, mode="w", encoding="utf-8")
        self.handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
        self.logger.addHandler(self.handler)
        self.warnings = _WarningCollector()
        self.logger.addHandler(self.warnings)

    def read_bytes(self) -> bytes:
        """What was logged so far (flushed first); raises the handler's write error if it had one."""
        self.handler.flush()
        if isinstance(self.handler.error, OSError):
            raise self.handler.error
        return self.path.read_bytes()

    def publish(self) -> None:
        """Close the log and move it to ``logs/<target>/<stage>.log`` (never raises)."""
        self.logger.removeHandler(self.handler)
        self.logger.removeHandler(self.warnings)
        self.handler.close()
        _publish(self.path, self.final)


def _publish(running: Path, final: Path) -> None:
    try:
        final.parent.mkdir(parents=True, exist_ok=True)
        os.replace(running, final)
    except OSError:
        running.unlink(missing_ok=True)


def salvage_log(task: StageTask, pid: int, note: str) -> None:
    """Publish the log the dead worker ``pid`` left for ``task``, ending with ``note`` (never raises).

    Called by an executor when a worker ended without a result (killed, out of memory, interrupted).
    """
    store = ArtifactStore(Path(task.store_root))
    running = running_log_path(store, task.target, task.stage, pid)
    if not running.is_file():
        return
    try:
        with open(running, "a", encoding="utf-8") as handle:
            handle.write(f"{time.strftime('%Y-%m-%d %H:%M:%S')} ERROR {note}\n")
    except OSError:
        pass
    _publish(running, store.log_path(task.target, task.stage))


def describe_error(exc: BaseException, *, writing: Path) -> str:
    """One line for a failed stage: a full disk says so and what to do, anything else its type and text.

    Parameters
    ----------
    exc : BaseException
        What the stage (or the commit of its outputs) raised.
    writing : Path
        Named as the place written when the error does not name a file.
    """
    full = _no_space(exc)
    if full is not None:
        where = full.filename or writing
        return f"no space left on device while writing {where}; free space and run the same command to resume"
    message = str(exc).strip() or type(exc).__name__
    return f"{type(exc).__name__}: {message}"


def _no_space(exc: BaseException | None) -> OSError | None:
    """The ``ENOSPC``/``EDQUOT`` error in ``exc``'s chain of causes, if any."""
    seen = 0
    while exc is not None and seen < 20:
        if isinstance(exc, OSError) and exc.errno in _NO_SPACE:
            return exc
        exc = exc.__cause__ or exc.__context__
        seen += 1
    return None


def run_task(task: StageTask, progress: Any = None) -> TaskResult:
    """Run ``task``; on success its outputs are committed to the store.

    Parameters
    ----------
    task : StageTask
        What to run.
    progress : queue-like, optional
        Receives ``(node_id, done, total, description)`` tuples from ``ctx.progress`` (``put``).

    Returns
    -------
    TaskResult
        Never raises for a failing stage: the error (one line) and the log path are in the result.
        ``KeyboardInterrupt`` is raised again once the log is published.
    """
    store = ArtifactStore(Path(task.store_root))
    log_path = store.log_path(task.target, task.stage)
    started, cpu_started = time.perf_counter(), _cpu_seconds()
    tmp_dirs: dict[str, Path] = {}
    log: _StageLog | None = None
    try:
        log = _StageLog(store, task)
        ctx = _run_stage(task, store, log.logger, tmp_dirs, progress)
        wall = time.perf_counter() - started
        cpu = _cpu_seconds() - cpu_started
        peak = _peak_rss_mb()
        log.logger.info("done in %.2f s wall, %.2f s cpu, peak %.0f MB", wall, cpu, peak)
        _commit_outputs(
            task, store, tmp_dirs, log, ctx, run={"wall_s": wall, "cpu_s": cpu, "peak_rss_mb": peak}
        )
        shutil.rmtree(store.checkpoint_dir(task.node_key), ignore_errors=True)  # committed: not needed
        return TaskResult(
            node_id=task.node_id,
            ok=True,
            log_path=str(log_path),
            wall_s=wall,
            cpu_s=cpu,
            peak_rss_mb=peak,
            stats=dict(ctx.stats),
            warnings=log.warnings.kept(),
        )
    except BaseException as exc:  # a failing stage must not take the build down
        if log is not None:
            log.logger.error("failed:\n%s", traceback.format_exc())
        for tmp in tmp_dirs.values():
            shutil.rmtree(tmp, ignore_errors=True)
        if isinstance(exc, KeyboardInterrupt):
            raise
        return TaskResult(
            node_id=task.node_id,
            ok=False,
            error=describe_error(exc, writing=store.root),
            log_path=str(log_path),
            wall_s=time.perf_counter() - started,
        )
    finally:
        if log is not None:
            log.publish()


def _run_stage(
    task: StageTask,
    store: ArtifactStore,
    logger: logging.Logger,
    tmp_dirs: dict[str, Path],
    progress: Any,
) -> StageContext:
    """Import and call the stage function with fresh output directories (filled into ``tmp_dirs``)."""
    spec = import_stage(task.module, task.stage)
    params = spec.params_model.model_validate(task.params)
    for out in task.outputs:
        tmp_dirs[out.name] = store.new_tmp(task.stage, out.name, out.key)
    inputs: dict[str, Path | list[Path]] = {
        name: [Path(p) for p in paths] if task.many.get(name) else Path(paths[0])
        for name, paths in task.inputs.items()
    }

    def sink(done: int, total: int, description: str) -> None:
        if progress is not None:
            progress.put((task.node_id, done, total, description))

    ctx = StageContext(
        target=task.target,
        stage=task.stage,
        recipe=task.recipe,
        recipe_hash=task.recipe_hash,
        seed=task.seed,
        rng=make_rng(task.seed),
        inputs=inputs,
        outputs=dict(tmp_dirs),
        log=logger,
        progress_sink=sink,
        fanout=task.fanout,
        checkpoints=store.checkpoint_dir(task.node_key),
    )
    logger.info("stage %s for %s (key %s, seed %d)", task.stage, task.target, task.node_key, task.seed)
    spec.fn(ctx, params)
    return ctx


def _commit_outputs(
    task: StageTask,
    store: ArtifactStore,
    tmp_dirs: dict[str, Path],
    log: _StageLog,
    ctx: StageContext,
    *,
    run: dict[str, float],
) -> None:
    """Copy the log into each output, write its manifest and commit it."""
    text = log.read_bytes()
    for out in task.outputs:
        tmp = tmp_dirs[out.name]
        (tmp / LOG_NAME).write_bytes(text)
        manifest = {
            "key": out.key,
            "node_key": task.node_key,
            "stage": task.stage,
            "output": out.name,
            "target": task.target,
            "recipe": task.recipe,
            "recipe_hash": task.recipe_hash,
            "seed": task.seed,
            "code_version": task.code_version,
            "params": task.params,
            "inputs": task.input_keys,
            "files": hash_tree(tmp, exclude=frozenset({LOG_NAME, MANIFEST_NAME})),
            "stats": ctx.stats,
            "run": {
                "wall_s": round(run["wall_s"], 4),
                "cpu_s": round(run["cpu_s"], 4),
                "peak_rss_mb": round(run["peak_rss_mb"], 1),
            },
        }
        store.commit(tmp, Path(out.final), manifest, replace=out.replace)


def _cpu_seconds() -> float:
    """CPU seconds of this process and of the child processes it has waited for (a stage's process
    pools), user and system."""
    times = os.times()
    return time.process_time() + times.children_user + times.children_system


# -- running in a worker process ---------------------------------------------------------------
_PR_SET_PDEATHSIG = 1


class _PipeProgress:
    """Queue-like progress channel over the worker's pipe (``put``), safe to use from threads."""

    def __init__(self, send: Any) -> None:
        self._send = send

    def put(self, item: tuple[str, int, int, str]) -> None:
        self._send(("progress", item))


def child_main(task: StageTask, conn: Any, parent_pid: int) -> None:
    """Entry point of a worker process: run ``task``, send its progress and result over ``conn``.

    The worker ignores SIGINT (a Ctrl-C reaches the whole process group: the parent ends the
    workers), dies with the parent (``PR_SET_PDEATHSIG`` on Linux, else a watchdog thread), and
    never prints logging tracebacks.

    Parameters
    ----------
    task : StageTask
        What to run.
    conn : multiprocessing.connection.Connection
        Write end of a pipe to the parent: ``("progress", tuple)`` messages, then ``("result", TaskResult)``.
    parent_pid : int
        The process that started this one; when it is gone, this one ends.
    """
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})  # the parent blocked it for the start
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    die_with_parent(parent_pid)
    logging.raiseExceptions = False
    lock = threading.Lock()

    def send(message: tuple[str, Any]) -> None:
        with lock, contextlib.suppress(OSError):  # the parent is gone: nothing to tell
            conn.send(message)

    send(("result", run_task(task, _PipeProgress(send))))
    conn.close()
