"""What a stage function receives besides its params, and fan-out inside a stage (``ctx.map``).

Fan-out inside a stage
----------------------
``ctx.map(fn, items)`` applies ``fn`` to every item and returns the results in item order, running on
the executor the build uses: a process pool next to the stage's worker locally (spawned processes
that end with the worker, the stage's share of the cores: ``cores // --jobs``), Ray tasks when
the build runs on Ray (``--executor ray``: the items spread over the cluster), and in the stage's
own process when its share is one core, when the items make one chunk, or when the build runs
in-process (``--jobs 0``). ``fn`` must be a module-level function (it is pickled by reference, on every
executor, so a lambda fails the same way everywhere) and items and results must pickle.

Items are cut into chunks of ``chunksize`` consecutive items (default: about four chunks per
worker); a chunk is one pool job or one Ray task. Results do not depend on the executor or the
number of workers: each item's result is ``fn(item)`` alone, so ``fn`` must draw no randomness of
its own — give each item its seed (e.g. ``ctx.rng.integers(2**63, size=len(items))``, drawn before
the call). If ``fn`` raises, the stage fails with :class:`MapError` naming the lowest failing
item's index (``ctx.map: fn raised on item 17 of 50: ValueError: ...``), the same index whatever
ran it: earlier chunks are waited for, later ones are dropped (cancelled in a local pool; left to end
on Ray, whose cancellation can abort the calling process). Progress is reported per chunk.

Resuming a killed stage
-----------------------
Each item's result is saved as it is made (``checkpoints/<stage run key>/map-<n>/<item digest>.pkl``
in the build store, written atomically; ``n`` counts the stage run's ``ctx.map`` calls), and a run of
the same key (same code, params, inputs and seed) takes a saved result instead of calling ``fn``
again: a stage of hours killed part way loses only the items in flight. Since ``fn`` draws no
randomness of its own, the result is the one ``fn`` would make. The worker removes the checkpoints
once the stage's outputs are committed.
"""

from __future__ import annotations

import concurrent.futures as cf
import hashlib
import logging
import math
import multiprocessing
import os
import pickle
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np

from pipeline.processes import end_with_parent

ProgressSink = Callable[[int, int, str], None]

FanOutKind = Literal["inline", "processes", "ray"]

CHUNKS_PER_WORKER = 4
"""Default number of chunks per worker of ``ctx.map`` (small enough to balance, few enough to be cheap)."""


@dataclass(frozen=True)
class FanOut:
    """Where ``ctx.map`` runs; set by the executor on each task it starts.

    Attributes
    ----------
    kind : {"inline", "processes", "ray"}
        In the stage's process, in a local process pool, or as Ray tasks.
    workers : int
        Pool processes (``processes``), or the cluster's CPUs (``ray``: used to size the chunks).
        The executor picks ``inline`` rather than a pool of one.
    """

    kind: FanOutKind = "inline"
    workers: int = 1


class MapError(RuntimeError):
    """``fn`` raised on an item of ``ctx.map``; the message names the item's index.

    Attributes
    ----------
    index : int
        The failing item's index.
    """

    def __init__(self, message: str, index: int) -> None:
        super().__init__(message, index)
        self.index = index

    def __str__(self) -> str:
        return str(self.args[0])


def apply_chunk(fn: Callable[[Any], Any], start: int, total: int, chunk: Sequence[Any]) -> list[Any]:
    """``[fn(item) for item in chunk]``; an exception becomes a :class:`MapError` naming the item's index.

    Parameters
    ----------
    fn : callable
        The mapped function.
    start : int
        Index of the chunk's first item among all items.
    total : int
        How many items the whole map has (for the message).
    chunk : sequence
        The items.
    """
    results = []
    for offset, item in enumerate(chunk):
        try:
            results.append(fn(item))
        except Exception as exc:
            name = getattr(fn, "__qualname__", repr(fn))
            text = str(exc).strip() or type(exc).__name__
            index = start + offset
            message = f"ctx.map: {name} raised on item {index} of {total}: {type(exc).__name__}: {text}"
            raise MapError(message, index) from exc
    return results


def chunk_bounds(count: int, workers: int, chunksize: int | None = None) -> list[tuple[int, int]]:
    """``[(start, stop), ...]``: chunks of ``count`` items (default: :data:`CHUNKS_PER_WORKER` per worker)."""
    if chunksize is None:
        chunksize = max(1, math.ceil(count / (max(1, workers) * CHUNKS_PER_WORKER)))
    if chunksize < 1:
        raise ValueError(f"ctx.map: chunksize must be at least 1, not {chunksize}")
    return [(start, min(start + chunksize, count)) for start in range(0, count, chunksize)]


def run_map(
    fn: Callable[[Any], Any],
    items: Iterable[Any],
    *,
    fanout: FanOut,
    chunksize: int | None = None,
    progress: ProgressSink | None = None,
    checkpoints: Path | None = None,
) -> list[Any]:
    """Apply ``fn`` to every item where ``fanout`` says; the engine of :meth:`StageContext.map`.

    Parameters
    ----------
    fn : callable
        A module-level function of one item.
    items : iterable
        The items (materialised into a list).
    fanout : FanOut
        Where to run.
    chunksize : int, optional
        Items per chunk.
    progress : callable, optional
        Called with ``(done items, total, description)`` after each chunk.
    checkpoints : Path, optional
        A directory where each item's result is saved as it is made, and taken from on a later call
        (see "Resuming a killed stage" above).

    Returns
    -------
    list
        ``[fn(item) for item in items]``.

    Raises
    ------
    MapError
        ``fn`` raised on an item (the lowest failing index).
    TypeError
        ``fn`` cannot be pickled by reference (a lambda or a nested function).
    """
    values = list(items)
    _check_picklable(fn)
    description = f"map {getattr(fn, '__name__', 'fn')}"
    if checkpoints is not None:
        fn = _Saving(fn, checkpoints)
    bounds = chunk_bounds(len(values), fanout.workers, chunksize)
    chunks = [(start, values[start:stop]) for start, stop in bounds]

    def report(done: int) -> None:
        if progress is not None:
            progress(done, len(values), description)

    if fanout.kind == "inline" or len(chunks) <= 1:
        return _map_inline(fn, chunks, len(values), report)
    if fanout.kind == "ray":
        from pipeline.ray_executor import ray_map  # only a build on Ray gets here

        return ray_map(fn, chunks, len(values), report)
    return _map_processes(fn, chunks, len(values), report, workers=fanout.workers)


class _Saving:
    """``fn`` whose result for an item is taken from ``checkpoints`` when an earlier run saved it, else
    made and saved there (atomically); it pickles by reference to ``fn``, as ``fn`` does."""

    def __init__(self, fn: Callable[[Any], Any], checkpoints: Path) -> None:
        self.fn = fn
        self.checkpoints = checkpoints
        self.__qualname__ = getattr(fn, "__qualname__", repr(fn))  # what a MapError names

    def __call__(self, item: Any) -> Any:
        name = f"{getattr(self.fn, '__module__', '')}.{self.__qualname__}"
        digest = hashlib.sha256(pickle.dumps((name, item), protocol=5)).hexdigest()[:32]
        path = self.checkpoints / f"{digest}.pkl"
        try:
            return pickle.loads(path.read_bytes())
        except FileNotFoundError:
            pass
        except Exception:  # a file a crash left unreadable: make the result again
            path.unlink(missing_ok=True)
        result = self.fn(item)
        self.checkpoints.mkdir(parents=True, exist_ok=True)
        partial = path.with_name(f".{path.name}.{os.getpid()}.partial")
        partial.write_bytes(pickle.dumps(result, protocol=5))
        os.replace(partial, path)
        return result


def _check_picklable(fn: Callable[[Any], Any]) -> None:
    try:
        pickle.dumps(fn)
    except Exception as exc:
        raise TypeError(
            f"ctx.map needs a module-level function (pickled by reference), not {fn!r}: {exc}"
        ) from None


def _map_inline(
    fn: Callable[[Any], Any], chunks: list[tuple[int, list[Any]]], total: int, report: Callable[[int], None]
) -> list[Any]:
    results: list[Any] = []
    for start, chunk in chunks:
        results += apply_chunk(fn, start, total, chunk)
        report(len(results))
    return results


def _map_processes(
    fn: Callable[[Any], Any],
    chunks: list[tuple[int, list[Any]]],
    total: int,
    report: Callable[[int], None],
    *,
    workers: int,
) -> list[Any]:
    """The chunks on a pool of spawned processes that end with this one; results collected in order."""
    context = multiprocessing.get_context("spawn")
    pool = cf.ProcessPoolExecutor(
        max_workers=min(workers, len(chunks)), mp_context=context, initializer=end_with_parent
    )
    try:
        futures = [pool.submit(apply_chunk, fn, start, total, chunk) for start, chunk in chunks]
        results: list[Any] = []
        for future in futures:
            try:
                results += future.result()
            except MapError:
                for later in futures:
                    later.cancel()
                raise
            report(len(results))
        return results
    finally:
        pool.shutdown(wait=True, cancel_futures=True)


# -- pool processes end with the stage's worker ---------------------------------------------------


@dataclass
class StageContext:
    """The run of one stage for one target.

    A stage reads only :attr:`inputs`, writes only into :attr:`outputs`, and draws randomness only
    from :attr:`rng`.

    Attributes
    ----------
    target : str
        Target id.
    stage : str
        Stage name.
    recipe : str
        Recipe path (relative to the recipes folder).
    recipe_hash : str
        Hash of the target's recipe.
    seed : int
        The derived seed of this stage run.
    rng : numpy.random.Generator
        Seeded from :attr:`seed`.
    inputs : dict
        ``{name: Path}`` (or ``list[Path]`` for many-inputs) of committed input artifacts.
    outputs : dict
        ``{name: Path}`` empty directories to write into.
    log : logging.Logger
        Writes to the stage's log file.
    fanout : FanOut
        Where :meth:`map` runs (set by the executor).
    checkpoints : Path or None
        Where :meth:`map` saves each item's result for a killed run to resume from (set by the
        worker: the store's checkpoint directory of this stage run); None saves nothing.
    """

    target: str
    stage: str
    recipe: str
    recipe_hash: str
    seed: int
    rng: np.random.Generator
    inputs: dict[str, Path | list[Path]]
    outputs: dict[str, Path]
    log: logging.Logger
    stats: dict[str, Any] = field(default_factory=dict)
    progress_sink: ProgressSink | None = None
    fanout: FanOut = FanOut()
    checkpoints: Path | None = None
    _maps: int = field(default=0, repr=False)

    @property
    def output(self) -> Path:
        """The output directory of a stage with exactly one output."""
        if len(self.outputs) != 1:
            raise RuntimeError(f"stage {self.stage} has {len(self.outputs)} outputs; use ctx.outputs[name]")
        return next(iter(self.outputs.values()))

    def input(self, name: str) -> Path:
        """The directory of the single input artifact ``name``."""
        value = self.inputs[name]
        if isinstance(value, list):
            raise RuntimeError(f"input {name!r} of stage {self.stage} is a list; use ctx.inputs[name]")
        return value

    def record(self, **stats: Any) -> None:
        """Record counts or figures (JSON-able) in the artifact manifests under ``stats``."""
        self.stats.update(stats)

    def progress(self, done: int, total: int, description: str = "") -> None:
        """Report inner progress (shown as a bar while the stage runs)."""
        if self.progress_sink is not None:
            self.progress_sink(done, total, description)

    def map(
        self, fn: Callable[[Any], Any], items: Iterable[Any], *, chunksize: int | None = None
    ) -> list[Any]:
        """``[fn(item) for item in items]``, fanned out on the executor in use (see the module docstring).

        Parameters
        ----------
        fn : callable
            A module-level function of one item; it must draw no randomness of its own.
        items : iterable
            The items; they and the results must pickle.
        chunksize : int, optional
            Items per chunk (one pool job or Ray task); default about four chunks per worker.

        Returns
        -------
        list
            The results, in item order; the same whatever executor and number of workers.

        Raises
        ------
        MapError
            ``fn`` raised; the message names the (lowest) failing item's index.
        """
        saved = None
        if self.checkpoints is not None:
            self._maps += 1
            saved = self.checkpoints / f"map-{self._maps}"
        return run_map(
            fn, items, fanout=self.fanout, chunksize=chunksize, progress=self.progress, checkpoints=saved
        )
