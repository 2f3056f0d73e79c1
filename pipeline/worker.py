"""Runs one stage task where an executor puts it (this process or another) and commits its outputs."""

from __future__ import annotations

import logging
import resource
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from pipeline.context import StageContext
from pipeline.hashing import hash_tree
from pipeline.seeds import make_rng
from pipeline.stage import import_stage
from pipeline.store import MANIFEST_NAME, ArtifactStore

LOG_NAME = "stage.log"


@dataclass(frozen=True)
class TaskOutput:
    """Where one output of a task goes."""

    name: str
    key: str
    final: str


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


def _peak_rss_mb() -> float:
    # ru_maxrss is in KiB on Linux; with one process per task it is the task's own peak.
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def _logger(task: StageTask, path: Path) -> tuple[logging.Logger, logging.Handler]:
    path.parent.mkdir(parents=True, exist_ok=True)
    logger = logging.getLogger(f"pipeline.stage.{task.node_id}")
    logger.setLevel(logging.INFO)
    logger.propagate = False
    handler = logging.FileHandler(path, mode="w", encoding="utf-8")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    logger.addHandler(handler)
    return logger, handler


def run_task(task: StageTask, progress: Any = None) -> TaskResult:
    """Run ``task``; on success its outputs are committed to the store.

    Parameters
    ----------
    task : StageTask
        What to run.
    progress : queue-like, optional
        Receives ``(node_id, done, total, description)`` tuples from ``ctx.progress``.

    Returns
    -------
    TaskResult
        Never raises for a failing stage: the error and the log path are in the result.
    """
    store = ArtifactStore(Path(task.store_root))
    log_path = store.log_path(task.target, task.stage)
    logger, handler = _logger(task, log_path)
    started, cpu_started = time.perf_counter(), time.process_time()
    tmp_dirs: dict[str, Path] = {}
    try:
        spec = import_stage(task.module, task.stage)
        params = spec.params_model.model_validate(task.params)
        tmp_dirs = {out.name: store.new_tmp(task.stage, out.name, out.key) for out in task.outputs}
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
        )
        logger.info("stage %s for %s (key %s, seed %d)", task.stage, task.target, task.node_key, task.seed)
        spec.fn(ctx, params)
        wall = time.perf_counter() - started
        cpu = time.process_time() - cpu_started
        peak = _peak_rss_mb()
        logger.info("done in %.2f s wall, %.2f s cpu, peak %.0f MB", wall, cpu, peak)
        handler.flush()
        for out in task.outputs:
            tmp = tmp_dirs[out.name]
            (tmp / LOG_NAME).write_bytes(log_path.read_bytes())
            files = hash_tree(tmp, exclude=frozenset({LOG_NAME, MANIFEST_NAME}))
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
                "files": files,
                "stats": ctx.stats,
                "run": {"wall_s": round(wall, 4), "cpu_s": round(cpu, 4), "peak_rss_mb": round(peak, 1)},
            }
            store.commit(tmp, Path(out.final), manifest)
        return TaskResult(
            node_id=task.node_id,
            ok=True,
            log_path=str(log_path),
            wall_s=wall,
            cpu_s=cpu,
            peak_rss_mb=peak,
            stats=dict(ctx.stats),
        )
    except BaseException as exc:  # a failing stage must not take the build down
        logger.error("failed:\n%s", traceback.format_exc())
        for tmp in tmp_dirs.values():
            _remove(tmp)
        if isinstance(exc, KeyboardInterrupt):
            raise
        message = str(exc).strip() or type(exc).__name__
        return TaskResult(
            node_id=task.node_id,
            ok=False,
            error=f"{type(exc).__name__}: {message}",
            log_path=str(log_path),
            wall_s=time.perf_counter() - started,
        )
    finally:
        logger.removeHandler(handler)
        handler.close()


def _remove(path: Path) -> None:
    import shutil

    shutil.rmtree(path, ignore_errors=True)
