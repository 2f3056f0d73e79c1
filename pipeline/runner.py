"""Plans and runs builds: cache look-ups, scheduling on an executor, progress, and the summary."""

from __future__ import annotations

import concurrent.futures as cf
import time
from collections import Counter
from collections.abc import Callable, Sequence
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from typing import Literal

from rich.console import Console
from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn
from rich.table import Table

from pipeline.dag import ArtifactRef, Graph, Node
from pipeline.executors import Executor
from pipeline.store import ArtifactStore
from pipeline.worker import StageTask, TaskOutput, TaskResult

NodeState = Literal["cached", "build"]
TargetStatus = Literal["fresh", "stale", "missing"]


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


def plan(graph: Graph, store: ArtifactStore, *, force: Sequence[str] = ()) -> dict[str, NodeState]:
    """``{node_id: "cached" | "build"}`` in graph order; ``force`` names targets to rebuild."""
    forced = set(force)
    states: dict[str, NodeState] = {}
    for node_id in graph.order:
        node = graph.nodes[node_id]
        have = all(store.has(node.stage, out, key) for out, key in node.artifact_keys.items())
        states[node_id] = "cached" if have and node.target.id not in forced else "build"
    return states


def target_status(graph: Graph, store: ArtifactStore) -> dict[str, TargetStatus]:
    """Per target: ``fresh`` (every artifact current), ``stale`` (built before, out of date), ``missing``."""
    result: dict[str, TargetStatus] = {}
    by_target: dict[str, list[Node]] = {}
    for node in graph.nodes.values():
        by_target.setdefault(node.target.id, []).append(node)
    for target_id, nodes in sorted(by_target.items()):
        current = all(store.has(n.stage, out, key) for n in nodes for out, key in n.artifact_keys.items())
        built_before = any(
            store.target_output(target_id, out) is not None for n in nodes for out in n.artifact_keys
        )
        result[target_id] = "fresh" if current else ("stale" if built_before else "missing")
    return result


def describe_plan(graph: Graph, states: dict[str, NodeState], console: Console) -> None:
    """Print the graph: every stage run in execution order with inputs, outputs and cache state."""
    counts = Counter(states.values())
    targets = sorted({n.target.id for n in graph.nodes.values()})
    console.print(
        f"[bold]Build graph[/]: {len(targets)} targets, {len(graph.nodes)} stage runs "
        f"({counts['cached']} cached, {counts['build']} to build)"
    )
    table = Table(show_edge=False, pad_edge=False, box=None)
    for column in ("#", "target", "stage", "reads", "writes", "state", "key"):
        # Target ids and stage names are shown whole: they are what the user types next.
        whole = column in ("target", "stage")
        width = max((len(t) for t in targets), default=6) if column == "target" else None
        table.add_column(column, no_wrap=whole, min_width=width, overflow="fold" if not whole else "ellipsis")
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
        console.print(f"skipped {run}: {stands}")


def _ref_label(ref: ArtifactRef, input_name: str, target: str) -> str:
    """``self``/``<target>``, with ``:<artifact>`` when the artifact is not named like the input."""
    owner = "self" if ref[0] == target else ref[0]
    return owner if ref[1] == input_name else f"{owner}:{ref[1]}"


def _task(node: Node, graph: Graph, store: ArtifactStore) -> StageTask:
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
            TaskOutput(name=out, key=key, final=str(store.artifact_path(spec.name, out, key)))
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
    console: Console | None = None,
) -> BuildReport:
    """Build every node of ``graph`` whose artifacts are not committed yet.

    Nodes run as soon as their inputs exist; a failing node skips only the nodes that need its
    outputs, the rest goes on. Nothing is started when everything is cached.

    Parameters
    ----------
    graph : Graph
        What to build.
    store : ArtifactStore
        Where artifacts are.
    executor_factory : callable
        Makes the executor, only if there is work.
    force : sequence of str
        Target ids whose stages run even if cached.
    console : rich.console.Console, optional
        Where progress and the summary go.

    Returns
    -------
    BuildReport
    """
    console = console or Console()
    started = time.perf_counter()
    report = BuildReport()
    store.clean_stale_tmp()
    for node in graph.nodes.values():
        for out, key in node.artifact_keys.items():
            store.discard_untrusted(node.stage, out, key)
    states = plan(graph, store, force=force)
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

    executor = executor_factory()
    deps = {n: graph.dependencies(n) for n in todo}
    done = set(report.cached)
    waiting = list(todo)
    running: dict[cf.Future[TaskResult], str] = {}
    stage_totals = Counter(graph.nodes[n].stage for n in todo)
    progress = Progress(
        TextColumn("{task.description:<28}"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=console,
        transient=False,
    )
    stage_bars = {s: progress.add_task(s, total=c) for s, c in sorted(stage_totals.items())}
    inner_bars: dict[str, int] = {}
    try:
        with progress:
            while waiting or running:
                for node_id in list(waiting):
                    blocked = [d for d in deps[node_id] if d in report.failed or d in report.skipped]
                    if blocked:
                        waiting.remove(node_id)
                        report.skipped[node_id] = f"input from {blocked[0]} is missing"
                        progress.advance(stage_bars[graph.nodes[node_id].stage])
                    elif all(d in done for d in deps[node_id]) and len(running) < executor.jobs:
                        waiting.remove(node_id)
                        running[executor.submit(_task(graph.nodes[node_id], graph, store))] = node_id
                        inner_bars[node_id] = progress.add_task(f"  {node_id}"[:28], total=None)
                if not running:
                    continue
                finished, _ = cf.wait(running, timeout=0.2, return_when=cf.FIRST_COMPLETED)
                _drain_progress(executor, progress, inner_bars)
                for future in finished:
                    node_id = running.pop(future)
                    node = graph.nodes[node_id]
                    try:
                        result = future.result()
                    except BrokenProcessPool:
                        result = TaskResult(
                            node_id, ok=False, error="the worker process died (killed, or out of memory)"
                        )
                        executor.restart()
                    except Exception as exc:  # an executor fault is this node's failure, not the build's
                        result = TaskResult(node_id, ok=False, error=f"{type(exc).__name__}: {exc}")
                    progress.remove_task(inner_bars.pop(node_id))
                    progress.advance(stage_bars[node.stage])
                    if result.ok:
                        report.built[node_id] = result
                        done.add(node_id)
                        _link_outputs(node, graph, store)
                        progress.console.print(
                            f"[green]built[/] {node_id}  {result.wall_s:.1f} s, {result.peak_rss_mb:.0f} MB"
                        )
                    else:
                        report.failed[node_id] = result
                        progress.console.print(f"[red]failed[/] {node_id}: {result.error}")
    finally:
        executor.close()
    report.seconds = time.perf_counter() - started
    _summary(report, console)
    return report


def _drain_progress(executor: Executor, progress: Progress, bars: dict[str, int]) -> None:
    while True:
        try:
            node_id, done, total, description = executor.progress.get_nowait()
        except Exception:  # queue.Empty, or a closed channel
            return
        if node_id in bars:
            label = f"  {node_id} {description}".rstrip()[:28]
            progress.update(bars[node_id], completed=done, total=total or None, description=label)


def _summary(report: BuildReport, console: Console) -> None:
    console.print(
        f"[bold]Build finished[/] in {report.seconds:.1f} s: {len(report.built)} built, "
        f"{len(report.cached)} cached, {len(report.failed)} failed, {len(report.skipped)} skipped."
    )
    for node_id, result in sorted(report.failed.items()):
        console.print(f"  [red]FAILED[/] {node_id}: {result.error}\n         log: {result.log_path}")
    for node_id, reason in sorted(report.skipped.items()):
        console.print(f"  [yellow]skipped[/] {node_id}: {reason}")
