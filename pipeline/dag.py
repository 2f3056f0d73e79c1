"""The build graph: one node per (target, stage), edges from declared inputs and outputs."""

from __future__ import annotations

import fnmatch
from collections.abc import Sequence
from dataclasses import dataclass, field

from pipeline.errors import DagError
from pipeline.hashing import hash_file, short_key
from pipeline.params import source_files
from pipeline.recipes import StageCall, Target
from pipeline.seeds import derive_seed
from pipeline.stage import Input

ArtifactRef = tuple[str, str]
"""``(target_id, artifact_name)``."""


@dataclass
class Node:
    """One stage run of one target.

    Attributes
    ----------
    target : Target
        The target.
    call : StageCall
        The stage and its params.
    inputs : dict
        ``{input_name: [ArtifactRef, ...]}`` resolved producers.
    key : str
        Cache key (set by :meth:`Graph.compute_keys`).
    artifact_keys : dict
        ``{output_name: artifact_key}``.
    """

    target: Target
    call: StageCall
    inputs: dict[str, list[ArtifactRef]] = field(default_factory=dict)
    key: str = ""
    artifact_keys: dict[str, str] = field(default_factory=dict)
    seed: int = 0

    @property
    def id(self) -> str:
        """``target_id:stage_name``."""
        return f"{self.target.id}:{self.call.spec.name}"

    @property
    def stage(self) -> str:
        """The stage name."""
        return self.call.spec.name


@dataclass
class Graph:
    """Nodes in a valid execution order, with the producers of every artifact and the artifacts that
    skipped stages pass through."""

    nodes: dict[str, Node]
    order: list[str]
    producers: dict[ArtifactRef, str]
    skipped: dict[str, dict[str, ArtifactRef]] = field(default_factory=dict)
    """Skipped stage runs: ``{"target:stage": {output: the artifact it stands for}}``."""

    @property
    def aliases(self) -> dict[ArtifactRef, ArtifactRef]:
        """``{(target, output): artifact}`` for the outputs of skipped stages."""
        return {
            (node_id.partition(":")[0], output): ref
            for node_id, outputs in self.skipped.items()
            for output, ref in outputs.items()
        }

    def dependencies(self, node_id: str) -> list[str]:
        """Node ids whose outputs ``node_id`` reads, in order, without repeats."""
        seen: dict[str, None] = {}
        for refs in self.nodes[node_id].inputs.values():
            for ref in refs:
                seen[self.producers[ref]] = None
        return list(seen)

    def artifact_key(self, ref: ArtifactRef) -> str:
        """Key of the artifact ``ref`` (after :meth:`compute_keys`)."""
        return self.nodes[self.producers[ref]].artifact_keys[ref[1]]

    def compute_keys(self) -> None:
        """Set every node's cache key and its artifacts' keys, upstream first.

        The key hashes the stage name and code version, the target id and derived seed, the params
        (files named in them by content) and the keys of the input artifacts.
        """
        code_versions: dict[str, str] = {}
        file_hashes: dict[str, str] = {}
        for node_id in self.order:
            node = self.nodes[node_id]
            spec = node.call.spec
            if spec.name not in code_versions:
                code_versions[spec.name] = spec.code_version()
            params = node.call.params.model_dump(mode="json")
            for dotted, path in sorted(source_files(node.call.params).items()):
                digest = file_hashes.setdefault(str(path), hash_file(path))
                _set_dotted(params, dotted, f"sha256:{digest}")
            node.seed = derive_seed(node.target.seed, node.target.id, spec.name)
            node.key = short_key(
                {
                    "stage": spec.name,
                    "code": code_versions[spec.name],
                    "target": node.target.id,
                    "seed": node.seed,
                    "params": params,
                    "inputs": {
                        name: [self.artifact_key(ref) for ref in refs]
                        for name, refs in sorted(node.inputs.items())
                    },
                }
            )
            node.artifact_keys = {out: short_key([node.key, out]) for out in spec.outputs}


def _set_dotted(data: dict, dotted: str, value: str) -> None:
    parts = dotted.split(".")
    node = data
    for part in parts[:-1]:
        node = node[int(part)] if isinstance(node, list) else node[part]
    last = parts[-1]
    if isinstance(node, list):
        node[int(last)] = value
    else:
        node[last] = value


def build_graph(targets: Sequence[Target], *, universe: Sequence[Target] | None = None) -> Graph:
    """Derive the graph of ``targets`` (plus the targets they link to, taken from ``universe``).

    An input binds, in this order, to the target's ``links`` entry of the input's name (the linked
    targets' artifact: the link's ``artifact``, else the one the stage declares), or to the artifact
    the stage declares made by another stage of the same target. A skipped stage runs nothing: its
    outputs are bound to what its passthrough inputs read.

    Raises
    ------
    DagError
        On an input nobody produces, an artifact produced twice in a target, a link that matches
        nothing or names no input, or a cycle; the message names the stages, inputs and artifacts.
    """
    pool = {t.id: t for t in (universe if universe is not None else targets)}
    for target in targets:
        pool.setdefault(target.id, target)
    wanted: dict[str, Target] = {}
    pending = [t.id for t in targets]
    nodes: dict[str, Node] = {}
    producers: dict[ArtifactRef, str] = {}
    aliases: dict[ArtifactRef, ArtifactRef] = {}
    skipped: dict[str, list[str]] = {}
    problems: list[str] = []

    while pending:
        target = pool[pending.pop()]
        if target.id in wanted:
            continue
        wanted[target.id] = target
        binder = _Binder(target, pool, problems)
        for call in target.stages:
            bound: dict[str, list[ArtifactRef]] = {}
            for declared in call.spec.inputs:
                refs = binder.bind(call, declared)
                if refs is not None:
                    bound[declared.name] = refs
                    pending.extend(tid for tid, _ in refs if tid != target.id)
            if call.skip:
                skipped[f"{target.id}:{call.spec.name}"] = list(call.spec.outputs)
                for output, input_name in call.spec.passthrough.items():
                    if input_name in bound:
                        aliases[(target.id, output)] = bound[input_name][0]
                continue
            node = Node(target=target, call=call, inputs=bound)
            nodes[node.id] = node
            for output in call.spec.outputs:
                producers[(target.id, output)] = node.id

    for node in nodes.values():
        for name, refs in node.inputs.items():
            resolved = []
            for ref in refs:
                real = _resolve_alias(ref, aliases)
                if real not in producers:
                    problems.append(
                        f"target {node.target.id!r}: stage {node.stage!r} reads "
                        f"{node.call.spec.input(name).describe()} from target {ref[0]!r}, which does not "
                        f"produce {ref[1]!r}"
                    )
                resolved.append(real)
            node.inputs[name] = resolved
    if problems:
        raise DagError("invalid build graph:\n  " + "\n  ".join(dict.fromkeys(problems)))

    graph = Graph(
        nodes=nodes,
        order=[],
        producers=producers,
        skipped={
            run: {out: _resolve_alias((run.partition(":")[0], out), aliases) for out in outputs}
            for run, outputs in sorted(skipped.items())
        },
    )
    graph.order = _topological_order(graph)
    graph.compute_keys()
    return graph


def _resolve_alias(ref: ArtifactRef, aliases: dict[ArtifactRef, ArtifactRef]) -> ArtifactRef:
    """Follow skipped stages' passthroughs to the artifact a running stage makes."""
    seen = {ref}
    while ref in aliases:
        ref = aliases[ref]
        if ref in seen:
            raise DagError(f"skipped stages pass {ref[1]!r} of target {ref[0]!r} around in a circle")
        seen.add(ref)
    return ref


class _Binder:
    """Binds the declared inputs of one target's stages to artifact references, noting problems."""

    def __init__(self, target: Target, pool: dict[str, Target], problems: list[str]) -> None:
        self.target = target
        self.pool = pool
        self.problems = problems
        self.made: dict[str, str] = {}
        for call in target.stages:
            for output in call.spec.outputs:
                if output in self.made:
                    self._problem(
                        f"artifact {output!r} is produced by both stage {self.made[output]!r} and stage "
                        f"{call.spec.name!r}; remove one of them from the recipe"
                    )
                self.made[output] = call.spec.name
        read = {i.name for call in target.stages for i in call.spec.inputs}
        for name in target.links:
            if name in self.made and name in read:
                self._problem(
                    f"{name!r} is both produced by stage {self.made[name]!r} and linked from other "
                    f"targets; keep one, or link the other target's artifact under another input name"
                )
            elif name not in read:
                inputs = ", ".join(sorted(read)) or "none"
                self._problem(
                    f"links name {name!r}, which no stage of the target reads (inputs: {inputs}); "
                    "a link's key is the name of the input it feeds"
                )

    def _problem(self, text: str) -> None:
        self.problems.append(f"target {self.target.id!r}: {text}")

    def bind(self, call: StageCall, declared: Input) -> list[ArtifactRef] | None:
        """The references ``declared`` reads, or ``None`` (with a problem noted) if it cannot bind."""
        stage = call.spec.name
        link = self.target.links.get(declared.name)
        if link is not None:
            artifact = link.artifact or declared.source
            linked = sorted(
                tid
                for tid in self.pool
                if tid != self.target.id and any(fnmatch.fnmatchcase(tid, p) for p in link.targets)
            )
            if not linked:
                self._problem(f"links for {link.describe(declared.name)} match no target")
                return None
            if not declared.many and len(linked) != 1:
                self._problem(
                    f"stage {stage!r} reads one {declared.describe()} but links match "
                    f"{len(linked)} targets ({', '.join(linked)})"
                )
                return None
            return [(tid, artifact) for tid in linked]
        if declared.source in self.made:
            if self.made[declared.source] == stage:
                self._problem(
                    f"stage {stage!r} reads {declared.describe()}, which it writes itself; link the "
                    f"input from another target (links: {{{declared.name}: {{artifact: {declared.source}, "
                    "targets: [...]}})"
                )
                return None
            if declared.many:
                self._problem(
                    f"stage {stage!r} reads many {declared.describe()} artifacts; provide them with "
                    "'links', not a stage of the same target"
                )
            return [(self.target.id, declared.source)]
        stages = ", ".join(c.spec.name for c in self.target.stages)
        self._problem(
            f"stage {stage!r} needs {declared.describe()}, which no stage of the target produces "
            f"(stages: {stages}) and no link provides; add a stage that outputs {declared.source!r} or a "
            f"'links' entry for {declared.name!r}"
        )
        return None


def _topological_order(graph: Graph) -> list[str]:
    deps = {nid: graph.dependencies(nid) for nid in sorted(graph.nodes)}
    remaining = {nid: len(d) for nid, d in deps.items()}
    users: dict[str, list[str]] = {nid: [] for nid in deps}
    for nid, ds in deps.items():
        for d in ds:
            users[d].append(nid)
    ready = sorted(nid for nid, count in remaining.items() if count == 0)
    order: list[str] = []
    while ready:
        nid = ready.pop(0)
        order.append(nid)
        for user in sorted(users[nid]):
            remaining[user] -= 1
            if remaining[user] == 0:
                ready.append(user)
        ready.sort()
    if len(order) != len(deps):
        stuck = sorted(nid for nid, count in remaining.items() if count > 0)
        raise DagError(
            "the stages form a cycle (each waits for another's output): "
            + ", ".join(stuck)
            + "; change the stages' inputs or the recipes' links so that one of them "
            "does not depend on the others"
        )
    return order
