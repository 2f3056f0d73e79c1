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
    """Nodes in a valid execution order, with the producers of every artifact."""

    nodes: dict[str, Node]
    order: list[str]
    producers: dict[ArtifactRef, str]

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

    Raises
    ------
    DagError
        On an input nobody produces, an artifact produced twice in a target, a link that matches
        nothing, or a cycle; the message names the stages involved.
    """
    pool = {t.id: t for t in (universe if universe is not None else targets)}
    for target in targets:
        pool.setdefault(target.id, target)
    wanted: dict[str, Target] = {}
    pending = [t.id for t in targets]
    nodes: dict[str, Node] = {}
    producers: dict[ArtifactRef, str] = {}
    problems: list[str] = []

    while pending:
        target = pool[pending.pop()]
        if target.id in wanted:
            continue
        wanted[target.id] = target
        made: dict[str, str] = {}
        for call in target.stages:
            for output in call.spec.outputs:
                if output in made:
                    problems.append(
                        f"target {target.id!r}: artifact {output!r} is produced by both stage "
                        f"{made[output]!r} and stage {call.spec.name!r}; remove one of them from the recipe"
                    )
                made[output] = call.spec.name
        for artifact in target.links:
            if artifact in made:
                problems.append(
                    f"target {target.id!r}: artifact {artifact!r} is both produced by stage "
                    f"{made[artifact]!r} and linked from other targets; keep one"
                )
        for call in target.stages:
            node = Node(target=target, call=call)
            for declared in call.spec.inputs:
                if declared.name in made:
                    if declared.many:
                        problems.append(
                            f"target {target.id!r}: stage {call.spec.name!r} reads many {declared.name!r} "
                            "artifacts; provide them with 'links', not a stage of the same target"
                        )
                    node.inputs[declared.name] = [(target.id, declared.name)]
                elif declared.name in target.links:
                    linked = sorted(
                        tid
                        for tid in pool
                        if tid != target.id
                        and any(fnmatch.fnmatchcase(tid, pat) for pat in target.links[declared.name])
                    )
                    if not linked:
                        problems.append(
                            f"target {target.id!r}: links for {declared.name!r} "
                            f"({', '.join(target.links[declared.name])}) match no target"
                        )
                        continue
                    if not declared.many and len(linked) != 1:
                        problems.append(
                            f"target {target.id!r}: stage {call.spec.name!r} reads one {declared.name!r} "
                            f"but links match {len(linked)} targets ({', '.join(linked)})"
                        )
                        continue
                    node.inputs[declared.name] = [(tid, declared.name) for tid in linked]
                    pending.extend(linked)
                else:
                    stages = ", ".join(c.spec.name for c in target.stages)
                    problems.append(
                        f"target {target.id!r}: stage {call.spec.name!r} needs artifact {declared.name!r}, "
                        f"which no stage of the target produces (stages: {stages}) and no link provides; "
                        f"add a stage that outputs {declared.name!r} or a 'links' entry"
                    )
            nodes[node.id] = node
            for output in call.spec.outputs:
                producers[(target.id, output)] = node.id

    for node in nodes.values():
        for refs in node.inputs.values():
            for ref in refs:
                if ref not in producers:
                    problems.append(
                        f"target {node.target.id!r}: stage {node.stage!r} links {ref[1]!r} from target "
                        f"{ref[0]!r}, which does not produce it"
                    )
    if problems:
        raise DagError("invalid build graph:\n  " + "\n  ".join(dict.fromkeys(problems)))

    graph = Graph(nodes=nodes, order=[], producers=producers)
    graph.order = _topological_order(graph)
    graph.compute_keys()
    return graph


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
