"""Plans and runs builds: cache look-ups (with a check of what is reused), scheduling on an
executor, progress, interruption, and the summary.

A build reuses a committed artifact only if it is intact: every build checks the sizes of the files
of the artifacts it would reuse (a ``stat`` each), ``verify="hash"`` their sha256 too. A corrupt
artifact is reported (``corrupt: <artifact>/<file> size differs ...; rebuilding <node>``) and
rebuilt, the new directory replacing the old one atomically.

Interrupted (Ctrl-C, or SIGTERM under :func:`sigterm_interrupts`), a build stops its workers, keeps
what was committed, and raises :class:`BuildInterrupted` saying how many stage runs are left: the
same command resumes.
"""

from __future__ import annotations

import concurrent.futures as cf
import contextlib
import signal
import threading
import time
from collections import Counter
from collections.abc import Callable, Collection, Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from types import FrameType
from typing import Literal

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table
from rich.text import Text

from pipeline.dag import ArtifactRef, Graph, Node
from pipeline.executors import Executor
from pipeline.store import ArtifactStore, Corruption, VerifyLevel
from pipeline.summary import describe_stats
from pipeline.worker import StageTask, TaskOutput, TaskResult

NodeState = Literal["cached", "build"]
TargetStatus = Literal["fresh", "stale", "missing", "corrupt"]


class Terminated(KeyboardInterrupt):
    """Raised in the main thread by the SIGTERM handler of :func:`sigterm_interrupts`."""

    signum = signal.SIGTERM


class BuildInterrupted(KeyboardInterrupt):
    """A build stopped by Ctrl-C or SIGTERM after its workers were ended.

    Attributes
    ----------
    unfinished : int
        Stage runs not finished (running or waiting); the same command resumes them.
    signum : int
        ``SIGINT`` (Ctrl-C) or ``SIGTERM``.
    """

    def __init__(self, unfinished: int, signum: int) -> None:
        super().__init__(
            f"interrupted; {unfinished} stage{'s' if unfinished != 1 else ''} left unfinished, "
            "run the same command to resume"
        )
        self.unfinished = unfinished
        self.signum = signum


@contextlib.contextmanager
def sigterm_interrupts() -> Iterator[None]:
    """Within the block, SIGTERM raises :class:`Terminated` (a ``KeyboardInterrupt``) like Ctrl-C does.

    Only in the main thread; elsewhere the block runs unchanged.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def raise_terminated(signum: int, frame: FrameType | None) -> None:
        raise Terminated()

    previous = signal.signal(signal.SIGTERM, raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


@contextlib.contextmanager
def _signals_held() -> Iterator[None]:
    """Ignore SIGINT and SIGTERM while workers are being stopped (a second Ctrl-C changes nothing)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {s: signal.signal(s, signal.SIG_IGN) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


@dataclass
class BuildReport:
    """What a build did.

    Attributes
    ----------
    cached : list of str
        Node ids whose artifacts were already committed.
    built : dict
        ``{node_id: TaskResult}`` of nodes run successfully.
    failed : dict
        ``{node_id: TaskResult}`` of nodes that failed.
    skipped : dict
        ``{node_id: reason}`` of nodes not run because an input failed.
    """

    cached: list[str] = field(default_factory=list)
    built: dict[str, TaskResult] = field(default_factory=dict)
    failed: dict[str, TaskResult] = field(default_factory=dict)
    skipped: dict[str, str] = field(default_factory=dict)
    seconds: float = 0.0

    @property
    def ok(self) -> bool:
        """True if nothing failed or was skipped."""
        return not self.failed and not self.skipped


def find_corrupt(
    graph: Graph, store: ArtifactStore, *, level: VerifyLevel = "size", skip: Collection[str] = ()
) -> dict[str, list[Corruption]]:
    """Check the committed artifacts of ``graph`` against their manifests.

    Parameters
    ----------
    graph : Graph
        Whose nodes' artifacts to check.
    store : ArtifactStore
        Where they are.
    level : {"size", "hash"}
        ``size``: a ``stat`` per file (and a listing, for files the manifest lacks); ``hash``: the
        sha256 of every file too.
    skip : collection of str
        Node ids not to check (e.g. forced ones: rebuilt anyway).

    Returns
    -------
    dict
        ``{node_id: [Corruption, ...]}`` of the nodes with a corrupt artifact, in graph order.
    """
    found: dict[str, list[Corruption]] = {}
    for node_id in graph.order:
        if node_id in skip:
            continue
        node = graph.nodes[node_id]
        problems = [
            problem
            for out, key in node.artifact_keys.items()
            if store.has(node.stage, out, key)
            for problem in store.verify(store.artifact_path(node.stage, out, key), level=level)
        ]
        if problems:
            found[node_id] = problems
    return found


def plan(
    graph: Graph, store: ArtifactStore, *, force: Sequence[str] = (), corrupt: Collection[str] = ()
) -> dict[str, NodeState]:
    """``{node_id: "cached" | "build"}`` in graph order.

    ``force`` names targets to rebuild; ``corrupt`` node ids (see :func:`find_corrupt`) are rebuilt.
    """
    forced = set(force)
    states: dict[str, NodeState] = {}
    for node_id in graph.order:
        node = graph.nodes[node_id]
        have = all(store.has(node.stage, out, key) for out, key in node.artifact_keys.items())
        reuse = have and node.target.id not in forced and node_id not in corrupt
        states[node_id] = "cached" if reuse else "build"
    return states


def target_status(
    graph: Graph, store: ArtifactStore, *, corrupt: Collection[str] = ()
) -> dict[str, TargetStatus]:
    """Per target: ``fresh`` (every artifact current), ``stale`` (built before, out of date),
    ``missing``, or ``corrupt`` (a current artifact differs from its manifest: ``corrupt`` node ids)."""
    result: dict[str, TargetStatus] = {}
    by_target: dict[str, list[Node]] = {}
    for node in graph.nodes.values():
        by_target.setdefault(node.target.id, []).append(node)
    for target_id, nodes in sorted(by_target.items()):
        current = all(store.has(n.stage, out, key) for n in nodes for out, key in n.artifact_keys.items())
        built_before = any(
            store.target_output(target_id, out) is not None for n in nodes for out in n.artifact_keys
        )
        if any(n.id in corrupt for n in nodes):
            result[target_id] = "corrupt"
        else:
            result[target_id] = "fresh" if current else ("stale" if built_before else "missing")
    return result


def print_corrupt(
    corrupt: Mapping[str, list[Corruption]], store: ArtifactStore, console: Console, *, action: str = ""
) -> None:
    """One line per corrupt node: ``corrupt: <artifact>/<file> <problem>[; <action> <node>]``."""
    for node_id, problems in corrupt.items():
        first = problems[0].describe(store.root)
        more = f" (and {len(problems) - 1} more)" if len(problems) > 1 else ""
        tail = f"; {action} {node_id}" if action else f" ({node_id})"
        console.print(f"[red]corrupt[/]: {first}{more}{tail}", highlight=False, soft_wrap=True)


def describe_plan(graph: Graph, states: dict[str, NodeState], console: Console) -> None:
    """Print the graph: every stage run in execution order with inputs, outputs and cache state."""
    counts = Counter(states.values())
    targets = sorted({n.target.id for n in graph.nodes.values()})
    console.print(
        f"[bold]Build graph[/]: {len(targets)} targets, {len(graph.nodes)} stage runs "
        f"({counts['cached']} cached, {counts['build']} to build)",
        soft_wrap=True,
    )
    table = _table(
        "#", "target", "stage", "reads", "writes", "state", "key", graph=graph, width=console.width
    )
    for index, node_id in enumerate(graph.order, 1):
        node = graph.nodes[node_id]
        reads = ", ".join(
            f"{name}<-{','.join(_ref_label(ref, name, node.target.id) for ref in refs)}"
            for name, refs in sorted(node.inputs.items())
        )
        state = states[node_id]
        table.add_row(
            str(index),
            node.target.id,
            node.stage,
            reads or "-",
            ", ".join(node.call.spec.outputs),
            "[green]cached[/]" if state == "cached" else "[yellow]build[/]",
            node.key[:10],
        )
    console.print(table)
    for run, outputs in graph.skipped.items():
        target = run.partition(":")[0]
        stands = ", ".join(f"{out} = {_ref_label(ref, '', target)}" for out, ref in outputs.items())
        console.print(f"skipped {run}: {stands}", highlight=False, soft_wrap=True)


def _table(*columns: str, graph: Graph, width: int | None) -> Table:
    """A borderless table whose cells are never cut: on a console too narrow for a cell, its text
    wraps, and a word longer than its column folds onto the next line. The ``target`` and ``stage``
    columns are as wide as the longest of ``graph`` when the console of ``width`` columns (None: not
    known) leaves room for the others (an id stays whole and greppable), and the short columns
    (counts, states, times, keys) stay on one line. Nothing is truncated, so a wide console (output
    that is not a terminal) shows every cell whole on one line."""
    table = Table(show_edge=False, pad_edge=False, box=None)
    widest = {
        "target": max((len(node.target.id) for node in graph.nodes.values()), default=0),
        "stage": max((len(node.stage) for node in graph.nodes.values()), default=0),
    }
    folded = sum(column in _FOLDED for column in columns)
    room = -1 if width is None else width - sum(widest.values()) - 2 * len(columns) - _FOLDED_MIN * folded
    for column in columns:
        table.add_column(
            column,
            overflow="fold",
            min_width=widest.get(column) if room >= 0 else None,
            no_wrap=column not in _FOLDED and (column not in widest or room >= 0),
        )
    return table


_FOLDED = ("reads", "writes", "made")
_FOLDED_MIN = 12
"""Columns left at least to each folding column before the id columns are given their full width."""
"""The columns of the engine's tables that may fold onto several lines on a narrow terminal."""


def _ref_label(ref: ArtifactRef, input_name: str, target: str) -> str:
    """``self``/``<target>``, with ``:<artifact>`` when the artifact is not named like the input."""
    owner = "self" if ref[0] == target else ref[0]
    return owner if ref[1] == input_name else f"{owner}:{ref[1]}"


def _task(node: Node, graph: Graph, store: ArtifactStore, *, replace: bool) -> StageTask:
    spec = node.call.spec
    return StageTask(
        node_id=node.id,
        target=node.target.id,
        stage=spec.name,
        module=spec.module,
        recipe=node.target.recipe,
        recipe_hash=node.target.recipe_hash,
        seed=node.seed,
        node_key=node.key,
        params=node.call.params.model_dump(mode="json"),
        inputs={
            name: [
                str(
                    store.artifact_path(
                        graph.nodes[graph.producers[ref]].stage, ref[1], graph.artifact_key(ref)
                    )
                )
                for ref in refs
            ]
            for name, refs in node.inputs.items()
        },
        many={i.name: i.many for i in spec.inputs},
        input_keys={name: [graph.artifact_key(ref) for ref in refs] for name, refs in node.inputs.items()},
        outputs=tuple(
            TaskOutput(
                name=out, key=key, final=str(store.artifact_path(spec.name, out, key)), replace=replace
            )
            for out, key in node.artifact_keys.items()
        ),
        store_root=str(store.root),
        code_version=spec.code_version(),
    )


def _link_outputs(node: Node, graph: Graph, store: ArtifactStore) -> None:
    """Point the target's links at ``node``'s artifacts, and at those that skipped stages pass on."""
    for out, key in node.artifact_keys.items():
        store.link_target(node.target.id, out, store.artifact_path(node.stage, out, key))
    for (target, out), ref in graph.aliases.items():
        if graph.producers.get(ref) == node.id:
            store.link_target(
                target, out, store.artifact_path(node.stage, ref[1], node.artifact_keys[ref[1]])
            )


def run_build(
    graph: Graph,
    store: ArtifactStore,
    executor_factory: Callable[[], Executor],
    *,
    force: Sequence[str] = (),
    verify: VerifyLevel = "size",
    console: Console | None = None,
) -> BuildReport:
    """Build every node of ``graph`` whose artifacts are not committed yet, or are corrupt.

    Nodes run as soon as their inputs exist; a failing node skips only the nodes that need its
    outputs, the rest goes on. Nothing is started when everything is cached. The caller holds the
    workspace lock (:mod:`pipeline.lock`) if other builds may run.

    Parameters
    ----------
    graph : Graph
        What to build.
    store : ArtifactStore
        Where artifacts are.
    executor_factory : callable
        Makes the executor, only if there is work.
    force : sequence of str
        Target ids whose stages run even if cached; their artifacts are replaced.
    verify : {"size", "hash"}
        How the artifacts to reuse are checked (see :func:`find_corrupt`).
    console : rich.console.Console, optional
        Where progress and the summary go.

    Returns
    -------
    BuildReport

    Raises
    ------
    BuildInterrupted
        On Ctrl-C (or SIGTERM under :func:`sigterm_interrupts`), after the workers were ended.
    """
    console = console or Console()
    started = time.perf_counter()
    report = BuildReport()
    store.clean_stale_tmp()
    for node in graph.nodes.values():
        for out, key in node.artifact_keys.items():
            store.discard_untrusted(node.stage, out, key)
    forced = {n for n, node in graph.nodes.items() if node.target.id in set(force)}
    corrupt = find_corrupt(graph, store, level=verify, skip=forced)
    print_corrupt(corrupt, store, console, action="rebuilding")
    states = plan(graph, store, force=force, corrupt=corrupt)
    for node_id, state in states.items():
        if state == "cached":
            report.cached.append(node_id)
            _link_outputs(graph.nodes[node_id], graph, store)
    todo = [n for n in graph.order if states[n] == "build"]
    if not todo:
        report.seconds = time.perf_counter() - started
        console.print(
            f"Nothing to do: {len(graph.nodes)} stage runs are up to date ({report.seconds:.2f} s)."
        )
        return report
    _Schedule(graph, store, report, todo, replace=forced | set(corrupt)).run(executor_factory(), console)
    report.seconds = time.perf_counter() - started
    _summary(report, graph, store, console)
    return report


class _Schedule:
    """Runs the ``todo`` nodes of a build on an executor, as their inputs become ready."""

    def __init__(
        self, graph: Graph, store: ArtifactStore, report: BuildReport, todo: list[str], *, replace: set[str]
    ) -> None:
        self.graph, self.store, self.report = graph, store, report
        self.replace = replace
        self.deps = {n: graph.dependencies(n) for n in todo}
        self.done = set(report.cached)
        self.waiting = list(todo)
        self.running: dict[cf.Future[TaskResult], str] = {}

    def run(self, executor: Executor, console: Console) -> None:
        """Run every waiting node; on an interrupt, end the workers and raise :class:`BuildInterrupted`."""
        progress = Progress(
            TextColumn("{task.description:<28}"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            console=console,
            transient=False,
        )
        stage_totals = Counter(self.graph.nodes[n].stage for n in self.waiting)
        bars = {s: progress.add_task(s, total=c) for s, c in sorted(stage_totals.items())}
        try:
            with progress:
                self._loop(executor, progress, bars)
        except KeyboardInterrupt as exc:
            with _signals_held():
                executor.abort()
                self.store.clean_stale_tmp()  # the ended workers' unfinished outputs
            unfinished = len(self.waiting) + len(self.running)
            raise BuildInterrupted(unfinished, getattr(exc, "signum", signal.SIGINT)) from None
        finally:
            with _signals_held():
                executor.close()

    def _loop(self, executor: Executor, progress: Progress, bars: dict[str, int]) -> None:
        inner: dict[str, int] = {}
        while self.waiting or self.running:
            for node_id in list(self.waiting):
                blocked = [d for d in self.deps[node_id] if d in self._lost]
                if blocked:
                    self.waiting.remove(node_id)
                    self.report.skipped[node_id] = f"input from {blocked[0]} is missing"
                    progress.advance(bars[self.graph.nodes[node_id].stage])
                elif all(d in self.done for d in self.deps[node_id]) and len(self.running) < executor.jobs:
                    node = self.graph.nodes[node_id]
                    task = _task(node, self.graph, self.store, replace=node_id in self.replace)
                    self.running[executor.submit(task)] = node_id
                    self.waiting.remove(node_id)
                    inner[node_id] = progress.add_task(f"  {node_id}"[:28], total=None)
            if not self.running:
                continue
            finished, _ = cf.wait(self.running, timeout=0.2, return_when=cf.FIRST_COMPLETED)
            _drain_progress(executor, progress, inner)
            for future in finished:
                node_id = self.running.pop(future)
                progress.remove_task(inner.pop(node_id))
                progress.advance(bars[self.graph.nodes[node_id].stage])
                self._record(node_id, _result_of(future, node_id), progress)

    @property
    def _lost(self) -> set[str]:
        """Nodes that will not produce their outputs (failed, or skipped)."""
        return {*self.report.failed, *self.report.skipped}

    def _record(self, node_id: str, result: TaskResult, progress: Progress) -> None:
        if result.ok:
            self.report.built[node_id] = result
            self.done.add(node_id)
            _link_outputs(self.graph.nodes[node_id], self.graph, self.store)
            progress.console.print(
                f"[green]built[/] {node_id}  {result.wall_s:.1f} s, {result.peak_rss_mb:.0f} MB"
            )
        else:
            self.report.failed[node_id] = result
            progress.console.print(f"[red]failed[/] {node_id} (the error is in the summary)")


def _result_of(future: cf.Future[TaskResult], node_id: str) -> TaskResult:
    """The future's result; a worker that died or an executor fault is this node's failure."""
    try:
        return future.result()
    except Exception as exc:
        return TaskResult(node_id, ok=False, error=str(exc) or type(exc).__name__)


def _drain_progress(executor: Executor, progress: Progress, bars: dict[str, int]) -> None:
    while True:
        try:
            node_id, done, total, description = executor.progress.get_nowait()
        except Exception:  # queue.Empty, or a closed channel
            return
        if node_id in bars:
            label = f"  {node_id} {description}".rstrip()[:28]
            progress.update(bars[node_id], completed=done, total=total or None, description=label)


def _summary(report: BuildReport, graph: Graph, store: ArtifactStore, console: Console) -> None:
    console.print(
        f"[bold]Build finished[/] in {report.seconds:.1f} s: {len(report.built)} built, "
        f"{len(report.cached)} cached, {len(report.failed)} failed, {len(report.skipped)} skipped.",
        soft_wrap=True,
    )
    console.print(runs_table(graph, store, report, width=console.width))
    for node_id, result in sorted(report.built.items()):
        for message in result.warnings:
            console.print(f"  [yellow]warning[/] {node_id}: {message}", highlight=False, soft_wrap=True)
    for node_id, result in sorted(report.failed.items()):
        where = f"\n         log: {result.log_path}" if result.log_path else ""
        console.print(f"  [red]FAILED[/] {node_id}: {result.error}{where}", highlight=False, soft_wrap=True)
    for node_id, reason in sorted(report.skipped.items()):
        console.print(f"  [yellow]skipped[/] {node_id}: {reason}", highlight=False, soft_wrap=True)


def runs_table(graph: Graph, store: ArtifactStore, report: BuildReport, *, width: int | None = None) -> Table:
    """The build summary's table: per target, each stage run with its time (or ``cached``, ``failed``,
    ``skipped``) and what it made (:func:`run_made`).

    Parameters
    ----------
    graph : Graph
        The graph built.
    store : ArtifactStore
        Where the reused artifacts' manifests are read.
    report : BuildReport
        What the build did.
    width : int, optional
        Columns of the console it is printed on (None: not known; ids fold like other cells).

    Returns
    -------
    rich.table.Table
        Columns ``target``, ``stage``, ``time``, ``made``; rows by target, then in execution order.
    """
    table = _table("target", "stage", "time", "made", graph=graph, width=width)
    position = {node_id: index for index, node_id in enumerate(graph.order)}
    cached = set(report.cached)
    for node_id in sorted(graph.order, key=lambda n: (graph.nodes[n].target.id, position[n])):
        node, made = graph.nodes[node_id], ""
        if node_id in report.built:
            time_text = f"{report.built[node_id].wall_s:.1f} s"
            made = run_made(node, store, report.built[node_id])
        elif node_id in cached:
            time_text = "[green]cached[/]"
            made = run_made(node, store)
        elif node_id in report.failed:
            time_text = "[red]failed[/]"
        else:
            time_text = "[yellow]skipped[/]" if node_id in report.skipped else "-"
        table.add_row(node.target.id, node.stage, time_text, Text(made))
    return table


def run_made(node: Node, store: ArtifactStore, result: TaskResult | None = None) -> str:
    """What a stage run made, in one line (:func:`pipeline.summary.describe_stats`): the figures its
    stage declares (``@stage(..., summary=...)``), from the stats of ``result`` when it ran in this
    build, otherwise from the manifest of its committed artifact; empty when it has none."""
    fields = node.call.spec.summary
    if not fields:
        return ""
    if result is not None:
        return describe_stats(result.stats, fields)
    for out, key in node.artifact_keys.items():
        manifest = store.read_manifest(store.artifact_path(node.stage, out, key))
        if manifest is not None and isinstance(manifest.get("stats"), dict):
            return describe_stats(manifest["stats"], fields)
    return ""
